//! Generated against hand-written WGSL, side by side in one run on the adapter wgpu finds
//! (lavapipe without a GPU): the samples' mean (Listing 15, kernelSize 10) and bilateral
//! (Listing 16, radius 5, σs 10, σr 50) filters at 512×512 and 1024×1024 against the runtime's
//! hand-written WGSL of the listings, and the two-stage findIndex reduction of Listings 34–39
//! over 1 048 576 shuffled elements (Main's search and one nothing matches) against the same two
//! stages written by hand, and beside them the runtime's own findIndex kernel (another algorithm). Times are the compute
//! pass by the GPU's timestamps where the adapter has them (else submit-to-done) of one
//! dispatch (both stages for findIndex), data already on the device, medians of runs that
//! alternate the two; lines are the WGSL's non-blank, non-comment lines (the
//! author's generated OpenCL had 23–70 % more than hand-written, 10.4.5).
//!
//! `cargo bench -p gudsl-host --bench generated_vs_handwritten [-- filters | findIndex]`

#[path = "../tests/support/mod.rs"]
mod support;

use std::time::Duration;

use gudsl_host::{Launcher, Number};
use gudsl_runtime::{listings, ChainRun, Image, Kernel, Pipeline, Shape};
use support::{
    bench_gpu, dispatch_listing, generated, launch_filter, listing, median_ms, random_bytes, FindIndex, Rgba,
};

fn code_lines(wgsl: &str) -> usize {
    wgsl.lines().map(str::trim).filter(|line| !line.is_empty() && !line.starts_with("//")).count()
}

/// Times `a` and `b` alternately, `runs` times each after one warm-up each.
fn side_by_side(runs: usize, mut a: impl FnMut() -> Duration, mut b: impl FnMut() -> Duration) -> (f64, f64) {
    a();
    b();
    let (mut times_a, mut times_b) = (Vec::new(), Vec::new());
    for _ in 0..runs {
        times_a.push(a());
        times_b.push(b());
    }
    (median_ms(times_a), median_ms(times_b))
}

fn row(kernel: &str, size: &str, (hand, generated): (f64, f64), (hand_lines, generated_lines): (usize, usize)) {
    println!(
        "| {kernel:<9} | {size:>9} | {hand:>10.2} | {generated:>10.2} | {:>+6.1} % | {hand_lines:>4} | {generated_lines:>4} ({:+.0} %) |",
        (generated / hand - 1.0) * 100.0,
        (generated_lines as f64 / hand_lines as f64 - 1.0) * 100.0
    );
}

fn main() {
    let gpu = bench_gpu(true);
    println!(
        "| kernel    |      size | hand-written ms | generated ms | generated vs hand | lines hand | lines generated |"
    );
    println!("|---|---|---|---|---|---|---|");
    let mean = generated("AdFilterMean");
    let bilateral = generated("AdFilterBilateral");
    let (mean_launcher, bilateral_launcher) =
        (Launcher::new(&gpu, &mean).unwrap(), Launcher::new(&gpu, &bilateral).unwrap());
    let (mean_listing, bilateral_listing) =
        (listing(&gpu, listings::MEAN_WGSL), listing(&gpu, listings::BILATERAL_WGSL));
    for side in [512usize, 1024].into_iter().filter(|_| selected("filters")) {
        let runs = if side > 600 { 7 } else { 11 };
        let image = Rgba::random(side, side, 5);
        let (input, output) = (image.upload(&gpu), image.empty(&gpu));
        let size = format!("{side}×{side}");
        let params = listings::mean_params(10, side as u32, side as u32);
        let times = side_by_side(
            runs,
            || dispatch_listing(&gpu, &mean_listing, &params, &input, &output),
            || launch_filter(&gpu, &mean_launcher, &input, &output, &[Number::Int(10)]),
        );
        row("mean", &size, times, (code_lines(listings::MEAN_WGSL), code_lines(&mean.wgsl)));
        let params = listings::bilateral_params(5.0, 10.0, 50.0, side as u32, side as u32);
        let values = [Number::Float(5.0), Number::Float(10.0), Number::Float(50.0)];
        let times = side_by_side(
            runs,
            || dispatch_listing(&gpu, &bilateral_listing, &params, &input, &output),
            || launch_filter(&gpu, &bilateral_launcher, &input, &output, &values),
        );
        row("bilateral", &size, times, (code_lines(listings::BILATERAL_WGSL), code_lines(&bilateral.wgsl)));
    }

    if selected("findIndex") {
        find_index_rows(&gpu);
    }
}

/// Whether the command line selects `part` (`-- filters` or `-- findIndex`; all without one).
fn selected(part: &str) -> bool {
    let wanted: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    wanted.is_empty() || wanted.iter().any(|w| w == part)
}

fn find_index_rows(gpu: &gudsl_runtime::Gpu) {
    // findIndex over Main's 1 048 576 shuffled elements, for the value at index 4711.
    let len = 1usize << 20;
    let mut elements: Vec<u32> = (0..len as u32).collect();
    let swaps = random_bytes(8 * len, 9);
    for i in 0..len {
        let j = u64::from_le_bytes(swaps[8 * i..8 * i + 8].try_into().unwrap()) as usize % len;
        elements.swap(i, j);
    }
    let value = elements[4711];
    let find_index = FindIndex::new(gpu);
    let input = FindIndex::upload(gpu, &elements);
    let expected = elements.iter().position(|&v| v >= value).unwrap();
    assert_eq!(find_index.run(gpu, &input, value).0 as usize, expected);
    let first = generated("AdFindMinimumIndexFirstStage").wgsl;
    let second = generated("AdFindMinimumIndexSecondStage").wgsl;
    let lines = (code_lines(listings::find_index::WGSL), code_lines(&first) + code_lines(&second));
    // Main's search, and one that nothing matches (every element scanned).
    for (label, value) in [("findIndex", value), ("no match", u32::MAX)] {
        let times = side_by_side(
            9,
            || find_index.run_handwritten(gpu, &input, value).1,
            || find_index.run(gpu, &input, value).1,
        );
        row(label, "1048576", times, lines);
    }
    // Beside them, the runtime's own findIndex (one work-item per element, `atomicMin`: another
    // algorithm, so not the yardstick).
    let mut pipeline = Pipeline::new();
    let source = pipeline.source("values", Shape { width: 1024, height: 1024, planes: 1 });
    let found = pipeline.step(Kernel::FindIndex { threshold: value as f32 }, &[source]).unwrap()[0];
    pipeline.sink(found).unwrap();
    let mut runtime = ChainRun::new(Some(gpu), &pipeline);
    let floats = [Image { width: 1024, height: 1024, planes: 1, data: elements.iter().map(|&v| v as f32).collect() }];
    assert_eq!(runtime.run(&floats).unwrap()[0].data[0] as usize, expected);
    let times = side_by_side(9, || runtime.time_steps(&floats).unwrap()[0], || find_index.run(gpu, &input, value).1);
    let hand_lines = code_lines(include_str!("../../runtime/src/kernels/find_index.wgsl"));
    row("atomicMin", "1048576", times, (hand_lines, lines.1));
}
