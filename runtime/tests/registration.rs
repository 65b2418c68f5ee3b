//! ICP on simulated views finds the camera's move: a second view of the turned-box scene from a
//! known pose, preprocessed as in chapter 6 (median 5×5, Gaussian σ = 4 px, outlier removal),
//! registers back onto the first, the same on the CPU and the GPU; frame-to-frame
//! tracking chains the moves; clouds that do not overlap are an error, not a pose.

use gudsl_runtime::camera::{pose_difference, pose_from, Pose, IDENTITY};
use gudsl_runtime::kernels::car::remove_outliers;
use gudsl_runtime::kernels::tof::{demodulate, subtract_black};
use gudsl_runtime::kernels::{gaussian, median};
use gudsl_runtime::registration::{
    register_cpu, track, Accumulation, Cloud, GpuRegistration, IcpSettings, RegistrationError,
};
use gudsl_runtime::sim::{simulate, Camera, Motion, Scene};
use gudsl_runtime::Gpu;

fn view(pose: Pose, seed: u64) -> Cloud {
    let camera = Camera { pose, seed, ..Camera::default() };
    let frame = simulate(&Scene::turned_box(), Motion::Still, &camera, 0);
    let [.., distance] = demodulate(&subtract_black(&frame.raw, &frame.black), camera.modulation_hz);
    let smooth = gaussian(&median(&distance, 2), 4.0);
    let distance = remove_outliers(&smooth, 0.05, 3);
    Cloud::from_distance(&distance, &camera.intrinsics)
}

fn moved() -> Pose {
    pose_from([0.4f64.to_radians(), (-1.5f64).to_radians(), 2.0f64.to_radians()], [0.04, -0.02, 0.05])
}

#[test]
fn icp_recovers_the_second_views_pose_on_cpu_and_gpu() {
    let (model, source) = (view(IDENTITY, 1), view(moved(), 2));
    let settings = IcpSettings::default();
    let k = Camera::default().intrinsics;
    let cpu = register_cpu(&source, &model, &k, &settings, IDENTITY).expect("registration");
    let (angle, distance) = pose_difference(&cpu.pose, &moved());
    assert!(cpu.converged, "{cpu:?}");
    eprintln!("CPU: off by {angle}° and {distance} m: {cpu:?}");
    assert!(angle < 0.25 && distance < 0.01, "CPU ICP is off by {angle}° and {distance} m: {cpu:?}");
    assert!(cpu.rms < 0.02, "point-to-plane rms {} m", cpu.rms);
    let Some(gpu) = Gpu::for_tests() else { return };
    let on_gpu = GpuRegistration::new(&gpu, &k, &settings)
        .unwrap()
        .register(&source, &model, IDENTITY)
        .expect("GPU registration");
    let (angle, distance) = pose_difference(&on_gpu.pose, &cpu.pose);
    assert!(angle < 0.01 && distance < 0.0005, "GPU and CPU ICP differ by {angle}° and {distance} m");
}

#[test]
fn tracking_chains_frame_to_frame_moves_and_accumulates_one_model() {
    // The camera slides right and turns a little, 5 views.
    let truth: Vec<Pose> = (0..5)
        .map(|i| {
            let s = i as f64;
            pose_from([0.0, (-0.8 * s).to_radians(), 0.0], [0.03 * s, 0.0, 0.01 * s])
        })
        .collect();
    let clouds: Vec<Cloud> = truth.iter().enumerate().map(|(i, &p)| view(p, i as u64 + 1)).collect();
    let k = Camera::default().intrinsics;
    let settings = IcpSettings::default();
    let poses = track(&clouds, |s, m, guess| register_cpu(s, m, &k, &settings, guess)).expect("tracking");
    let (angle, distance) = pose_difference(&poses[4], &truth[4]);
    eprintln!("track: off by {angle}° and {distance} m");
    // Each step overestimates the slide by ~4 mm: with a 60° field of view a small pan and a
    // slide look alike (0.06° at 3.5 m is 4 mm). Without registration it would be 12.4 cm.
    assert!(angle < 0.5 && distance < 0.025, "after 4 moves the track is off by {angle}° and {distance} m");
    let mut model = Accumulation::default();
    for (cloud, pose) in clouds.iter().zip(&poses) {
        model.add(cloud, pose);
    }
    let mut ply = Vec::new();
    model.write_ply(&mut ply).unwrap();
    let header_end = ply.windows(11).position(|w| w == b"end_header\n").expect("a PLY header") + 11;
    let header = std::str::from_utf8(&ply[..header_end]).unwrap();
    assert!(header.contains(&format!("element vertex {}\n", model.points.len())), "{header}");
    assert_eq!(ply.len() - header_end, model.points.len() * 24);
    // The wall of every view lands on the same plane z = 4 m in the first view's frame.
    let wall: Vec<f32> = model.points.iter().map(|p| p[2]).filter(|z| *z > 3.9).collect();
    let mean = wall.iter().sum::<f32>() / wall.len() as f32;
    assert!((mean - 4.0).abs() < 0.01 && wall.len() > 100_000, "wall at {mean} m from {} points", wall.len());
}

#[test]
fn clouds_that_do_not_overlap_are_an_error() {
    let model = view(IDENTITY, 1);
    let far = pose_from([0.0, 0.0, 0.0], [5.0, 0.0, 0.0]);
    let settings = IcpSettings::default();
    let error = register_cpu(&model, &model, &Camera::default().intrinsics, &settings, far).unwrap_err();
    assert!(matches!(error, RegistrationError::TooFewPairs { pairs: 0, .. }), "{error}");
    assert!(error.to_string().contains("barely overlap"), "{error}");
}
