//! `gudsl calibrate-phases OUT.npy`: the phase-normalization calibration of chapter 4
//! (sec. 4.2.2.1) fitted on static walls — recorded ones (`--from DIR`: each wall's channel
//! files, `gudsl_host::pipeline::calibration_walls`) or the simulated camera's (4 distances × 3
//! reflectivities, each the mean of 4 frames) — written as a float32 `.npy` of shape (8, H, W)
//! (a, b, c, d of tap A, then of tap B; `docs/pipelines.md`) that
//! `MotionCompensation (phaseCalibration = "…")` reads. Exit code: 0 written, 2 not written.

use std::{
    path::{Path, PathBuf},
    process::ExitCode,
};

use clap::Args;
use gudsl_runtime::{phase_normalization::PhaseCalibration, sim::Camera};

#[derive(Args)]
pub struct CalibratePhasesArgs {
    /// The `.npy` file to write (its folder must exist).
    output: PathBuf,
    /// The pixels' gain spread (relative σ) of the simulated camera; 0 is `SimulatedCamera`'s.
    #[arg(long, default_value_t = 0.0, conflicts_with = "from")]
    gain_spread: f32,
    /// Fit on recorded walls instead: a folder of static recordings of homogeneous walls at
    /// several distances and reflectivities (at least 4), each as `<wall>_a.npy` and
    /// `<wall>_b.npy` (raw frames, (4, H, W) or (N, 4, H, W), averaged), with the black image
    /// as `black_a.npy` and `black_b.npy` if it is to be subtracted.
    #[arg(long, value_name = "DIR")]
    from: Option<PathBuf>,
}

pub fn run(args: &CalibratePhasesArgs) -> ExitCode {
    if !(0.0..1.0).contains(&args.gain_spread) {
        eprintln!("gudsl calibrate-phases: --gain-spread is a relative σ in [0, 1), not {}", args.gain_spread);
        return ExitCode::from(2);
    }
    let calibration = match &args.from {
        Some(dir) => match recorded(dir) {
            Ok(calibration) => calibration,
            Err(message) => {
                eprintln!("gudsl calibrate-phases: {message}");
                return ExitCode::from(2);
            }
        },
        None => PhaseCalibration::simulated(&Camera { gain_spread: args.gain_spread, ..Camera::default() }),
    };
    if let Err(e) = calibration.save(&args.output) {
        eprintln!("gudsl calibrate-phases: {e}");
        return ExitCode::from(2);
    }
    let (width, height) = (calibration.coefficients.width, calibration.coefficients.height);
    println!("wrote {} (8 × {height} × {width}: a, b, c, d of taps A and B)", args.output.display());
    ExitCode::SUCCESS
}

/// The calibration fitted on the walls recorded in `dir` (read beneath `dir` only).
fn recorded(dir: &Path) -> Result<PhaseCalibration, String> {
    let files = super::access(Some(dir)).files(dir);
    let walls = gudsl_host::pipeline::calibration_walls(&files, dir)?;
    let names: Vec<&str> = walls.iter().map(|(name, _)| name.as_str()).collect();
    eprintln!("fitting on {} wall(s): {}", walls.len(), names.join(", "));
    let images: Vec<_> = walls.into_iter().map(|(_, image)| image).collect();
    PhaseCalibration::fit(&images).map_err(|e| format!("{}: {e}", dir.display()))
}
