//! `gudsl calibrate-phases OUT.npy`: the phase-normalization calibration of chapter 4
//! (sec. 4.2.2.1) fitted on the simulated camera's static walls (4 distances × 3 reflectivities,
//! each the mean of 4 frames), written as a float32 `.npy` of shape (8, H, W) that
//! `MotionCompensation (phaseCalibration = "…")` reads. Exit code: 0 written, 2 not written.

use std::{path::PathBuf, process::ExitCode};

use clap::Args;
use gudsl_runtime::{
    phase_normalization::PhaseCalibration,
    sim::{Camera, Intrinsics},
};

#[derive(Args)]
pub struct CalibratePhasesArgs {
    /// The `.npy` file to write (its folder must exist).
    output: PathBuf,
    /// The pixels' gain spread (relative σ) of the simulated camera; 0 is `SimulatedCamera`'s.
    #[arg(long, default_value_t = 0.0)]
    gain_spread: f32,
}

pub fn run(args: &CalibratePhasesArgs) -> ExitCode {
    if !(0.0..1.0).contains(&args.gain_spread) {
        eprintln!("gudsl calibrate-phases: --gain-spread is a relative σ in [0, 1), not {}", args.gain_spread);
        return ExitCode::from(2);
    }
    let camera = Camera { gain_spread: args.gain_spread, ..Camera::default() };
    let calibration = PhaseCalibration::simulated(&camera);
    if let Err(e) = calibration.save(&args.output) {
        eprintln!("gudsl calibrate-phases: {e}");
        return ExitCode::from(2);
    }
    let Intrinsics { width, height, .. } = camera.intrinsics;
    println!("wrote {} (8 × {height} × {width}: a, b, c, d of taps A and B)", args.output.display());
    ExitCode::SUCCESS
}
