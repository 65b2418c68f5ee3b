//! Chapter 4's chain on recorded frames three ways, side by side in one run, at 200×200 and
//! 640×480: GU-DSL on the CPU reference (`gudsl run --cpu`: the runtime's kernels on every
//! core), GU-DSL on the adapter wgpu finds (lavapipe here), and the numpy script a researcher
//! would write from the dissertation's equations (`cpu_vs_numpy.py`: detection, block matching
//! vectorised over the image, correction, demodulation). Each reads the same 25 recorded frames
//! (`a.npy`, `b.npy`: a camera moving 1 cm per phase image), computes the distance and writes
//! it as `.npy` each frame; MWS 5 and 7, θ 1 %, no direction restriction, whole pixels (what the
//! numpy script does). The time per frame is the steady state: GU-DSL's (T(25) − T(1)) / 24 of
//! whole runs without reading files, numpy's over frames 1–24 of its loop; medians of `RUNS`
//! runs. The distances agree: the largest difference between numpy's and the CPU's is printed.
//!
//! `cargo bench -p gudsl-host --bench cpu_vs_numpy` (numpy must be importable by `python3`;
//! without it that column says so).

#[path = "common/chapter4.rs"]
mod chapter4;
#[path = "../tests/support/mod.rs"]
mod support;

use std::{path::Path, process::Command, time::Duration};

use chapter4::{record, run_model, Frames, RECORDED_FRAMES};
use gudsl_formats::arrays;
use gudsl_runtime::Gpu;
use support::{bench_gpu, median_ms};

const RUNS: usize = 5;

/// The chain on the recorded frames of `dir`, MWS `window`.
fn model(dir: &Path, window: u32, frames: usize) -> String {
    // The recorded chain of `pipeline_vs_rust` (its size is the recording's).
    chapter4::model(0, 0, frames, Frames::Recorded(dir)).replace("windowSize = 5", &format!("windowSize = {window}"))
}

/// GU-DSL's steady-state time per frame on `gpu` (`None`: the CPU reference).
fn gudsl(gpu: Option<&Gpu>, dir: &Path, window: u32, out: &Path) -> Duration {
    let one = run_model(gpu, &model(dir, window, 1), None, &out.join("one"));
    let all = run_model(gpu, &model(dir, window, RECORDED_FRAMES), None, &out.join("all"));
    all.saturating_sub(one) / (RECORDED_FRAMES as u32 - 1)
}

/// numpy's steady-state time per frame, or why there is none.
fn numpy(dir: &Path, window: u32) -> Result<Duration, String> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/cpu_vs_numpy.py");
    let theta = (0.01 * 65535.0f32).to_string();
    let out = Command::new("python3")
        .arg(script)
        .arg(dir)
        .args([RECORDED_FRAMES.to_string(), window.to_string(), theta])
        .output()
        .map_err(|e| format!("no python3: {e}"))?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let why = stderr.lines().last().unwrap_or("failed").to_string();
        return Err(if why.contains("numpy") { "numpy missing (pip install numpy)".into() } else { why });
    }
    let ms: f64 = String::from_utf8_lossy(&out.stdout).trim().parse().map_err(|e| format!("{e}"))?;
    Ok(Duration::from_secs_f64(ms / 1000.0))
}

/// The largest difference between numpy's distances and the CPU reference's, in metres.
fn largest_difference(dir: &Path, ours: &Path) -> f32 {
    let folder = gudsl_files::Folder::open(&std::env::temp_dir()).unwrap();
    (0..RECORDED_FRAMES)
        .map(|frame| {
            let name = format!("distance_{frame:04}.npy");
            let theirs = arrays::read(&folder, &dir.join("numpy").join(&name)).unwrap().values;
            let ours = arrays::read(&folder, &ours.join("Depth").join(&name)).unwrap().values;
            theirs.iter().zip(&ours).map(|(a, b)| (a - b).abs()).fold(0.0, f32::max)
        })
        .fold(0.0, f32::max)
}

fn main() {
    let gpu = bench_gpu(false);
    let scratch = std::env::temp_dir().join(format!("gudsl-bench-cpu-numpy-{}", std::process::id()));
    println!(
        "chapter 4 on {RECORDED_FRAMES} recorded frames (motion compensation, demodulation, .npy), ms per frame, median of {RUNS} runs; {} cores; GPU: {}",
        std::thread::available_parallelism().map_or(1, |n| n.get()),
        gpu.describe()
    );
    println!(
        "{:>9}  {:>4}  {:>10}  {:>10}  {:>10}  {:>14}  {:>12}",
        "size", "MWS", "--cpu", "GPU", "numpy", "numpy / --cpu", "max |Δ| m"
    );
    for (width, height) in [(200, 200), (640, 480)] {
        let dir = scratch.join(format!("{width}x{height}"));
        record(width, height, &dir);
        for window in [5, 7] {
            let (mut cpu, mut device, mut reference, mut why) = (Vec::new(), Vec::new(), Vec::new(), None);
            for run in 0..RUNS {
                let out = scratch.join(format!("{width}x{height}-{window}-{run}"));
                cpu.push(gudsl(None, &dir, window, &out.join("cpu")));
                device.push(gudsl(Some(&gpu), &dir, window, &out.join("gpu")));
                match numpy(&dir, window) {
                    Ok(time) => reference.push(time),
                    Err(error) => why = Some(error),
                }
            }
            let difference = match why {
                None => format!(
                    "{:.1e}",
                    largest_difference(&dir, &scratch.join(format!("{width}x{height}-{window}-0/cpu/all")))
                ),
                Some(_) => "-".to_string(),
            };
            let (cpu, device) = (median_ms(cpu), median_ms(device));
            let (numpy, ratio) = match &why {
                None => {
                    let numpy = median_ms(reference);
                    (format!("{numpy:.2}"), format!("{:.1}×", numpy / cpu))
                }
                Some(why) => (why.clone(), "-".to_string()),
            };
            println!(
                "{:>9}  {window:>4}  {cpu:>10.2}  {device:>10.2}  {numpy:>10}  {ratio:>14}  {difference:>12}",
                format!("{width}x{height}")
            );
        }
    }
    let _ = std::fs::remove_dir_all(scratch);
}
