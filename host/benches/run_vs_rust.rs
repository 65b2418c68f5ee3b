//! The whole run of `Main` (Listings 30–33 as `samples/seed/main_full.gudsl`) by the host
//! interpreter against the same work written in Rust on the runtime's API, side by side in one
//! process on the adapter wgpu finds: load the bundled image, upload it, the bilateral and mean
//! filters (the same generated kernels, so the difference is the host side), fill and shuffle
//! 1 048 576 elements with the same generator, the two findIndex stages, read the results back
//! and write the four viewer images. Medians of runs that alternate the two; the shuffle loop on
//! its own as well (the dissertation's 10.4.5 anchor: its fully generated executables were
//! 12–87 % slower than hand-written ones), and against Rust that divides by the element count
//! as a variable, as the model does (`max_elements`), not as a constant it can turn into a mask.
//!
//! `cargo bench -p gudsl-host --bench run_vs_rust`

#[path = "../tests/support/mod.rs"]
mod support;

use std::{
    path::Path,
    time::{Duration, Instant},
};

use gudsl_host::{Arg, Launcher, Number, WorkRange};
use gudsl_runtime::{DeviceBuffer, DeviceImage, Gpu, TexelFormat};
use support::{bench_gpu, generated, main_sources, median_ms, prepared, samples};

const ELEMENTS: usize = 1_048_576;

/// The kernels of `Main`, compiled once (the interpreter compiles its own at each run).
struct Kernels {
    bilateral: Launcher,
    mean: Launcher,
    first: Launcher,
    second: Launcher,
}

/// `initRandomReduceBuffer`'s fill and shuffle of `len` elements with the same generator. Where
/// the caller passes a constant, the compiler turns `% len` into a mask (1 048 576 is a power
/// of two); `black_box(len)` keeps it a division, as `max_elements` is a variable in the model.
#[inline(always)]
fn fill_and_shuffle(len: usize) -> Vec<u32> {
    let mut elements: Vec<u32> = (0..len as u32).collect();
    let mut state =
        (std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).unwrap().as_secs() as u32).max(1);
    let mut rand = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        (state >> 1) as i32
    };
    for _ in 0..len {
        let a = (rand() % len as i32) as usize;
        let b = (rand() % len as i32) as usize;
        elements.swap(a, b);
    }
    elements
}

/// `Main`'s work in Rust: the total and the shuffle's time.
fn main_in_rust(gpu: &Gpu, kernels: &Kernels, out: &Path) -> (Duration, Duration) {
    let started = Instant::now();
    let input = image::open(samples().join("seed/tof_amplitude.png")).unwrap().to_rgba8();
    let (width, height) = input.dimensions();
    let size = [width, height, 1];
    let image = |label| DeviceImage::new(gpu, label, TexelFormat::Rgba8Uint, 2, size).unwrap();
    let (source, bilateral, mean) = (image("in"), image("bilateral"), image("mean"));
    source.write(gpu, input.as_raw()).unwrap();

    let shuffle_started = Instant::now();
    let elements = fill_and_shuffle(ELEMENTS);
    let shuffle = shuffle_started.elapsed();
    let bytes: Vec<u8> = elements.iter().flat_map(|v| v.to_le_bytes()).collect();
    let buffer = |label, len: usize| DeviceBuffer::new(gpu, label, 4 * len as u64).unwrap();
    let (all, minima, last) = (buffer("in", ELEMENTS), buffer("minima", ELEMENTS), buffer("last", 1));
    all.write(gpu, &bytes).unwrap();

    let range = WorkRange { dimensions: 2, global: [width, height, 1], local: None };
    let float = |v| Arg::Number(Number::Float(v));
    kernels
        .bilateral
        .launch(gpu, &[Arg::Image(&source), Arg::Image(&bilateral), float(5.0), float(10.0), float(50.0)], &range)
        .unwrap();
    let bilateral = bilateral.read(gpu).unwrap();
    kernels.mean.launch(gpu, &[Arg::Image(&source), Arg::Image(&mean), Arg::Number(Number::Int(10))], &range).unwrap();
    let mean = mean.read(gpu).unwrap();

    // Main's work sizes (estimateWorkSizes).
    let local =
        gpu.device.limits().max_compute_invocations_per_workgroup.min(gpu.device.limits().max_compute_workgroup_size_x);
    let groups = (ELEMENTS as u32 / local).min(local);
    let per_item = ELEMENTS as u32 / groups / local;
    let int = |v: u32| Arg::Number(Number::Int(v as i64));
    let value = Arg::Number(Number::UInt(elements[4711] as u64));
    let args = [
        Arg::Buffer(&all),
        Arg::Buffer(&minima),
        int(ELEMENTS as u32),
        int(local * 4),
        int(local),
        value,
        int(per_item),
    ];
    kernels
        .first
        .launch(gpu, &args, &WorkRange { dimensions: 2, global: [groups * local, 1, 1], local: Some([local, 1, 1]) })
        .unwrap();
    let args =
        [Arg::Buffer(&all), Arg::Buffer(&minima), Arg::Buffer(&last), int(groups), int(groups * 4), int(groups), value];
    kernels
        .second
        .launch(gpu, &args, &WorkRange { dimensions: 2, global: [groups, 1, 1], local: Some([groups, 1, 1]) })
        .unwrap();
    let index = i32::from_le_bytes(last.read(gpu).unwrap()[..4].try_into().unwrap());
    assert!(index >= 0);

    let rgb = |rgba: &[u8]| -> Vec<u8> { rgba.chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect() };
    for (i, pixels) in [input.as_raw(), &bilateral, &mean, input.as_raw()].into_iter().enumerate() {
        let path = out.join(format!("viewer1-image{i}.png"));
        image::save_buffer(path, &rgb(pixels), width, height, image::ExtendedColorType::Rgb8).unwrap();
    }
    (started.elapsed(), shuffle)
}

fn main() {
    let gpu = bench_gpu(false);
    let main = prepared(&main_sources(|text| text), "Main").unwrap_or_else(|e| panic!("{e:?}"));
    let kernels = Kernels {
        bilateral: Launcher::new(&gpu, &generated("AdFilterBilateral")).unwrap(),
        mean: Launcher::new(&gpu, &generated("AdFilterMean")).unwrap(),
        first: Launcher::new(&gpu, &generated("AdFindMinimumIndexFirstStage")).unwrap(),
        second: Launcher::new(&gpu, &generated("AdFindMinimumIndexSecondStage")).unwrap(),
    };
    let out = std::env::temp_dir().join(format!("gudsl-bench-run-{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let runs = 5;
    let (mut run_total, mut run_shuffle, mut rust_total, mut rust_shuffle) = (vec![], vec![], vec![], vec![]);
    let mut rust_divided = vec![];
    for i in 0..=runs {
        let report = main.run(&gpu, &mut support::output(&out), &mut ());
        assert!(report.outcome.is_ok(), "{:?}", report.outcome);
        let (total, shuffle) = main_in_rust(&gpu, &kernels, &out);
        let divided = Instant::now();
        std::hint::black_box(fill_and_shuffle(std::hint::black_box(ELEMENTS)));
        let divided = divided.elapsed();
        if i == 0 {
            continue; // warm-up
        }
        run_total.push(report.total);
        run_shuffle.push(report.nodes.iter().find(|n| n.name == "initRandomReduceBuffer").unwrap().wall);
        rust_total.push(total);
        rust_shuffle.push(shuffle);
        rust_divided.push(divided);
    }
    let _ = std::fs::remove_dir_all(&out);
    let row = |what: &str, run: f64, rust: f64| {
        println!("| {what:<34} | {run:>12.1} | {rust:>8.1} | {:>+8.0} % |", (run / rust - 1.0) * 100.0)
    };
    println!("| work (medians of {runs} alternating runs) | gudsl run ms | Rust ms | run vs Rust |");
    println!("|------------------------------------|-------------:|--------:|------------:|");
    row("whole Main", median_ms(run_total), median_ms(rust_total));
    let run_shuffle = median_ms(run_shuffle);
    row("fill + shuffle of 1 048 576 elements", run_shuffle, median_ms(rust_shuffle));
    row("  the same, Rust dividing by a variable", run_shuffle, median_ms(rust_divided));
}
