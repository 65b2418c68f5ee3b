//! The chapter 6 steps on simulated frames do what they are for: outlier removal takes the
//! flying pixels, segmentation against the empty scene finds the object, the point cloud puts the
//! wall at 4 m and its normals face the camera.

use gudsl_runtime::kernels::car::{background, morphology, normals, point_cloud, remove_outliers, segment};
use gudsl_runtime::kernels::tof::{demodulate, subtract_black};
use gudsl_runtime::sim::{simulate, Camera, Frame, Motion, Scene};
use gudsl_runtime::Image;

fn demodulated(frame: &Frame) -> [Image; 4] {
    demodulate(&subtract_black(&frame.raw, &frame.black), 20.0e6)
}

#[test]
fn outlier_removal_takes_the_flying_pixels() {
    let frame = simulate(&Scene::sphere(), Motion::Still, &Camera::default(), 0);
    let [.., distance] = demodulated(&frame);
    let flying =
        |d: &Image| d.data.iter().zip(&frame.truth.data).filter(|(d, t)| **d != 0.0 && (*d - *t).abs() > 0.1).count();
    let before = flying(&distance);
    let cleaned = remove_outliers(&distance, 0.05, 3);
    let after = flying(&cleaned);
    let kept = cleaned.data.iter().filter(|d| **d != 0.0).count();
    assert!(before > 50, "the sphere's rim has flying pixels: {before}");
    assert!(after * 4 < before, "outlier removal: {before} -> {after} flying pixels");
    assert!(kept > 36_000, "valid pixels stay: {kept} of 40000 ({before} -> {after} flying)");
}

#[test]
fn segmentation_against_the_empty_scene_finds_the_object() {
    let camera = Camera::default();
    let empties: Vec<[Image; 4]> =
        (0..5).map(|k| demodulated(&simulate(&Scene::empty(), Motion::Still, &camera, k))).collect();
    let background_intensity = background(&empties.iter().map(|e| e[2].clone()).collect::<Vec<_>>());
    let background_distance = background(&empties.iter().map(|e| e[3].clone()).collect::<Vec<_>>());
    let frame = simulate(&Scene::cuboid(), Motion::Still, &camera, 7);
    let [_, _, intensity, distance] = demodulated(&frame);
    let mask = segment(&intensity, &distance, &background_intensity, &background_distance, 100.0, 0.3);
    // Opening removes single pixels, closing fills holes.
    let opened = morphology(&morphology(&mask, 1, false), 1, true);
    let closed = morphology(&morphology(&opened, 1, true), 1, false);
    let truth: Vec<bool> = frame.truth.data.iter().map(|t| *t < 3.85).collect();
    let both = closed.data.iter().zip(&truth).filter(|(m, t)| **m != 0.0 && **t).count();
    let either = closed.data.iter().zip(&truth).filter(|(m, t)| **m != 0.0 || **t).count();
    let iou = both as f32 / either as f32;
    assert!(iou > 0.9, "foreground vs the box: IoU {iou}");
}

#[test]
fn the_point_cloud_puts_the_wall_at_four_metres_facing_the_camera() {
    let camera = Camera { noise: false, ..Camera::default() };
    let frame = simulate(&Scene::empty(), Motion::Still, &camera, 0);
    let [.., distance] = demodulated(&frame);
    let points = point_cloud(&distance, &camera.intrinsics.rays());
    let n = points.pixels();
    let mut depths: Vec<f32> = points.data[2 * n..].to_vec();
    depths.sort_by(f32::total_cmp);
    let median = depths[n / 2];
    assert!((median - 4.0).abs() < 0.01, "the wall's z: {median}");
    let normal = normals(&points);
    let centre = 100 * 200 + 100;
    let nz = normal.data[2 * n + centre];
    assert!(nz < -0.99, "the wall's normal faces the camera: z = {nz}");
}
