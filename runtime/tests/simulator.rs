//! The simulated camera against its ground truth: demodulating a still, noiseless frame gives
//! the true distance away from depth edges, noise and motion add the errors they should, and
//! saturation and frames survive a trip through `.npy`; a camera standing where a motion took it
//! sees what the moving one saw in that phase image.

use gudsl_formats::arrays;
use gudsl_runtime::kernels::tof::{demodulate, subtract_black, unambiguous_range};
use gudsl_runtime::sim::{simulate, standing_at, Camera, Motion, Scene};
use gudsl_runtime::Image;

/// |measured − truth| over pixels whose 3×3 neighbourhood is one surface (no depth edge).
fn interior_errors(distance: &Image, truth: &Image) -> Vec<f32> {
    let (w, h) = (truth.width, truth.height);
    let mut errors = Vec::new();
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let centre = truth.data[y * w + x];
            let flat = (-1..=1).all(|dy: isize| {
                (-1..=1).all(|dx: isize| {
                    let t = truth.data[(y as isize + dy) as usize * w + (x as isize + dx) as usize];
                    (t - centre).abs() < 0.02
                })
            });
            if flat && centre.is_finite() {
                errors.push((distance.data[y * w + x] - centre).abs());
            }
        }
    }
    errors
}

fn mean(values: &[f32]) -> f32 {
    values.iter().sum::<f32>() / values.len() as f32
}

#[test]
fn still_noiseless_frames_demodulate_to_the_truth() {
    let camera = Camera { noise: false, ..Camera::default() };
    for scene in [Scene::sphere(), Scene::cuboid(), Scene::height_field()] {
        let frame = simulate(&scene, Motion::Still, &camera, 0);
        let [_, amplitude, _, distance] = demodulate(&subtract_black(&frame.raw, &frame.black), camera.modulation_hz);
        let errors = interior_errors(&distance, &frame.truth);
        assert!(errors.len() > 30_000, "most pixels are interior: {}", errors.len());
        let worst = errors.iter().copied().fold(0.0, f32::max);
        // Sub-rays span a little depth even on a flat slanted surface: millimetres at most.
        assert!(worst < 0.01, "{scene:?}: worst interior error {worst} m");
        assert!(amplitude.data.iter().all(|&a| a > 0.0));
        // The object is nearer than the wall.
        let nearest = frame.truth.data.iter().copied().fold(f32::INFINITY, f32::min);
        assert!((2.5..3.2).contains(&nearest), "{scene:?}: nearest {nearest}");
    }
    assert!((unambiguous_range(20.0e6) - 7.4948).abs() < 1e-3);
}

#[test]
fn black_image_noise_and_motion_add_the_errors_they_should() {
    let scene = Scene::sphere();
    let still = simulate(&scene, Motion::Still, &Camera { noise: false, ..Camera::default() }, 0);
    let [.., unsubtracted] = demodulate(&still.raw, 20.0e6);
    let [.., subtracted] = demodulate(&subtract_black(&still.raw, &still.black), 20.0e6);
    let with_pattern = mean(&interior_errors(&unsubtracted, &still.truth));
    let without = mean(&interior_errors(&subtracted, &still.truth));
    assert!(with_pattern > 2.0 * without, "the fixed pattern biases distances: {with_pattern} vs {without}");

    let noisy = simulate(&scene, Motion::Still, &Camera::default(), 0);
    let [.., distance] = demodulate(&subtract_black(&noisy.raw, &noisy.black), 20.0e6);
    let noise_error = mean(&interior_errors(&distance, &noisy.truth));
    assert!(noise_error > without && noise_error < 0.05, "shot noise: {noise_error} m");

    // One centimetre per phase image to the side: the sphere's rim smears (chapter 4).
    let moving =
        simulate(&scene, Motion::Translation([0.01, 0.0, 0.0]), &Camera { noise: false, ..Camera::default() }, 0);
    let [.., distance] = demodulate(&subtract_black(&moving.raw, &moving.black), 20.0e6);
    let all_errors: Vec<f32> = distance
        .data
        .iter()
        .zip(&moving.truth.data)
        .filter(|(_, t)| t.is_finite())
        .map(|(d, t)| (d - t).abs())
        .collect();
    let large = all_errors.iter().filter(|&&e| e > 0.1).count();
    assert!(large > 200, "motion artifacts at the rim: {large} pixels off by more than 10 cm");
}

#[test]
fn long_integration_saturates_and_frames_round_trip_through_npy() {
    let camera = Camera { integration_us: 20_000.0, noise: false, ..Camera::default() };
    let frame = simulate(&Scene::sphere(), Motion::Still, &camera, 0);
    assert!(frame.raw.data.contains(&65535.0), "channels clip at 65535");
    let dir = std::env::temp_dir().join(format!("gudsl-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("raw.npy");
    arrays::write(&path, &[8, 200, 200], &frame.raw.data, arrays::Dtype::U16).unwrap();
    let array = arrays::read(&gudsl_files::Folder::open(&dir).unwrap(), &path).unwrap();
    assert_eq!((array.shape, array.dtype), (vec![8, 200, 200], arrays::Dtype::U16));
    assert_eq!(array.values, frame.raw.data);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_camera_standing_where_the_motion_took_it_sees_that_phase_image() {
    let camera = Camera { noise: false, ..Camera::default() };
    let scene = Scene::cuboid();
    for motion in [Motion::Translation([0.01, 0.0, 0.0]), Motion::Rotation(1.0)] {
        let moving = simulate(&scene, motion, &camera, 2);
        let standing = simulate(&scene, Motion::Still, &standing_at(&camera, motion, 8), 2);
        let n = moving.truth.pixels();
        let differing = (0..2 * n).filter(|&i| (moving.raw.data[i] - standing.raw.data[i]).abs() > 1.0).count();
        assert!(differing <= n / 1000, "{motion:?}: {differing} of phase image 0's channels differ");
        let truth_gap =
            moving.truth.data.iter().zip(&standing.truth.data).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max);
        assert!(truth_gap < 1e-4, "{motion:?}: the truths differ by {truth_gap} m");
        // The later phase images differ: the standing camera does not move on.
        let later = (6 * n..8 * n).filter(|&i| (moving.raw.data[i] - standing.raw.data[i]).abs() > 1.0).count();
        assert!(later > n / 100, "{motion:?}: phase image 3 is the same standing and moving");
    }
}
