//! Chapter 4's pipeline run from GU-DSL (a component-instance diagram: the model's plan, the
//! host's components) against the same work assembled on the runtime's Rust API, side by side
//! in one process on the adapter wgpu finds, at 200×200 and 640×480: a simulated camera moving
//! 1 cm per phase image, black-image correction, motion compensation (MWS 5, θ 1 %, no
//! direction restriction, so both sides run one fixed chain), demodulation, the distance
//! written as `.npy` each frame. Both simulate on the CPU, run the same kernels on the GPU and
//! read the distance back once a frame.
//!
//! The time per frame is the steady state: for GU-DSL (T(n) − T(1)) / (n − 1) over runs, each
//! without reading its files (`PipelineReport::loading`), so compiling the kernels and the
//! first frame cancel out; for Rust the loop over frames after the chain is built, recorded
//! frames already in memory. Runs alternate the two; the times are medians, the overhead the
//! median of each run's ratio with its quartiles (the machine's pace drifts between runs, both
//! sides with it, so the paired ratio is steadier than the ratio of medians); the simulator's
//! share of the Rust loop beside them (the CPU's work both sides do).
//!
//! Chapter 6's scan (`samples/pipelines/ch6_object_scan.gudsl`: three simulated cameras, three
//! frames of the empty scene learnt as background, then segmentation, clouds, ICP, transforms,
//! accumulation, the PLY at the end) against `tests/support/scan.rs`, the same on the API: the
//! time per frame over frames 1–5 (GU-DSL: (T(6) − T(1)) / 5; Rust: after frame 0), both with
//! the PLY written.
//!
//! `cargo bench -p gudsl-host --bench pipeline_vs_rust [-- FILTER]` (FILTER: run only the rows
//! whose label holds it, e.g. `chapter-4 640x480 recorded`'s `640x480 recorded`).

#[path = "common/chapter4.rs"]
mod chapter4;
#[path = "../../tests/support/scan.rs"]
mod scan;
#[path = "../tests/support/mod.rs"]
mod support;

use std::{
    path::Path,
    time::{Duration, Instant},
};

use chapter4::{model, record, run_model, Frames, FRAMES, MOTION, RECORDED_FRAMES};
use gudsl_formats::arrays;
use gudsl_runtime::{
    camera::Intrinsics,
    sim::{simulate, Camera, Scene},
    ChainRun, Gpu, Image, Kernel, Pipeline, Shape,
};
use support::{bench_gpu, median_ms};

/// Runs of chapter 4 (25 when the frames are recorded: short runs drift most).
const RUNS: usize = 9;

impl Frames<'_> {
    /// Runs to take the median of.
    pub fn runs(self) -> usize {
        match self {
            Frames::Simulated => RUNS,
            Frames::Recorded(_) => 25,
        }
    }
}

/// Runs of chapter 6 (each simulates 3 cameras × 12 frames on the CPU).
const SCAN_RUNS: usize = 5;
/// A whole GU-DSL run of `frames` frames (plan, prepare, run) without reading its files.
fn gudsl_run(gpu: &Gpu, width: usize, height: usize, frames: usize, source: Frames, out: &Path) -> Duration {
    run_model(Some(gpu), &model(width, height, frames, source), None, out)
}

/// Chapter 6's sample at `width × height`, its pipeline named `Bench`.
fn scan_model(width: usize, height: usize) -> String {
    let text = std::fs::read_to_string(support::samples().join("pipelines/ch6_object_scan.gudsl")).unwrap();
    let text = text.replace("ComponentInstanceDiagram ObjectScanPipeline", "ComponentInstanceDiagram Bench");
    text.replace("frames = 6,", &format!("frames = 6, width = {width}, height = {height},"))
}

/// Frames 1–5 of chapter 6's scan on the API (the chains built and frame 0 run before), the PLY
/// written at the end.
fn rust_scan(gpu: &Gpu, width: usize, height: usize, out: &Path) -> Duration {
    let mut cameras = scan::cameras(gpu, width, height);
    assert_eq!(scan::accumulate(&mut cameras, 0..1).0.len(), 0, "frame 0 is learnt");
    let started = Instant::now();
    let (points, normals) = scan::accumulate(&mut cameras, 1..6);
    std::fs::create_dir_all(out).unwrap();
    let mut file = std::io::BufWriter::new(std::fs::File::create(out.join("cloud.ply")).unwrap());
    gudsl_formats::ply::write(&mut file, &points, &normals, "gudsl").unwrap();
    drop(file);
    started.elapsed()
}

/// The same frames on the runtime's API: the loop's time (the chain built before it), and the
/// part of it the simulator took. Recorded frames are read from the files in `recorded` before
/// the loop (as GU-DSL reads them before the first frame) and skip the black image as the model
/// does.
fn rust_run(gpu: &Gpu, width: usize, height: usize, recorded: Option<&Path>, out: &Path) -> (Duration, Duration) {
    let camera = Camera { intrinsics: Intrinsics::camcube_at(width, height), ..Camera::default() };
    let mut p = Pipeline::new();
    let shape = Shape { width, height, planes: 8 };
    let raw = match recorded {
        None => {
            let (raw, black) = (p.source("raw", shape), p.source("black", shape));
            p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0]
        }
        Some(_) => p.source("raw", shape),
    };
    // Detection and matching in one pass, as `ToF.MotionCompensation` runs them.
    let detect_match = Kernel::DetectMatch { theta: 0.01 * 65535.0, window: 5, restriction: None, subpixel: false };
    let flow = p.step(detect_match, &[raw]).unwrap()[0];
    let corrected = p.step(Kernel::CorrectRaw, &[raw, flow]).unwrap()[0];
    let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[corrected]).unwrap()[3];
    p.sink(distance).unwrap();
    let mut chain = ChainRun::new(Some(gpu), &p);
    std::fs::create_dir_all(out).unwrap();
    let frames = recorded.map(|dir| read_recorded(dir, width, height));
    let started = Instant::now();
    let mut simulating = Duration::ZERO;
    let count = if recorded.is_some() { RECORDED_FRAMES } else { FRAMES };
    for frame in 0..count {
        let distance = match recorded {
            None => {
                let simulation = Instant::now();
                let simulated = simulate(&Scene::sphere(), MOTION, &camera, frame);
                simulating += simulation.elapsed();
                chain.run(&[simulated.raw, simulated.black]).unwrap().remove(0)
            }
            Some(_) => chain.run(std::slice::from_ref(&frames.as_ref().unwrap()[frame])).unwrap().remove(0),
        };
        let path = out.join(format!("distance_{frame:04}.npy"));
        arrays::write(&path, &[height, width], &distance.data, arrays::Dtype::F32).unwrap();
    }
    (started.elapsed(), simulating)
}

/// The frames of the channel files in `dir`, planes `A0 B0 … A3 B3`.
fn read_recorded(dir: &Path, width: usize, height: usize) -> Vec<Image> {
    let folder = gudsl_files::Folder::open(dir).unwrap();
    let (a, b) =
        (arrays::read(&folder, &dir.join("a.npy")).unwrap(), arrays::read(&folder, &dir.join("b.npy")).unwrap());
    let plane = width * height;
    (0..RECORDED_FRAMES)
        .map(|f| {
            let mut data = Vec::with_capacity(8 * plane);
            for p in 0..4 {
                for channel in [&a, &b] {
                    data.extend_from_slice(&channel.values[(4 * f + p) * plane..(4 * f + p + 1) * plane]);
                }
            }
            Image { width, height, planes: 8, data }
        })
        .collect()
}

/// GU-DSL's time over Rust's, run by run: the median ratio and its quartiles, in per cent.
struct Overhead {
    median: f64,
    low: f64,
    high: f64,
}

impl Overhead {
    fn of(ours: &[Duration], theirs: &[Duration]) -> Overhead {
        let mut ratios: Vec<f64> =
            ours.iter().zip(theirs).map(|(o, t)| (o.as_secs_f64() / t.as_secs_f64() - 1.0) * 100.0).collect();
        ratios.sort_by(f64::total_cmp);
        let at = |q: usize| ratios[(ratios.len() - 1) * q / 4];
        Overhead { median: at(2), low: at(1), high: at(3) }
    }
}

impl std::fmt::Display for Overhead {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let text = format!("{:+.1} % ({:+.1} … {:+.1})", self.median, self.low, self.high);
        write!(f, "{text:>26}")
    }
}

/// Whether the row `label` is asked for (by the first argument that is not an option).
fn wanted(label: &str) -> bool {
    std::env::args().skip(1).find(|a| !a.starts_with("--")).is_none_or(|filter| label.contains(&filter))
}

fn main() {
    let gpu = bench_gpu(false);
    let scratch = std::env::temp_dir().join(format!("gudsl-bench-pipeline-{}", std::process::id()));
    println!(
        "chapter 4 (motion compensation, demodulation, .npy), ms per frame, median of {RUNS} runs of {FRAMES} frames (recorded: 25 of {RECORDED_FRAMES})"
    );
    println!(
        "{:>9}  {:>9}  {:>8}  {:>8}  {:>26}  {:>10}",
        "size", "frames", "GU-DSL", "Rust API", "overhead (quartiles)", "simulator"
    );
    for (width, height) in [(200, 200), (640, 480)] {
        let recorded_dir = scratch.join(format!("{width}x{height}-recorded"));
        record(width, height, &recorded_dir);
        for source in [Frames::Simulated, Frames::Recorded(&recorded_dir)] {
            let files = matches!(source, Frames::Recorded(_)).then_some(recorded_dir.as_path());
            let kind = if files.is_some() { "recorded" } else { "simulated" };
            if !wanted(&format!("chapter-4 {width}x{height} {kind}")) {
                continue;
            }
            let (mut ours, mut theirs, mut simulator) = (Vec::new(), Vec::new(), Vec::new());
            for run in 0..source.runs() {
                let dir = scratch.join(format!("{width}x{height}-{run}"));
                let one = gudsl_run(&gpu, width, height, 1, source, &dir.join("one"));
                let frames = source.count();
                let all = gudsl_run(&gpu, width, height, frames, source, &dir.join("all"));
                ours.push(all.saturating_sub(one) / (frames as u32 - 1));
                let (rust, simulating) = rust_run(&gpu, width, height, files, &dir.join("rust"));
                theirs.push(rust / frames as u32);
                simulator.push(simulating / frames as u32);
            }
            let overhead = Overhead::of(&ours, &theirs);
            let (ours, theirs, simulator) = (median_ms(ours), median_ms(theirs), median_ms(simulator));
            println!(
                "{:>9}  {:>9}  {ours:>8.2}  {theirs:>8.2}  {overhead}  {simulator:>10.2}",
                format!("{width}×{height}"),
                kind
            );
        }
    }
    println!("\nchapter 6 (three cameras: background, segmentation, clouds, ICP, accumulation, PLY), ms per frame over frames 1-5, median of {SCAN_RUNS}");
    println!("{:>9}  {:>8}  {:>8}  {:>26}", "size", "GU-DSL", "Rust API", "overhead (quartiles)");
    for (width, height) in [(200, 200), (640, 480)] {
        if !wanted(&format!("chapter-6 {width}x{height}")) {
            continue;
        }
        let text = scan_model(width, height);
        let (mut ours, mut theirs) = (Vec::new(), Vec::new());
        for run in 0..SCAN_RUNS {
            let dir = scratch.join(format!("scan-{width}x{height}-{run}"));
            let one = run_model(Some(&gpu), &text, Some(1), &dir.join("one"));
            let all = run_model(Some(&gpu), &text, Some(6), &dir.join("all"));
            ours.push(all.saturating_sub(one) / 5);
            theirs.push(rust_scan(&gpu, width, height, &dir.join("rust")) / 5);
        }
        let overhead = Overhead::of(&ours, &theirs);
        let (ours, theirs) = (median_ms(ours), median_ms(theirs));
        println!("{:>9}  {ours:>8.2}  {theirs:>8.2}  {overhead}", format!("{width}×{height}"));
    }
    let _ = std::fs::remove_dir_all(&scratch);
}
