//! Every kernel on the GPU (lavapipe in CI) against its CPU reference, on random and on
//! simulated data, with a tolerance per kernel. Without an adapter these tests fail, unless
//! GUDSL_NO_GPU=1 says the machine has none on purpose.

use gudsl_runtime::sim::{simulate, Camera, Motion, Scene};
use gudsl_runtime::{run_cpu, ChainRun, Gpu, Image, Kernel, Pipeline, Shape};

/// A deterministic xorshift generator: the same data on every machine.
struct Random(u64);

impl Random {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn image(&mut self, width: usize, height: usize, planes: usize, scale: f32) -> Image {
        let data = (0..width * height * planes).map(|_| self.next() * scale).collect();
        Image { width, height, planes, data }
    }
}

fn gpu() -> Option<Gpu> {
    Gpu::for_tests()
}

/// Runs `kernel` on `inputs` on both and compares every output sample.
fn check(gpu: &Gpu, kernel: Kernel, inputs: &[Image], tolerance: f32) {
    let mut pipeline = Pipeline::new();
    let sources: Vec<_> = inputs
        .iter()
        .enumerate()
        .map(|(i, image)| {
            let shape = Shape { width: image.width, height: image.height, planes: image.planes };
            pipeline.source(&format!("in{i}"), shape)
        })
        .collect();
    for slot in pipeline.step(kernel, &sources).unwrap() {
        pipeline.sink(slot).unwrap();
    }
    let expected = run_cpu(&pipeline, inputs).unwrap();
    let actual = ChainRun::new(Some(gpu), &pipeline).run(inputs).unwrap();
    for (e, a) in expected.iter().zip(&actual) {
        assert_eq!((e.width, e.height, e.planes), (a.width, a.height, a.planes));
        let worst = e
            .data
            .iter()
            .zip(&a.data)
            .map(|(x, y)| if x.is_nan() && y.is_nan() { 0.0 } else { (x - y).abs() / x.abs().max(1.0) })
            .fold(0.0f32, f32::max);
        assert!(worst <= tolerance, "{}: GPU differs from the CPU by {worst} (tolerance {tolerance})", kernel.name());
    }
}

#[test]
fn filters_match_on_random_images() {
    let Some(gpu) = gpu() else { return };
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    // Odd sizes: partial workgroups at the right and bottom edges.
    let image = random.image(203, 97, 1, 7.5);
    check(&gpu, Kernel::Mean { radius: 1 }, std::slice::from_ref(&image), 1e-6);
    check(&gpu, Kernel::Mean { radius: 3 }, std::slice::from_ref(&image), 1e-6);
    check(&gpu, Kernel::Median { radius: 1 }, std::slice::from_ref(&image), 0.0);
    check(&gpu, Kernel::Median { radius: 2 }, std::slice::from_ref(&image), 0.0);
    check(&gpu, Kernel::Gaussian { sigma: 1.2 }, std::slice::from_ref(&image), 1e-5);
    check(&gpu, Kernel::Bilateral { radius: 2, sigma_space: 2.0, sigma_range: 0.5 }, &[image], 1e-5);
}

#[test]
fn find_index_matches_including_no_match() {
    let Some(gpu) = gpu() else { return };
    let mut random = Random(7);
    let image = random.image(640, 480, 1, 1.0);
    for threshold in [0.0, 0.5, 0.999_99, 2.0] {
        check(&gpu, Kernel::FindIndex { threshold }, std::slice::from_ref(&image), 0.0);
    }
}

#[test]
fn pmd_kernels_match_on_simulated_and_random_frames() {
    let Some(gpu) = gpu() else { return };
    let frame = simulate(&Scene::height_field(), Motion::Translation([0.01, 0.0, 0.0]), &Camera::default(), 0);
    let mut random = Random(99);
    let random_raw = random.image(64, 48, 8, 65535.0);
    let random_black = random.image(64, 48, 8, 200.0);
    for (raw, black) in [(&frame.raw, &frame.black), (&random_raw, &random_black)] {
        check(&gpu, Kernel::SubtractBlack, &[raw.clone(), black.clone()], 0.0);
        // Phase in radians and distance in metres: atan2 and sqrt agree to a few ulps.
        check(&gpu, Kernel::Demodulate { modulation_hz: 20.0e6 }, std::slice::from_ref(raw), 2e-5);
    }
    let distance = random.image(200, 200, 1, 7.0);
    let intensity = random.image(200, 200, 1, 30_000.0);
    let correction = Kernel::CorrectIntensity { q: [0.01, -2e-6, 3e-11], int_time_calib: 500.0, int_time: 1000.0 };
    check(&gpu, correction, &[distance, intensity], 1e-5);
}

/// Black-image subtraction fused into the kernel that reads the frame next — demodulation
/// (`Kernel::SubtractBlackDemodulate`), phase normalization (`SubtractBlackNormalizePhases`) —
/// gives bit for bit what the two kernels give on the GPU, in one dispatch instead of two, on a
/// simulated frame and on random ones whose black image exceeds the raw samples (the clamp at
/// 0); its CPU twin is the two CPU kernels, exactly.
#[test]
fn black_subtraction_fused_into_the_next_kernel_is_exactly_the_two_kernels() {
    let Some(gpu) = gpu() else { return };
    let frame = simulate(&Scene::height_field(), Motion::Still, &Camera::default(), 0);
    let mut random = Random(1234);
    let (random_raw, random_black) = (random.image(67, 45, 8, 3000.0), random.image(67, 45, 8, 1500.0));
    assert!(random_raw.data.iter().zip(&random_black.data).any(|(r, b)| r < b), "some samples clamp");
    let modulation_hz = 20.0e6;
    let pairs = [
        (Kernel::Demodulate { modulation_hz }, Kernel::SubtractBlackDemodulate { modulation_hz }),
        (Kernel::NormalizePhases, Kernel::SubtractBlackNormalizePhases),
    ];
    for (raw, black) in [(&frame.raw, &frame.black), (&random_raw, &random_black)] {
        // Curves f(X) = a·√max(X + b, 0) + c·X + d of every shape: a, b, c, d from 0 to 2, 50, 1.5, 10.
        let scales = [2.0, 50.0, 1.5, 10.0, 2.0, 50.0, 1.5, 10.0];
        let mut calibration = random.image(raw.width, raw.height, 8, 1.0);
        let n = raw.pixels();
        calibration.data.iter_mut().enumerate().for_each(|(at, v)| *v *= scales[at / n]);
        for (next, fused) in pairs {
            let mut inputs = vec![raw.clone(), black.clone()];
            inputs.extend((next == Kernel::NormalizePhases).then(|| calibration.clone()));
            let shapes: Vec<Shape> =
                inputs.iter().map(|i| Shape { width: i.width, height: i.height, planes: 8 }).collect();
            let mut apart = Pipeline::new();
            let sources: Vec<_> = shapes.iter().enumerate().map(|(k, s)| apart.source(&format!("in{k}"), *s)).collect();
            let corrected = apart.step(Kernel::SubtractBlack, &sources[..2]).unwrap()[0];
            let two = apart.step(next, &[&[corrected], &sources[2..]].concat()).unwrap();
            let mut one_pass = Pipeline::new();
            let sources: Vec<_> =
                shapes.iter().enumerate().map(|(k, s)| one_pass.source(&format!("in{k}"), *s)).collect();
            let one = one_pass.step(fused, &sources).unwrap();
            for (pipeline, sinks) in [(&mut apart, two), (&mut one_pass, one)] {
                sinks.into_iter().for_each(|slot| pipeline.sink(slot).unwrap());
            }
            let (mut two, mut one) = (ChainRun::new(Some(&gpu), &apart), ChainRun::new(Some(&gpu), &one_pass));
            let (expected, actual) = (two.run(&inputs).unwrap(), one.run(&inputs).unwrap());
            for (k, (e, a)) in expected.iter().zip(&actual).enumerate() {
                assert!(e.data == a.data, "{}: output {k} differs from the two kernels'", fused.name());
            }
            assert_eq!((two.take_work().dispatches, one.take_work().dispatches), (vec![0, 1], vec![0]));
            let cpu = run_cpu(&one_pass, &inputs).unwrap();
            assert!(cpu == run_cpu(&apart, &inputs).unwrap(), "{}: the CPU twin", fused.name());
        }
    }
}

#[test]
fn motion_compensation_kernels_match_on_a_moving_scene() {
    let Some(gpu) = gpu() else { return };
    let frame = simulate(&Scene::height_field(), Motion::Translation([0.02, 0.0, 0.0]), &Camera::default(), 0);
    let raw = gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black);
    let calibration = gudsl_runtime::phase_normalization::PhaseCalibration::simulated(&Camera {
        intrinsics: gudsl_runtime::camera::Intrinsics::camcube_at(raw.width, raw.height),
        gain_spread: 0.02,
        ..Camera::default()
    });
    check(&gpu, Kernel::NormalizePhases, &[raw.clone(), calibration.coefficients], 1e-5);
    check(&gpu, Kernel::DetectMotion { theta: 655.0 }, std::slice::from_ref(&raw), 0.0);
    let [_, mask] = gudsl_runtime::kernels::motion::detect(&raw, 655.0);
    let moving = mask.data.iter().filter(|&&m| m == 1.0).count();
    assert!(moving > 1000, "the moving scene has moving pixels: {moving}");
    for restriction in [None, Some((0.0, std::f32::consts::FRAC_PI_4)), Some((3.0, std::f32::consts::FRAC_PI_2))] {
        for (window, subpixel) in [(5, false), (7, false), (5, true)] {
            // SSD sums may round differently on the GPU (fused multiply-add): a near tie may
            // pick another vector; allow one pixel in ten thousand.
            let kernel = Kernel::MatchBlocks { window, restriction, subpixel };
            let (cpu, gpu_flow) = both(&gpu, kernel, &[raw.clone(), mask.clone()]);
            let differing = (0..cpu.pixels())
                .filter(|&i| {
                    cpu.data[i] != gpu_flow.data[i] || cpu.data[cpu.pixels() + i] != gpu_flow.data[cpu.pixels() + i]
                })
                .count();
            assert!(
                differing * 10_000 <= cpu.pixels(),
                "{window} {subpixel} {restriction:?}: {differing} flow vectors differ"
            );
            check(&gpu, Kernel::SmoothFlow { window }, std::slice::from_ref(&cpu), 0.0);
            // Whole-pixel flows copy samples; quarter-pixel ones blend four (FMA may round apart).
            check(&gpu, Kernel::CorrectRaw, &[raw.clone(), cpu], if subpixel { 1e-6 } else { 0.0 });
        }
    }
}

/// Motion compensation's fused pass (`Kernel::DetectMatch`) gives exactly what detection then
/// matching give on the GPU, in one dispatch instead of two; its CPU twin agrees as matching's
/// does.
#[test]
fn fused_detection_and_matching_is_exactly_the_two_kernels() {
    let Some(gpu) = gpu() else { return };
    let frame = simulate(&Scene::height_field(), Motion::Translation([0.02, 0.0, 0.0]), &Camera::default(), 0);
    let raw = gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black);
    let shape = Shape { width: raw.width, height: raw.height, planes: 8 };
    let theta = 655.0;
    for restriction in [None, Some((0.5, std::f32::consts::FRAC_PI_4))] {
        for (window, subpixel) in [(5, false), (7, true)] {
            let mut apart = Pipeline::new();
            let source = apart.source("raw", shape);
            let mask = apart.step(Kernel::DetectMotion { theta }, &[source]).unwrap()[1];
            let flow = apart.step(Kernel::MatchBlocks { window, restriction, subpixel }, &[source, mask]).unwrap()[0];
            let mut fused = Pipeline::new();
            let source = fused.source("raw", shape);
            let both = fused.step(Kernel::DetectMatch { theta, window, restriction, subpixel }, &[source]).unwrap();
            for (pipeline, sinks) in [(&mut apart, [flow, mask]), (&mut fused, [both[0], both[1]])] {
                sinks.into_iter().for_each(|slot| pipeline.sink(slot).unwrap());
            }
            let (mut two, mut one) = (ChainRun::new(Some(&gpu), &apart), ChainRun::new(Some(&gpu), &fused));
            let (expected, actual) =
                (two.run(std::slice::from_ref(&raw)).unwrap(), one.run(std::slice::from_ref(&raw)).unwrap());
            assert_eq!(expected[1].data, actual[1].data, "the masks");
            assert!(actual[1].data.iter().filter(|&&m| m == 1.0).count() > 1000, "moving pixels");
            assert_eq!(expected[0].data, actual[0].data, "{window} {subpixel} {restriction:?}: the flows");
            // One submission a run (the sources' upload rides on it), one dispatch a kernel.
            let (work_two, work_one) = (two.take_work(), one.take_work());
            assert_eq!((work_two.dispatches, work_two.submissions), (vec![0, 1], 1));
            assert_eq!((work_one.dispatches, work_one.submissions), (vec![0], 1));
            let cpu = run_cpu(&fused, std::slice::from_ref(&raw)).unwrap();
            assert_eq!(cpu[1].data, actual[1].data, "the CPU's mask");
            let differing = (0..2 * cpu[0].pixels()).filter(|&i| cpu[0].data[i] != actual[0].data[i]).count();
            assert!(differing * 10_000 <= cpu[0].pixels(), "{differing} flow samples differ from the CPU's");
        }
    }
}

#[test]
fn car_chain_kernels_match_on_simulated_frames() {
    let Some(gpu) = gpu() else { return };
    let camera = Camera::default();
    let frame = simulate(&Scene::sphere(), Motion::Still, &camera, 0);
    let empty = simulate(&Scene::empty(), Motion::Still, &camera, 0);
    let demodulated = |f: &gudsl_runtime::sim::Frame| {
        gudsl_runtime::kernels::tof::demodulate(&gudsl_runtime::kernels::tof::subtract_black(&f.raw, &f.black), 20.0e6)
    };
    let [_, amplitude, intensity, distance] = demodulated(&frame);
    let [_, _, background_intensity, background_distance] = demodulated(&empty);
    check(&gpu, Kernel::MaskAmplitude { min: 250.0, max: 1200.0 }, &[distance.clone(), amplitude], 0.0);
    check(&gpu, Kernel::RemoveOutliers { range: 0.05, min_similar: 3 }, std::slice::from_ref(&distance), 0.0);
    let segment = Kernel::Segment { theta_intensity: 50.0, theta_distance: 0.1 };
    let inputs = [intensity, distance.clone(), background_intensity, background_distance];
    check(&gpu, segment, &inputs, 0.0);
    let mask = run_cpu_single(segment, &inputs);
    for dilate in [false, true] {
        check(&gpu, Kernel::Morphology { radius: 1, dilate }, std::slice::from_ref(&mask), 0.0);
    }
    check(&gpu, Kernel::ApplyMask, &[distance.clone(), mask], 0.0);
    let rays = camera.intrinsics.rays();
    check(&gpu, Kernel::PointCloud, &[distance.clone(), rays.clone()], 1e-6);
    let points = gudsl_runtime::kernels::car::point_cloud(&distance, &rays);
    check(&gpu, Kernel::Normals, std::slice::from_ref(&points), 1e-5);
    let turned = gudsl_runtime::camera::pose_from([0.01, -0.02, 0.015], [0.03, -0.01, 0.02]);
    check(&gpu, Kernel::TransformPoints { pose: turned }, std::slice::from_ref(&points), 1e-6);
}

#[test]
fn integration_time_estimate_matches_on_bright_and_dark_frames() {
    let Some(gpu) = gpu() else { return };
    let model = gudsl_runtime::kernels::integration::IntegrationModel::CAMCUBE;
    for t in [50.0, 1000.0, 8000.0] {
        let camera = Camera { integration_us: t, supersampling: 1, ..Camera::default() };
        let frame = simulate(&Scene::plates(), Motion::Still, &camera, 0);
        let raw = gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black);
        let [_, _, intensity, _] = gudsl_runtime::kernels::tof::demodulate(&raw, 20.0e6);
        // Scaled into Table 5.1's intensity range, so h's part is exercised too.
        let scaled = Image { data: intensity.data.iter().map(|v| v * 0.2).collect(), ..intensity };
        // A weighted mean of 40 000 values: f32 trees against f64.
        check(&gpu, Kernel::IntegrationTime { t_curr: t, model }, &[scaled], 1e-4);
    }
    let dark = Image::zeros(200, 200, 1);
    check(&gpu, Kernel::IntegrationTime { t_curr: 700.0, model }, &[dark], 0.0);
}

#[test]
fn icp_reduction_matches_on_two_views() {
    let Some(gpu) = gpu() else { return };
    let cloud = |pose| {
        let camera = Camera { pose, ..Camera::default() };
        let frame = simulate(&Scene::turned_box(), Motion::Still, &camera, 0);
        let raw = gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black);
        let [.., distance] = gudsl_runtime::kernels::tof::demodulate(&raw, 20.0e6);
        let distance = gudsl_runtime::kernels::gaussian(&distance, 2.0);
        gudsl_runtime::registration::Cloud::from_distance(&distance, &camera.intrinsics)
    };
    let moved = gudsl_runtime::camera::pose_from([0.01, -0.02, 0.015], [0.03, -0.01, 0.02]);
    let (model, source) = (cloud(gudsl_runtime::camera::IDENTITY), cloud(moved));
    let inputs = [source.points, source.normals, model.points, model.normals];
    // At the identity, halfway and at the move: the sums of ~36 000 pairs, f32 tree on the GPU
    // against f64 on the CPU; a pair on the edge of a threshold may flip, hence 1e-3.
    for pose in [gudsl_runtime::camera::IDENTITY, moved] {
        let kernel = Kernel::IcpReduce {
            pose,
            intrinsics: Camera::default().intrinsics,
            max_distance: 0.2,
            min_cos: 20f32.to_radians().cos(),
        };
        check(&gpu, kernel, &inputs, 1e-3);
        let pairs = run_cpu_single(kernel, &inputs).data[27];
        assert!(pairs > 30_000.0, "pairs at {pose:?}: {pairs}");
    }
}

fn run_cpu_single(kernel: Kernel, inputs: &[Image]) -> Image {
    let refs: Vec<&Image> = inputs.iter().collect();
    kernel.cpu(&refs).remove(0)
}

/// The single output of `kernel` on the CPU and on the GPU.
fn both(gpu: &Gpu, kernel: Kernel, inputs: &[Image]) -> (Image, Image) {
    let mut pipeline = Pipeline::new();
    let sources: Vec<_> = inputs
        .iter()
        .enumerate()
        .map(|(i, im)| {
            pipeline.source(&format!("in{i}"), Shape { width: im.width, height: im.height, planes: im.planes })
        })
        .collect();
    let out = pipeline.step(kernel, &sources).unwrap()[0];
    pipeline.sink(out).unwrap();
    let cpu = run_cpu(&pipeline, inputs).unwrap().remove(0);
    let gpu = ChainRun::new(Some(gpu), &pipeline).run(inputs).unwrap().remove(0);
    (cpu, gpu)
}

#[test]
fn without_an_adapter_the_same_pipeline_runs_on_the_cpu_reference() {
    let image = Random(7).image(64, 48, 1, 1.0);
    let mut pipeline = Pipeline::new();
    let input = pipeline.source("in", Shape { width: 64, height: 48, planes: 1 });
    let out = pipeline.step(Kernel::Gaussian { sigma: 1.5 }, &[input]).unwrap()[0];
    pipeline.sink(out).unwrap();
    let mut on_cpu = gudsl_runtime::ChainRun::new(None, &pipeline);
    assert!(!on_cpu.on_gpu());
    let expected = on_cpu.run(std::slice::from_ref(&image)).unwrap().remove(0);
    assert_eq!(expected, gudsl_runtime::kernels::gaussian(&image, 1.5));
    let Some(gpu) = gpu() else { return };
    let mut on_gpu = gudsl_runtime::ChainRun::new(Some(&gpu), &pipeline);
    assert!(on_gpu.on_gpu());
    let actual = on_gpu.run(&[image]).unwrap().remove(0);
    let worst = expected.data.iter().zip(&actual.data).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
    assert!(worst < 1e-5, "{worst}");
}
