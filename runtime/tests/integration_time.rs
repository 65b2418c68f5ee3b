//! Chapter 5 on the simulated camera: the preprocessing finds the sensor's optimum and undoes
//! its non-linearity; from over- and underexposure the per-pixel method settles within a few
//! frames and faster than May et al.'s controller; a sweep that never bends is an error.

use gudsl_runtime::exposure::{
    calibrate, closed_loop, frames_to_converge, intensity_rate, CalibrationError, Controller, ProportionalController,
    Sample,
};
use gudsl_runtime::kernels::integration::IntegrationModel;
use gudsl_runtime::kernels::tof::{demodulate, subtract_black};
use gudsl_runtime::sim::{simulate, Camera, Motion, Scene};
use gudsl_runtime::Image;

const RANGE: (f32, f32) = (50.0, 8000.0);

fn acquire(t: f32, seed: u64) -> (Sample, Image) {
    let camera = Camera { integration_us: t, supersampling: 1, seed, ..Camera::default() };
    let frame = simulate(&Scene::plates(), Motion::Still, &camera, 0);
    let [_, amplitude, intensity, distance] = demodulate(&subtract_black(&frame.raw, &frame.black), 20.0e6);
    (Sample { integration_us: t, amplitude, intensity, distance }, frame.truth)
}

fn sweep(times: impl Iterator<Item = f32>) -> (Vec<Sample>, Image) {
    let frames: Vec<_> = times.enumerate().map(|(k, t)| acquire(t, k as u64 + 1)).collect();
    let truth = frames[0].1.clone();
    (frames.into_iter().map(|f| f.0).collect(), truth)
}

#[test]
fn calibration_finds_the_optimum_and_per_pixel_control_beats_the_proportional_one() {
    let (samples, truth) = sweep((1..=40).map(|k| 200.0 * k as f32));
    let model = calibrate(&samples, &truth, RANGE).expect("calibration");
    eprintln!("{model:?}");
    assert_eq!(model, IntegrationModel::SIMULATED, "the simulated sensor's model the pipelines use");
    // h undoes the bend: a bright plate's measured intensity maps back onto its linear growth.
    let (short, long) = (acquire(300.0, 90).0, acquire(2400.0, 91).0);
    let white = 150 * 200 + 150; // the white plate (bottom right)
    let linear = short.intensity.data[white] * 8.0;
    let measured = long.intensity.data[white];
    let corrected = model.correct(measured);
    eprintln!("white plate at 2400 µs: linear {linear}, measured {measured}, corrected {corrected}");
    assert!(
        (corrected - linear).abs() < (measured - linear).abs() && (corrected - linear).abs() < 0.05 * linear,
        "h({measured}) = {corrected}, linear {linear}"
    );
    let rate = intensity_rate(&samples, &model);
    assert!(
        (0.5 / rate - 0.025).abs() < 0.001,
        "the gain the ToF library's IntegrationTimeControl defaults to: {}",
        0.5 / rate
    );
    let controllers = [
        Controller::PerPixel(model),
        Controller::Proportional(ProportionalController::tuned(model.i_opt, rate, RANGE)),
    ];
    let converged: Vec<usize> = controllers
        .iter()
        .map(|c| {
            let run = closed_loop(c, model.a_opt, 8000.0, 15, |k, t| acquire(t, 100 + k as u64));
            eprintln!("{:?}", run.iter().map(|f| f.integration_us).collect::<Vec<_>>());
            frames_to_converge(&run)
        })
        .collect();
    assert!(converged[0] <= 4 && converged[0] < converged[1], "frames to converge from 8000 µs: {converged:?}");
}

#[test]
fn a_sweep_that_stays_linear_cannot_calibrate_h() {
    let (samples, truth) = sweep([50.0, 100.0, 150.0, 200.0].into_iter());
    let error = calibrate(&samples, &truth, RANGE).unwrap_err();
    assert!(matches!(error, CalibrationError::NoNonLinearity | CalibrationError::NoErrorMinimum), "{error}");
    let _ = IntegrationModel::CAMCUBE;
}
