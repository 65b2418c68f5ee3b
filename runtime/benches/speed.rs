//! Speed of every kernel and of whole chains at 200×200, 640×480 and 1024×1024, on the CPU
//! reference (one thread) and on wgpu (the adapter wgpu finds: lavapipe without a GPU), side by
//! side in one run. GPU kernel times are submit-to-done of that kernel alone, data already on the
//! GPU; chain rows also give the round trip (upload, all steps, readback of the sinks).
//! Medians of repeated runs.
//!
//! `cargo bench -p gudsl-runtime --bench speed`

use std::{
    f32::consts::FRAC_PI_4,
    time::{Duration, Instant},
};

use gudsl_runtime::camera::{Intrinsics, IDENTITY};
use gudsl_runtime::kernels::integration::IntegrationModel;
use gudsl_runtime::{run_cpu, ChainRun, Gpu, Image, Kernel, Pipeline, Shape};

/// Deterministic test data (xorshift): raw frames in 0..65535, images in 0..8.
fn random(width: usize, height: usize, planes: usize, scale: f32, seed: u64) -> Image {
    let mut state = seed | 1;
    let data = (0..width * height * planes)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 40) as f32 / (1u64 << 24) as f32 * scale).round()
        })
        .collect();
    Image { width, height, planes, data }
}

fn median_ms(mut samples: Vec<Duration>) -> f64 {
    samples.sort();
    samples[samples.len() / 2].as_secs_f64() * 1e3
}

fn repeats(width: usize) -> usize {
    if width > 600 {
        5
    } else {
        15
    }
}

/// A one-kernel pipeline over fresh sources of the right shapes.
fn single(kernel: Kernel, inputs: &[Image]) -> Pipeline {
    let mut p = Pipeline::new();
    let sources: Vec<_> = inputs
        .iter()
        .enumerate()
        .map(|(i, im)| p.source(&format!("in{i}"), Shape { width: im.width, height: im.height, planes: im.planes }))
        .collect();
    for out in p.step(kernel, &sources).unwrap() {
        p.sink(out).unwrap();
    }
    p
}

/// Motion compensation (chapter 4, MWS 5, θ 1 %) then demodulation.
fn motion_chain(width: usize, height: usize) -> Pipeline {
    let mut p = Pipeline::new();
    let shape = Shape { width, height, planes: 8 };
    let (raw, black) = (p.source("raw", shape), p.source("black", shape));
    let raw = p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0];
    let detect_match = Kernel::DetectMatch { theta: 655.0, window: 5, restriction: None, subpixel: false };
    let flow = p.step(detect_match, &[raw]).unwrap()[0];
    let corrected = p.step(Kernel::CorrectRaw, &[raw, flow]).unwrap()[0];
    let outputs = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[corrected]).unwrap();
    p.sink(outputs[1]).unwrap();
    p.sink(outputs[3]).unwrap();
    p
}

/// Demodulation and the chapter 6 filters: median 3×3, median 5×5, Gaussian, bilateral.
fn filter_chain(width: usize, height: usize) -> Pipeline {
    let mut p = Pipeline::new();
    let raw = p.source("raw", Shape { width, height, planes: 8 });
    let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[3];
    let a = p.step(Kernel::Median { radius: 1 }, &[distance]).unwrap()[0];
    let b = p.step(Kernel::Median { radius: 2 }, &[a]).unwrap()[0];
    let c = p.step(Kernel::Gaussian { sigma: 1.0 }, &[b]).unwrap()[0];
    let d = p.step(Kernel::Bilateral { radius: 2, sigma_space: 2.0, sigma_range: 0.05 }, &[c]).unwrap()[0];
    p.sink(d).unwrap();
    p
}

/// Intrinsics of Table 2.1 stretched to another sensor size.
fn intrinsics(width: usize, height: usize) -> Intrinsics {
    Intrinsics { width, height, cx: width as f32 / 2.0, cy: height as f32 / 2.0, ..Intrinsics::CAMCUBE }
}

/// The chapter 6 chain per frame after motion compensation: demodulation, amplitude mask,
/// median 5×5, Gaussian σ 4, outlier removal, segmentation with opening and closing, point
/// cloud, normals, one ICP reduction against the model and the transform of the cloud.
fn car_chain(width: usize, height: usize) -> Pipeline {
    let mut p = Pipeline::new();
    let plane = Shape { width, height, planes: 1 };
    let cloud = Shape { planes: 3, ..plane };
    let raw = p.source("raw", Shape { planes: 8, ..plane });
    let (bg_intensity, bg_distance) = (p.source("background intensity", plane), p.source("background distance", plane));
    let rays = p.source("rays", cloud);
    let (model, model_normals) = (p.source("model", cloud), p.source("model normals", cloud));
    let [_, amplitude, intensity, distance] = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[..]
    else {
        unreachable!()
    };
    let mut d = p.step(Kernel::MaskAmplitude { min: 250.0, max: 60_000.0 }, &[distance, amplitude]).unwrap()[0];
    d = p.step(Kernel::Median { radius: 2 }, &[d]).unwrap()[0];
    d = p.step(Kernel::Gaussian { sigma: 4.0 }, &[d]).unwrap()[0];
    d = p.step(Kernel::RemoveOutliers { range: 0.05, min_similar: 3 }, &[d]).unwrap()[0];
    let segment = Kernel::Segment { theta_intensity: 100.0, theta_distance: 0.3 };
    let mut mask = p.step(segment, &[intensity, d, bg_intensity, bg_distance]).unwrap()[0];
    for dilate in [false, true, true, false] {
        mask = p.step(Kernel::Morphology { radius: 1, dilate }, &[mask]).unwrap()[0];
    }
    d = p.step(Kernel::ApplyMask, &[d, mask]).unwrap()[0];
    let points = p.step(Kernel::PointCloud, &[d, rays]).unwrap()[0];
    let normals = p.step(Kernel::Normals, &[points]).unwrap()[0];
    let icp =
        Kernel::IcpReduce { pose: IDENTITY, intrinsics: intrinsics(width, height), max_distance: 0.2, min_cos: 0.94 };
    let sums = p.step(icp, &[points, normals, model, model_normals]).unwrap()[0];
    let moved = p.step(Kernel::TransformPoints { pose: IDENTITY }, &[points]).unwrap()[0];
    p.sink(sums).unwrap();
    p.sink(moved).unwrap();
    p
}

fn main() {
    let gpu = Gpu::new().map_err(|e| eprintln!("{e}: GPU columns left empty")).ok();
    let device = gpu.as_ref().map_or("none".to_string(), Gpu::describe);
    println!("CPU: reference, one thread. GPU: {device}. Milliseconds, medians.\n");
    println!("{:<28} {:>10} | {:>9} {:>9} {:>9} | {:>7}", "kernel", "size", "CPU", "GPU", "GPU trip", "speedup");
    for (w, h) in [(200usize, 200usize), (640, 480), (1024, 1024)] {
        let raw = random(w, h, 8, 30_000.0, 1);
        let black = random(w, h, 8, 100.0, 2);
        let image = random(w, h, 1, 8.0, 3);
        let intensity = random(w, h, 1, 30_000.0, 4);
        let intensity_bg = random(w, h, 1, 30_000.0, 6);
        let [_, mask] = gudsl_runtime::kernels::motion::detect(&raw, 655.0);
        let flow = gudsl_runtime::kernels::motion::match_blocks(&raw, &mask, 5, None, false);
        let direction = Image { width: 1, height: 1, planes: 2, data: vec![0.5, 1.0] };
        let k = intrinsics(w, h);
        let rays = k.rays();
        let points = gudsl_runtime::kernels::car::point_cloud(&image, &rays);
        let normals = gudsl_runtime::kernels::car::normals(&points);
        let icp = Kernel::IcpReduce { pose: IDENTITY, intrinsics: k, max_distance: 0.2, min_cos: 0.94 };
        let background = random(w, h, 1, 8.0, 5);
        let cases: Vec<(Kernel, Vec<Image>)> = vec![
            (Kernel::SubtractBlack, vec![raw.clone(), black.clone()]),
            (Kernel::Demodulate { modulation_hz: 20.0e6 }, vec![raw.clone()]),
            (Kernel::SubtractBlackDemodulate { modulation_hz: 20.0e6 }, vec![raw.clone(), black.clone()]),
            (
                Kernel::CorrectIntensity { q: [0.01, -1e-6, 1e-11], int_time_calib: 500.0, int_time: 1000.0 },
                vec![image.clone(), intensity],
            ),
            (Kernel::DetectMotion { theta: 655.0 }, vec![raw.clone()]),
            (Kernel::MatchBlocks { window: 5, restriction: None, subpixel: false }, vec![raw.clone(), mask.clone()]),
            (Kernel::MatchBlocks { window: 7, restriction: None, subpixel: false }, vec![raw.clone(), mask.clone()]),
            (Kernel::DetectMatch { theta: 655.0, window: 5, restriction: None, subpixel: false }, vec![raw.clone()]),
            // ρ = 90°: around a direction given as a parameter, and one in a buffer (the GPU's).
            (
                Kernel::DetectMatch { theta: 655.0, window: 5, restriction: Some((0.5, FRAC_PI_4)), subpixel: false },
                vec![raw.clone()],
            ),
            (
                Kernel::DetectMatchAround { theta: 655.0, window: 5, half_width: FRAC_PI_4, subpixel: false },
                vec![raw.clone(), direction.clone()],
            ),
            (Kernel::MeanDirection, vec![flow.clone(), direction.clone()]),
            (Kernel::SmoothFlow { window: 5 }, vec![flow.clone()]),
            (Kernel::CorrectRaw, vec![raw.clone(), flow]),
            (Kernel::Mean { radius: 1 }, vec![image.clone()]),
            (Kernel::Median { radius: 1 }, vec![image.clone()]),
            (Kernel::Median { radius: 2 }, vec![image.clone()]),
            (Kernel::Gaussian { sigma: 1.0 }, vec![image.clone()]),
            (Kernel::Bilateral { radius: 2, sigma_space: 2.0, sigma_range: 0.05 }, vec![image.clone()]),
            (Kernel::FindIndex { threshold: 7.9 }, vec![image.clone()]),
            (Kernel::MaskAmplitude { min: 2.0, max: 6.0 }, vec![image.clone(), image.clone()]),
            (Kernel::RemoveOutliers { range: 0.05, min_similar: 3 }, vec![image.clone()]),
            (Kernel::Segment { theta_intensity: 1.0, theta_distance: 1.0 }, vec![image.clone(); 4]),
            (Kernel::Morphology { radius: 1, dilate: true }, vec![mask.clone()]),
            (Kernel::PointCloud, vec![image.clone(), rays.clone()]),
            (Kernel::Normals, vec![points.clone()]),
            (icp, vec![points.clone(), normals.clone(), points.clone(), normals.clone()]),
            (Kernel::TransformPoints { pose: IDENTITY }, vec![points.clone()]),
            (Kernel::IntegrationTime { t_curr: 1000.0, model: IntegrationModel::CAMCUBE }, vec![image.clone()]),
        ];
        let n = repeats(w);
        for (kernel, inputs) in cases {
            let label = match kernel {
                Kernel::MatchBlocks { window, .. } => format!("match_blocks MWS {window}"),
                Kernel::DetectMatch { window, restriction: None, .. } => format!("detect_match MWS {window}"),
                Kernel::DetectMatch { window, .. } => format!("detect_match MWS {window}, ρ 90°"),
                Kernel::DetectMatchAround { window, .. } => format!("detect_match_around MWS {window}, ρ 90°"),
                Kernel::Median { radius } => format!("median {0}×{0}", 2 * radius + 1),
                other => other.name().to_string(),
            };
            let pipeline = single(kernel, &inputs);
            let cpu = median_ms((0..n.min(5)).map(|_| time(|| drop(run_cpu(&pipeline, &inputs).unwrap()))).collect());
            let gpu_ms = gpu.as_ref().map(|gpu| {
                let mut prepared = ChainRun::new(Some(gpu), &pipeline);
                prepared.run(&inputs).unwrap(); // warm up: pipelines compiled, buffers touched
                median_ms((0..n).map(|_| prepared.time_steps(&inputs).unwrap()[0]).collect())
            });
            row(&label, w, h, cpu, gpu_ms, None);
        }
        for (label, pipeline, inputs) in [
            ("chain: motion comp. + demod", motion_chain(w, h), vec![raw.clone(), black.clone()]),
            ("chain: demod + 4 filters", filter_chain(w, h), vec![raw.clone()]),
            (
                "chain: car (ch. 6, 1 ICP step)",
                car_chain(w, h),
                vec![
                    raw.clone(),
                    intensity_bg.clone(),
                    background.clone(),
                    rays.clone(),
                    points.clone(),
                    normals.clone(),
                ],
            ),
        ] {
            let cpu = median_ms((0..n.min(5)).map(|_| time(|| drop(run_cpu(&pipeline, &inputs).unwrap()))).collect());
            let (gpu_ms, trip) = gpu.as_ref().map_or((None, None), |gpu| {
                let mut prepared = ChainRun::new(Some(gpu), &pipeline);
                prepared.run(&inputs).unwrap();
                let steps =
                    median_ms((0..n).map(|_| prepared.time_steps(&inputs).unwrap().into_iter().sum()).collect());
                let trip = median_ms((0..n).map(|_| time(|| drop(prepared.run(&inputs).unwrap()))).collect());
                (Some(steps), Some(trip))
            });
            row(label, w, h, cpu, gpu_ms, trip);
        }
        println!();
    }
    println!("Reference (dissertation, GTX 680): motion compensation 12.58 ms at MWS 5 (200×200, Table 4.2); car chain 40.96 ms per frame.");
}

fn time(f: impl FnOnce()) -> Duration {
    let start = Instant::now();
    f();
    start.elapsed()
}

fn row(label: &str, w: usize, h: usize, cpu: f64, gpu: Option<f64>, trip: Option<f64>) {
    let show = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
    let speedup = gpu.map_or("-".to_string(), |g| format!("{:.1}×", cpu / g));
    println!("{label:<28} {:>10} | {cpu:>9.2} {:>9} {:>9} | {speedup:>7}", format!("{w}×{h}"), show(gpu), show(trip));
}
