//! The kernels generated from the samples' device diagrams run on the GPU (lavapipe in CI) and
//! compute what the hand-written code computes: Listing 15's mean filter and Listing 16's
//! bilateral filter against the runtime's hand-written WGSL of the listings and their CPU
//! references, on a random image and on a simulated ToF amplitude image (the mean against its
//! exact value: a device that divides in less than IEEE precision may round an exact mean
//! down, as the listing's `float` arithmetic allows; on lavapipe all agree value for value), and against the
//! runtime's own mean and bilateral kernels (f32 planes) in the interior; the findIndex reduction
//! against its hand-written WGSL, the runtime's findIndex kernel and the CPU, including no match,
//! and both its stages against the CPU over random arrays.

mod support;

use gudsl_host::{Arg, Launcher, Number, WorkRange};
use gudsl_runtime::{listings, ChainRun, DeviceBuffer, DeviceImage, Gpu, Image, Pipeline, Program, Shape, TexelFormat};
use support::{check_mean, generated, random_bytes, run_generated, run_handwritten, FindIndex, Rgba};

/// Runs one of the runtime's own kernels on an f32 plane.
fn run_runtime(gpu: &Gpu, kernel: gudsl_runtime::Kernel, plane: &Image) -> Image {
    let mut pipeline = Pipeline::new();
    let source = pipeline.source("in", Shape { width: plane.width, height: plane.height, planes: 1 });
    let out = pipeline.step(kernel, &[source]).unwrap()[0];
    pipeline.sink(out).unwrap();
    ChainRun::new(Some(gpu), &pipeline).run(std::slice::from_ref(plane)).unwrap().remove(0)
}

/// How many channel values differ, and by how much at most.
fn difference(a: &[u8], b: &[u8]) -> (usize, u8) {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).filter(|(x, y)| x != y).fold((0, 0), |(n, worst), (x, y)| (n + 1, worst.max(x.abs_diff(*y))))
}

/// The interior of a grey filtered image (first channel) against a runtime kernel's f32 result:
/// the listing truncates, so each value lies in (f − 1, f] up to float rounding.
fn assert_truncates(filtered: &Rgba, runtime: &Image, r: usize, what: &str) {
    for y in r..filtered.height - r {
        for x in r..filtered.width - r {
            let value = filtered.texels[4 * (y * filtered.width + x)] as f32;
            let reference = runtime.data[y * runtime.width + x];
            assert!(
                value - reference <= 0.01 && reference - value < 1.01,
                "{what}: pixel ({x}, {y}) is {value}, the runtime's kernel gives {reference}"
            );
        }
    }
}

#[test]
fn the_generated_mean_filter_equals_the_hand_written_one_and_the_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let kernel = generated("AdFilterMean");
    // Odd sizes: partial work-groups at the right and bottom edges.
    // Where the device divides exactly (lavapipe, as in CI), all three agree value for value.
    let exact_division = gpu.describe().contains("llvmpipe");
    for image in [Rgba::random(203, 97, 11), Rgba::amplitude()] {
        for kernel_size in [3, 10] {
            let ours = run_generated(&gpu, &kernel, &image, &[Number::Int(kernel_size)]);
            let params = listings::mean_params(kernel_size as i32, image.width as u32, image.height as u32);
            let handwritten = run_handwritten(&gpu, listings::MEAN_WGSL, &params, &image);
            let cpu = listings::mean(&image.texels, image.width, image.height, kernel_size as i32);
            for (what, filtered) in [("generated", &ours), ("hand-written", &handwritten), ("CPU", &cpu)] {
                let checked = check_mean(filtered, 4, &image, kernel_size as usize);
                let rounded_down = checked.unwrap_or_else(|e| panic!("{what}, size {kernel_size}: {e}"));
                eprintln!("{what}, size {kernel_size}: {rounded_down} exact means rounded down");
            }
            if exact_division {
                assert_eq!(difference(&ours, &handwritten), (0, 0), "generated vs hand-written, size {kernel_size}");
                assert_eq!(difference(&ours, &cpu), (0, 0), "generated vs CPU, size {kernel_size}");
            }
        }
    }
    // Grey levels against the runtime's f32 mean in the interior.
    let grey = Rgba::amplitude();
    let ours = Rgba { texels: run_generated(&gpu, &kernel, &grey, &[Number::Int(5)]), ..grey };
    let runtime = run_runtime(&gpu, gudsl_runtime::Kernel::Mean { radius: 2 }, &Rgba::amplitude().red_plane());
    assert_truncates(&ours, &runtime, 2, "mean");
}

#[test]
fn the_generated_bilateral_filter_matches_the_hand_written_one_and_the_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let kernel = generated("AdFilterBilateral");
    let (radius, sigma_spatial, sigma_range) = (5.0, 10.0, 50.0);
    let values = [Number::Float(radius), Number::Float(sigma_spatial), Number::Float(sigma_range)];
    for image in [Rgba::random(203, 97, 12), Rgba::amplitude()] {
        let ours = run_generated(&gpu, &kernel, &image, &values);
        let params = listings::bilateral_params(
            radius as f32,
            sigma_spatial as f32,
            sigma_range as f32,
            image.width as u32,
            image.height as u32,
        );
        let handwritten = run_handwritten(&gpu, listings::BILATERAL_WGSL, &params, &image);
        let cpu = listings::bilateral(
            &image.texels,
            image.width,
            image.height,
            radius as f32,
            sigma_spatial as f32,
            sigma_range as f32,
        );
        // A weighted mean in floats, truncated: rounding may move a value across an integer.
        for (other, what) in [(&handwritten, "hand-written"), (&cpu, "CPU")] {
            let (count, worst) = difference(&ours, other);
            eprintln!(
                "bilateral {}×{}: generated vs {what}: {count} values differ, by at most {worst}",
                image.width, image.height
            );
            assert!(worst <= 1, "generated vs {what}: off by {worst}");
            assert!(count * 1000 <= ours.len(), "generated vs {what}: {count} of {} values differ", ours.len());
        }
    }
    // Grey levels: |ΔRGB|² is 3Δ², so the runtime's one-plane filter takes σr/√3.
    let grey = Rgba::amplitude();
    let ours = Rgba { texels: run_generated(&gpu, &kernel, &grey, &values), ..Rgba::amplitude() };
    let sigma_range = (sigma_range / 3f64.sqrt()) as f32;
    let runtime = run_runtime(
        &gpu,
        gudsl_runtime::Kernel::Bilateral { radius: 5, sigma_space: sigma_spatial as f32, sigma_range },
        &grey.red_plane(),
    );
    assert_truncates(&ours, &runtime, 5, "bilateral");
}

#[test]
fn the_generated_find_index_equals_the_hand_written_one_the_runtimes_kernel_and_the_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let find_index = FindIndex::new(&gpu);
    // A shuffled permutation as Main builds it, and random values with repeats; sizes that are
    // and are not powers of two.
    let mut cases = Vec::new();
    for (len, seed) in [(1usize << 16, 3u64), (100_003, 4)] {
        let mut permutation: Vec<u32> = (0..len as u32).collect();
        let swaps = random_bytes(8 * len, seed);
        for i in 0..len {
            let j = u64::from_le_bytes(swaps[8 * i..8 * i + 8].try_into().unwrap()) as usize % len;
            permutation.swap(i, j);
        }
        cases.push(permutation);
        cases.push(random_bytes(len, seed + 10).into_iter().map(u32::from).collect());
    }
    for elements in &cases {
        let as_floats = Image::from_plane(elements.len(), 1, elements.iter().map(|&v| v as f32).collect());
        let len = elements.len() as u32;
        let input = FindIndex::upload(&gpu, elements);
        for value in [0, 200, 255, 4711, len - 1, len + 1, u32::MAX] {
            let cpu = elements.iter().position(|&v| v >= value);
            let (ours, _) = find_index.run(&gpu, &input, value);
            assert_eq!(ours, cpu.map_or(-1, |i| i as i32), "value {value} in {} elements", elements.len());
            let (hand, _) = find_index.run_handwritten(&gpu, &input, value);
            assert_eq!(hand, ours, "hand-written, value {value} in {} elements", elements.len());
            if value < 1 << 24 {
                // The runtime's kernel works on floats: exact for these values. It answers the
                // length where nothing matches.
                let runtime =
                    run_runtime(&gpu, gudsl_runtime::Kernel::FindIndex { threshold: value as f32 }, &as_floats);
                assert_eq!(runtime.data[0] as usize, cpu.unwrap_or(elements.len()), "runtime kernel, value {value}");
            }
        }
    }
}

/// Both stages over random arrays (values from a narrow or a wide range, so that hits are
/// rare, common or absent), random search values and work-groups of 1 to 256: stage 1 leaves
/// each group the first index of its slice whose element is >= the value, stage 2 the first of
/// all (-1 for none), as the CPU finds them.
#[test]
fn both_find_index_stages_find_what_the_cpu_finds_for_random_arrays() {
    use proptest::prelude::*;
    let Some(gpu) = Gpu::for_tests() else { return };
    let find_index = FindIndex::new(&gpu);
    let limit = gpu.device.limits().max_compute_invocations_per_workgroup.min(256);
    let arrays = (1u32..=1000, 1usize..3000).prop_flat_map(|(range, len)| prop::collection::vec(0..range, len));
    let case = (arrays, any::<u32>(), 0u32..=8).prop_map(|(elements, pick, local)| {
        // The search value: an element, one above the largest, or any number.
        let value = match pick % 3 {
            0 => elements[pick as usize % elements.len()],
            1 => elements.iter().max().unwrap() + 1,
            _ => pick % 1200,
        };
        (elements, value, 1u32 << local)
    });
    let config = ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() };
    let mut runner = proptest::test_runner::TestRunner::new(config);
    runner
        .run(&case, |(elements, value, local)| {
            let input = FindIndex::upload_for(&gpu, &elements, local.min(limit));
            let (found, _) = find_index.run(&gpu, &input, value);
            let first = |slice: &[u32], offset: usize| {
                slice.iter().position(|&v| v >= value).map_or(-1, |i| (offset + i) as i32)
            };
            let (candidates, per_group) = find_index.group_candidates(&gpu, &input);
            for (group, candidate) in candidates.iter().enumerate() {
                let start = (group * per_group).min(elements.len());
                let end = (start + per_group).min(elements.len());
                prop_assert_eq!(*candidate, first(&elements[start..end], start), "stage 1, group {}", group);
            }
            prop_assert_eq!(found, first(&elements, 0), "stage 2");
            prop_assert_eq!(find_index.run_handwritten(&gpu, &input, value).0, found, "hand-written");
            Ok(())
        })
        .unwrap();
}

#[test]
fn launches_that_cannot_run_are_errors_that_say_why() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let first = Launcher::new(&gpu, &generated("AdFindMinimumIndexFirstStage")).unwrap();
    let buffer = DeviceBuffer::new(&gpu, "elements", 4 * 1024).unwrap();
    let image = Rgba::random(8, 8, 1).upload(&gpu);
    let minima = DeviceBuffer::new(&gpu, "minima", 4).unwrap();
    fn with<'a>(buffer: &'a DeviceBuffer, minima: Arg<'a>, shared: i64) -> Vec<Arg<'a>> {
        let int = |v: i64| Arg::Number(Number::Int(v));
        vec![Arg::Buffer(buffer), minima, int(1024), int(shared), int(64), Arg::Number(Number::UInt(5)), int(16)]
    }
    let args = |minima, shared| with(&buffer, minima, shared);
    let error = |args: &[Arg<'_>], range: WorkRange| first.launch(&gpu, args, &range).unwrap_err().to_string();
    let range = WorkRange::linear(64, Some(64));

    let message = error(&args(Arg::Buffer(&buffer), 256)[..3], range);
    assert!(message.contains("3 argument(s) given, it takes 7"), "{message}");
    let message = error(&args(Arg::Image(&image), 256), range);
    assert!(message.contains("argument `minimumIndices`") && message.contains("does not fit"), "{message}");
    let message = error(&args(Arg::Buffer(&minima), 6), range);
    assert!(message.contains("argument `scratch`") && message.contains("multiple of 4 bytes"), "{message}");
    let message = error(&args(Arg::Buffer(&minima), 256), WorkRange::linear(100, Some(64)));
    assert!(message.contains("must be a multiple of the local size"), "{message}");
    let message = error(&args(Arg::Buffer(&minima), 256), WorkRange::linear(1 << 20, Some(1 << 20)));
    assert!(message.contains("this device runs at most"), "{message}");
    let message = error(&args(Arg::Buffer(&minima), 256), WorkRange::linear(0, None));
    assert!(message.contains("empty global size"), "{message}");
    let message = error(&args(Arg::Buffer(&buffer), 256), range);
    assert!(
        message
            .contains("binding 2 of kernel `AdFindMinimumIndexFirstStage`: it is given the same memory as binding 1"),
        "{message}"
    );
    // The launch that fits runs.
    first.launch(&gpu, &args(Arg::Buffer(&minima), 256), &range).unwrap();

    // Device-side refusals are errors too, not panics.
    let broken =
        Program::new(&gpu, "broken", "@compute @workgroup_size(1) fn main() { let x: u32 = 1.5; }", "main", &[]);
    assert!(matches!(broken, Err(gudsl_runtime::ProgramError::Compile { .. })), "{:?}", broken.err());
    let message = image.write(&gpu, &[0; 5]).unwrap_err().to_string();
    assert_eq!(message, "the image holds 256 bytes, 5 given");
    let texture = DeviceImage::new(&gpu, "empty", TexelFormat::Rgba8Uint, 2, [0, 4, 1]).unwrap_err().to_string();
    assert!(texture.contains("at least one texel"), "{texture}");
}
