//! The kernels generated from the samples' device diagrams run on the GPU (lavapipe in CI) and
//! compute what the hand-written code computes: Listing 15's mean filter and Listing 16's
//! bilateral filter against the runtime's hand-written WGSL of the listings and their CPU
//! references, on a random image and on a simulated ToF amplitude image, and against the
//! runtime's own mean and bilateral kernels (f32 planes) in the interior; the findIndex reduction
//! against the runtime's findIndex kernel and the CPU, including no match.

use gudsl_codegen::Kernel;
use gudsl_host::{Arg, Launcher, Number, WorkRange};
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    hir::Semantics,
    library,
};
use gudsl_runtime::{
    listings,
    sim::{simulate, Camera, Motion, Scene},
    DeviceBuffer, DeviceImage, Gpu, GpuPipeline, Image, Pipeline, Program, Resource, Shape, TexelFormat,
};

const SAMPLES: [&str; 4] = [
    "framework/framework.gudsl",
    "seed/listing15_mean_filter.gudsl",
    "seed/listing16_bilateral_filter.gudsl",
    "gpu/find_index.gudsl",
];

/// The kernel generated from the diagram `name` of the samples.
fn generated(name: &str) -> Kernel {
    let db = RootDatabase::default();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
    let mut files = library::library_files(&db);
    for sample in SAMPLES {
        let path = root.join(sample);
        let text = std::fs::read_to_string(&path).unwrap();
        files.push(SourceFile::new(&db, path.display().to_string(), text));
    }
    let workspace = Workspace::new(&db, files);
    let sema = Semantics::new(&db, workspace);
    let diagram = gudsl_codegen::device_diagrams(&sema).into_iter().find(|d| d.fqn == name).expect(name);
    gudsl_codegen::generate(&sema, diagram).unwrap_or_else(|e| panic!("{name}: {e:?}"))
}

/// Deterministic bytes (xorshift).
fn random_bytes(len: usize, seed: u64) -> Vec<u8> {
    let mut state = seed | 1;
    (0..len)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 56) as u8
        })
        .collect()
}

/// An RGBA8 image.
struct Rgba {
    width: usize,
    height: usize,
    texels: Vec<u8>,
}

impl Rgba {
    fn random(width: usize, height: usize, seed: u64) -> Rgba {
        let mut texels = random_bytes(4 * width * height, seed);
        texels.iter_mut().skip(3).step_by(4).for_each(|alpha| *alpha = 255);
        Rgba { width, height, texels }
    }

    /// The amplitude of a simulated ToF frame (the sphere scene), as grey levels.
    fn amplitude() -> Rgba {
        let camera = Camera { supersampling: 1, ..Camera::default() };
        let frame = simulate(&Scene::sphere(), Motion::Still, &camera, 0);
        let raw = gudsl_runtime::kernels::tof::subtract_black(&frame.raw, &frame.black);
        let [_, amplitude, _, _] = gudsl_runtime::kernels::tof::demodulate(&raw, camera.modulation_hz);
        let brightest = amplitude.data.iter().copied().fold(0.0f32, f32::max);
        let texels = amplitude.data.iter().flat_map(|&a| {
            let grey = (a / brightest * 255.0).round() as u8;
            [grey, grey, grey, 255]
        });
        Rgba { width: amplitude.width, height: amplitude.height, texels: texels.collect() }
    }

    /// Its first channel as an f32 plane.
    fn red_plane(&self) -> Image {
        let data = self.texels.iter().step_by(4).map(|&v| v as f32).collect();
        Image::from_plane(self.width, self.height, data)
    }

    fn upload(&self, gpu: &Gpu) -> DeviceImage {
        let image = self.empty(gpu);
        image.write(gpu, &self.texels).unwrap();
        image
    }

    fn empty(&self, gpu: &Gpu) -> DeviceImage {
        let size = [self.width as u32, self.height as u32, 1];
        DeviceImage::new(gpu, "image", TexelFormat::Rgba8Uint, 2, size).unwrap()
    }
}

/// Runs a generated image filter (input image, output image, then `values`) on `image`.
fn run_generated(gpu: &Gpu, kernel: &Kernel, image: &Rgba, values: &[Number]) -> Vec<u8> {
    let launcher = Launcher::new(gpu, kernel).unwrap();
    let (input, output) = (image.upload(gpu), image.empty(gpu));
    let mut args = vec![Arg::Image(&input), Arg::Image(&output)];
    args.extend(values.iter().map(|&v| Arg::Number(v)));
    args.extend(std::iter::repeat_n(Arg::None, kernel.params.len() - args.len()));
    let range = WorkRange::planar(image.width as u32, image.height as u32, None);
    launcher.launch(gpu, &args, &range).unwrap();
    output.read(gpu).unwrap()
}

/// Runs a hand-written listing filter on `image`.
fn run_handwritten(gpu: &Gpu, source: &str, params: &[u8], image: &Rgba) -> Vec<u8> {
    let program = Program::new(gpu, "listing", source, listings::ENTRY_POINT, &listings::BINDINGS).unwrap();
    let (input, output) = (image.upload(gpu), image.empty(gpu));
    let resources = [(0, Resource::Uniform(params)), (1, Resource::Image(&input)), (2, Resource::Image(&output))];
    program.dispatch(gpu, &[], &resources, listings::workgroups(image.width as u32, image.height as u32)).unwrap();
    output.read(gpu).unwrap()
}

/// Runs one of the runtime's own kernels on an f32 plane.
fn run_runtime(gpu: &Gpu, kernel: gudsl_runtime::Kernel, plane: &Image) -> Image {
    let mut pipeline = Pipeline::new();
    let source = pipeline.source("in", Shape { width: plane.width, height: plane.height, planes: 1 });
    let out = pipeline.step(kernel, &[source]).unwrap()[0];
    pipeline.sink(out).unwrap();
    GpuPipeline::new(gpu, &pipeline).run(std::slice::from_ref(plane)).unwrap().remove(0)
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
    for image in [Rgba::random(203, 97, 11), Rgba::amplitude()] {
        for kernel_size in [3, 10] {
            let ours = run_generated(&gpu, &kernel, &image, &[Number::Int(kernel_size)]);
            let params = listings::mean_params(kernel_size as i32, image.width as u32, image.height as u32);
            let handwritten = run_handwritten(&gpu, listings::MEAN_WGSL, &params, &image);
            assert_eq!(difference(&ours, &handwritten), (0, 0), "generated vs hand-written, size {kernel_size}");
            let cpu = listings::mean(&image.texels, image.width, image.height, kernel_size as i32);
            assert_eq!(difference(&ours, &cpu), (0, 0), "generated vs CPU, size {kernel_size}");
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

/// findIndex as Main's calcRange nodes run it (Listing 32): work sizes from the device's
/// largest work-group, stage 1 over the elements, stage 2 over the groups' results.
fn find_index_generated(gpu: &Gpu, first: &Launcher, second: &Launcher, elements: &[u32], value: u32) -> i32 {
    let n = elements.len() as u32;
    let local = gpu.device.limits().max_compute_invocations_per_workgroup.min(256);
    let needed = n.next_power_of_two();
    let groups = (needed / local).clamp(1, local);
    let per_item = (needed / groups / local).max(1);
    let bytes = |values: &[u32]| values.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>();
    let input = DeviceBuffer::new(gpu, "elements", 4 * n as u64).unwrap();
    input.write(gpu, &bytes(elements)).unwrap();
    let minima = DeviceBuffer::new(gpu, "minima", 4 * groups as u64).unwrap();
    let last = DeviceBuffer::new(gpu, "last", 4).unwrap();
    let int = |v: u32| Arg::Number(Number::Int(v as i64));
    let args = [
        Arg::Buffer(&input),
        Arg::Buffer(&minima),
        int(n),
        int(local * 4),
        int(local),
        Arg::Number(Number::UInt(value as u64)),
        int(per_item),
    ];
    first.launch(gpu, &args, &WorkRange::linear(groups * local, Some(local))).unwrap();
    let args = [
        Arg::Buffer(&input),
        Arg::Buffer(&minima),
        Arg::Buffer(&last),
        int(groups),
        int(groups * 4),
        int(groups),
        Arg::Number(Number::UInt(value as u64)),
    ];
    second.launch(gpu, &args, &WorkRange::linear(groups, Some(groups))).unwrap();
    i32::from_le_bytes(last.read(gpu).unwrap()[..4].try_into().unwrap())
}

#[test]
fn the_generated_find_index_equals_the_runtimes_kernel_and_the_cpu() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let first = Launcher::new(&gpu, &generated("AdFindMinimumIndexFirstStage")).unwrap();
    let second = Launcher::new(&gpu, &generated("AdFindMinimumIndexSecondStage")).unwrap();
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
        for value in [0, 200, 255, 4711, len - 1, len + 1, u32::MAX] {
            let cpu = elements.iter().position(|&v| v >= value);
            let ours = find_index_generated(&gpu, &first, &second, elements, value);
            assert_eq!(ours, cpu.map_or(-1, |i| i as i32), "value {value} in {} elements", elements.len());
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
