//! What the generated-kernel tests and the benchmark share: the samples' kernels, RGBA8 test
//! images (random, and a simulated ToF amplitude image), running a generated or a hand-written
//! image filter, and a `compute` kernel writing one `int` per work-item (functions' tests).

#![allow(dead_code)] // each user takes what it needs
use std::time::Duration;

use gudsl_codegen::Kernel;
use gudsl_host::{
    run::{prepare, PreparedRun, RunError},
    Arg, Launcher, Number, WorkRange,
};
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    hir::{Definition, Semantics},
    library,
};
use gudsl_runtime::{
    listings,
    sim::{simulate, Camera, Motion, Scene},
    DeviceBuffer, DeviceImage, Gpu, Image, Program, Resource, TexelFormat,
};

/// The samples the kernels come from.
const SAMPLES: [&str; 4] = [
    "framework/framework.gudsl",
    "seed/listing15_mean_filter.gudsl",
    "seed/listing16_bilateral_filter.gudsl",
    "seed/listing34_39_find_index.gudsl",
];

/// Kernel `compute(global ref int out)` owned by the OpenCL class `owner`: one action that
/// declares `var int id = get_global_id(0);` and then does `body`.
pub fn compute_kernel(owner: &str, body: &str) -> String {
    format!(
        "ActivityDiagram compute(global ref int out)
{{
    import OpenCL.GPU.*;

    swimlane Device, owner {owner}
    {{
        start S {{ => work; }}
        action work
        {{
            var int id = get_global_id(0);
{body}
            => f;
        }}
        final f;
    }}
}}
"
    )
}

/// What a kernel like [`compute_kernel`]'s writes into `out` over `count` work-items on the
/// test device; `None` without one.
pub fn run_compute_kernel(kernel: &Kernel, count: u32) -> Option<Vec<i32>> {
    let gpu = Gpu::for_tests()?;
    let out = DeviceBuffer::new(&gpu, "out", 4 * count as u64).unwrap();
    let launcher = Launcher::new(&gpu, kernel).unwrap();
    launcher.launch(&gpu, &[Arg::Buffer(&out)], &WorkRange::linear(count, None)).unwrap();
    Some(out.read(&gpu).unwrap().chunks(4).map(|b| i32::from_le_bytes(b.try_into().unwrap())).collect())
}

/// The samples' folder: the repository's where it was built, or `$GUDSL_REPO/samples` (a
/// benchmark built elsewhere: `scripts/bench-gpu --prebuilt`).
pub fn samples() -> std::path::PathBuf {
    match std::env::var_os("GUDSL_REPO") {
        Some(repo) => std::path::Path::new(&repo).join("samples"),
        None => std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples"),
    }
}

/// The kernels' samples and `Main` (`seed/main_full.gudsl`), as `(path, text)` with `edit`
/// applied to each text.
pub fn main_sources(edit: impl Fn(String) -> String) -> Vec<(String, String)> {
    SAMPLES
        .iter()
        .chain(&["seed/main_full.gudsl"])
        .map(|sample| {
            let path = samples().join(sample);
            (path.display().to_string(), edit(std::fs::read_to_string(&path).unwrap()))
        })
        .collect()
}

/// The diagram `name` of these `(path, text)` files in one workspace with the bundled library.
pub fn with_diagram<T>(
    sources: &[(String, String)],
    name: &str,
    f: impl FnOnce(&Semantics<'_>, &Definition) -> T,
) -> T {
    let db = RootDatabase::default();
    let mut files = library::library_files(&db);
    for (path, text) in sources {
        files.push(SourceFile::new(&db, path.clone(), text.clone()));
    }
    let sema = Semantics::new(&db, Workspace::new(&db, files));
    let def = sema.def_map().definitions.get(name).and_then(|d| d.first()).unwrap_or_else(|| panic!("no {name}"));
    f(&sema, def)
}

/// The kernel generated from the diagram `name` of the samples.
pub fn generated(name: &str) -> Kernel {
    let sources: Vec<(String, String)> = main_sources(|text| text);
    generated_from(&sources, name)
}

/// The kernel generated from the diagram `name` of these `(path, text)` files.
pub fn generated_from(sources: &[(String, String)], name: &str) -> Kernel {
    generation(sources, name).unwrap_or_else(|e| panic!("{name}: {e:?}"))
}

/// The kernel generated from the diagram `name` of these files, or what cannot be generated
/// (each error's path, 1-based line and message).
#[allow(dead_code)] // Not every test file that shares this module asks for errors.
pub fn generation(sources: &[(String, String)], name: &str) -> Result<Kernel, Vec<(String, u32, String)>> {
    with_diagram(sources, name, |sema, diagram| {
        gudsl_codegen::generate(sema, diagram).map_err(|errors| {
            errors
                .into_iter()
                .map(|e| {
                    let text = e.file.text(sema.db());
                    let line = text[..usize::from(e.range.start())].matches('\n').count() as u32 + 1;
                    (e.file.path(sema.db()).clone(), line, e.message)
                })
                .collect()
        })
    })
}

/// The host diagram `name` of these `(path, text)` files, prepared to run.
pub fn prepared(sources: &[(String, String)], name: &str) -> Result<PreparedRun, Vec<RunError>> {
    with_diagram(sources, name, |sema, def| prepare(sema, def, &gudsl_host::access::Access::default()))
}

/// The folder `dir` as a run's output folder (made if missing).
pub fn output(dir: &std::path::Path) -> gudsl_host::output::OutputDir {
    gudsl_host::output::OutputDir::named(dir).unwrap()
}

/// The device a benchmark runs on (dispatches timed by the GPU's clock where it has one, when
/// `timestamps`); exits when there is none.
pub fn bench_gpu(timestamps: bool) -> Gpu {
    match if timestamps { Gpu::with_timestamps() } else { Gpu::new() } {
        Ok(gpu) => {
            let timed = if gpu.times_on_device() {
                "dispatches timed by the GPU's timestamps (the compute pass alone)"
            } else {
                "dispatches timed from submission to completion"
            };
            println!("adapter: {}; {timed}\n", gpu.describe());
            gpu
        }
        Err(error) => {
            eprintln!("{error}");
            std::process::exit(1);
        }
    }
}

/// The median of `samples`, in milliseconds.
pub fn median_ms(mut samples: Vec<Duration>) -> f64 {
    samples.sort();
    samples[samples.len() / 2].as_secs_f64() * 1e3
}

/// Deterministic bytes (xorshift).
pub fn random_bytes(len: usize, seed: u64) -> Vec<u8> {
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
pub struct Rgba {
    pub width: usize,
    pub height: usize,
    pub texels: Vec<u8>,
}

impl Rgba {
    pub fn random(width: usize, height: usize, seed: u64) -> Rgba {
        let mut texels = random_bytes(4 * width * height, seed);
        texels.iter_mut().skip(3).step_by(4).for_each(|alpha| *alpha = 255);
        Rgba { width, height, texels }
    }

    /// The amplitude of a simulated ToF frame (the sphere scene), as grey levels.
    pub fn amplitude() -> Rgba {
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
    pub fn red_plane(&self) -> Image {
        let data = self.texels.iter().step_by(4).map(|&v| v as f32).collect();
        Image::from_plane(self.width, self.height, data)
    }

    pub fn upload(&self, gpu: &Gpu) -> DeviceImage {
        let image = self.empty(gpu);
        image.write(gpu, &self.texels).unwrap();
        image
    }

    pub fn empty(&self, gpu: &Gpu) -> DeviceImage {
        let size = [self.width as u32, self.height as u32, 1];
        DeviceImage::new(gpu, "image", TexelFormat::Rgba8Uint, 2, size).unwrap()
    }
}

/// Launches a generated image filter (input image, output image, then `values`); its time.
pub fn launch_filter(
    gpu: &Gpu,
    launcher: &Launcher,
    input: &DeviceImage,
    output: &DeviceImage,
    values: &[Number],
) -> Duration {
    let mut args = vec![Arg::Image(input), Arg::Image(output)];
    args.extend(values.iter().map(|&v| Arg::Number(v)));
    let [width, height, _] = input.size();
    launcher.launch(gpu, &args, &WorkRange::planar(width, height, None)).unwrap()
}

/// Dispatches a hand-written listing filter with its parameter block; its time.
pub fn dispatch_listing(
    gpu: &Gpu,
    program: &Program,
    params: &[u8],
    input: &DeviceImage,
    output: &DeviceImage,
) -> Duration {
    let resources = [(0, Resource::Uniform(params)), (1, Resource::Image(input)), (2, Resource::Image(output))];
    let [width, height, _] = input.size();
    program.dispatch(gpu, &[], &resources, listings::workgroups(width, height)).unwrap()
}

/// Compiles a hand-written listing filter.
pub fn listing(gpu: &Gpu, source: &str) -> Program {
    Program::new(gpu, "listing", source, listings::ENTRY_POINT, &listings::BINDINGS).unwrap()
}

/// Runs a generated image filter on `image`.
pub fn run_generated(gpu: &Gpu, kernel: &Kernel, image: &Rgba, values: &[Number]) -> Vec<u8> {
    let launcher = Launcher::new(gpu, kernel).unwrap();
    let (input, output) = (image.upload(gpu), image.empty(gpu));
    launch_filter(gpu, &launcher, &input, &output, values);
    output.read(gpu).unwrap()
}

/// Runs a hand-written listing filter on `image`.
pub fn run_handwritten(gpu: &Gpu, source: &str, params: &[u8], image: &Rgba) -> Vec<u8> {
    let (input, output) = (image.upload(gpu), image.empty(gpu));
    dispatch_listing(gpu, &listing(gpu, source), params, &input, &output);
    output.read(gpu).unwrap()
}

/// The two generated findIndex kernels, run as Main's calcRange nodes run them (Listing 32):
/// work sizes from the device's largest work-group (at most 256), stage 1 over the elements,
/// stage 2 over the groups' results; and the same two stages written by hand
/// (`listings::find_index`).
pub struct FindIndex {
    first: Launcher,
    second: Launcher,
    hand_first: Program,
    hand_second: Program,
}

/// The elements on the device and the work sizes for them.
pub struct FindIndexInput {
    elements: DeviceBuffer,
    minima: DeviceBuffer,
    last: DeviceBuffer,
    len: u32,
    local: u32,
    groups: u32,
    per_item: u32,
}

impl FindIndex {
    pub fn new(gpu: &Gpu) -> FindIndex {
        let first = Launcher::new(gpu, &generated("AdFindMinimumIndexFirstStage")).unwrap();
        let second = Launcher::new(gpu, &generated("AdFindMinimumIndexSecondStage")).unwrap();
        let hand = |entry| {
            let (source, bindings) = (listings::find_index::WGSL, &listings::find_index::BINDINGS);
            Program::new(gpu, "findIndex", source, entry, bindings).unwrap()
        };
        let (hand_first, hand_second) =
            (hand(listings::find_index::FIRST_STAGE), hand(listings::find_index::SECOND_STAGE));
        FindIndex { first, second, hand_first, hand_second }
    }

    /// `elements` on the device, with Main's work sizes for the device's largest work-group
    /// (at most 256).
    pub fn upload(gpu: &Gpu, elements: &[u32]) -> FindIndexInput {
        let local = gpu.device.limits().max_compute_invocations_per_workgroup.min(256);
        FindIndex::upload_for(gpu, elements, local)
    }

    /// `elements` on the device, with Main's work sizes for work-groups of `local` (a power
    /// of two): as many groups as fit `local` (stage 2 is one group of them), each work-item
    /// scanning a slice so that they cover the elements.
    pub fn upload_for(gpu: &Gpu, elements: &[u32], local: u32) -> FindIndexInput {
        let len = elements.len() as u32;
        let needed = len.next_power_of_two();
        let groups = (needed / local).clamp(1, local);
        let per_item = needed.div_ceil(groups * local).max(1);
        let bytes: Vec<u8> = elements.iter().flat_map(|v| v.to_le_bytes()).collect();
        let input = DeviceBuffer::new(gpu, "elements", 4 * len as u64).unwrap();
        input.write(gpu, &bytes).unwrap();
        let minima = DeviceBuffer::new(gpu, "minima", 4 * groups as u64).unwrap();
        let last = DeviceBuffer::new(gpu, "last", 4).unwrap();
        FindIndexInput { elements: input, minima, last, len, local, groups, per_item }
    }

    /// What [`FindIndex::run`] finds, by the hand-written kernels at the same work sizes.
    pub fn run_handwritten(&self, gpu: &Gpu, input: &FindIndexInput, value: u32) -> (i32, Duration) {
        let FindIndexInput { elements, minima, last, len, local, groups, per_item } = input;
        let params = listings::find_index::params(*len, value, *per_item, *groups);
        let resources = [
            (0, Resource::Uniform(&params)),
            (1, Resource::Buffer(elements)),
            (2, Resource::Buffer(minima)),
            (3, Resource::Buffer(last)),
        ];
        let size = |n: u32| [(listings::find_index::GROUP_SIZE, f64::from(n))];
        let first = self.hand_first.dispatch(gpu, &size(*local), &resources, [*groups, 1, 1]).unwrap();
        let second = self.hand_second.dispatch(gpu, &size(*groups), &resources, [1, 1, 1]).unwrap();
        let index = i32::from_le_bytes(last.read(gpu).unwrap()[..4].try_into().unwrap());
        (index, first + second)
    }

    /// What stage 1 left for each work-group (its first index of an element >= the value, -1
    /// for none), after [`FindIndex::run`], and the elements each group scanned.
    pub fn group_candidates(&self, gpu: &Gpu, input: &FindIndexInput) -> (Vec<i32>, usize) {
        let bytes = input.minima.read(gpu).unwrap();
        let candidates = bytes.chunks_exact(4).map(|b| i32::from_le_bytes(b.try_into().unwrap())).collect();
        (candidates, (input.local * input.per_item) as usize)
    }

    /// The first index of an element >= `value` (-1 for none), and the time of both stages.
    pub fn run(&self, gpu: &Gpu, input: &FindIndexInput, value: u32) -> (i32, Duration) {
        let int = |v: u32| Arg::Number(Number::Int(v as i64));
        let value = Arg::Number(Number::UInt(value as u64));
        let FindIndexInput { elements, minima, last, len, local, groups, per_item } = input;
        let args =
            [Arg::Buffer(elements), Arg::Buffer(minima), int(*len), int(local * 4), int(*local), value, int(*per_item)];
        let first = self.first.launch(gpu, &args, &WorkRange::linear(groups * local, Some(*local))).unwrap();
        let args = [
            Arg::Buffer(elements),
            Arg::Buffer(minima),
            Arg::Buffer(last),
            int(*groups),
            int(groups * 4),
            int(*groups),
            value,
        ];
        let second = self.second.launch(gpu, &args, &WorkRange::linear(*groups, Some(*groups))).unwrap();
        let index = i32::from_le_bytes(last.read(gpu).unwrap()[..4].try_into().unwrap());
        (index, first + second)
    }
}

/// Checks an image filtered by Listing 15's mean (`channels` per pixel: 3 or 4) against the
/// mean of `input`'s windows done exactly: each interior value is the window's integer sum
/// divided by its size and truncated — or one less where that quotient is exact, because the
/// listing divides in `float` and a device may round the quotient just below it (WGSL allows
/// 2.5 ULP for division; lavapipe and the CPU divide exactly); pixels nearer the border than
/// the radius are invalid (0, 0, 0). The number of values one less, or the first that is wrong.
#[allow(dead_code)] // Not every test file that shares this module filters means.
pub fn check_mean(filtered: &[u8], channels: usize, input: &Rgba, kernel_size: usize) -> Result<usize, String> {
    let (width, height, r) = (input.width, input.height, kernel_size / 2);
    let count = ((2 * r + 1) * (2 * r + 1)) as u32;
    let mut rounded_down = 0;
    for y in 0..height {
        for x in 0..width {
            let interior = x >= r && y >= r && x + r < width && y + r < height;
            for c in 0..3 {
                let got = filtered[channels * (y * width + x) + c] as u32;
                if !interior {
                    if got != 0 {
                        return Err(format!("border pixel ({x}, {y}) channel {c} is {got}, not 0"));
                    }
                    continue;
                }
                let sum: u32 = (y - r..=y + r)
                    .flat_map(|v| (x - r..=x + r).map(move |u| (u, v)))
                    .map(|(u, v)| input.texels[4 * (v * width + u) + c] as u32)
                    .sum();
                let mean = sum / count;
                if got == mean {
                    continue;
                }
                if sum.is_multiple_of(count) && got + 1 == mean {
                    rounded_down += 1;
                    continue;
                }
                return Err(format!("pixel ({x}, {y}) channel {c} is {got}; its window's mean is {sum}/{count}"));
            }
        }
    }
    Ok(rounded_down)
}

/// Diagrams called with `call behavior` from device code (`called_diagrams.rs`, as WGSL
/// functions) and from host code (`host_calls.rs`, interpreted): the same GU-DSL on both sides.
#[allow(dead_code)] // Not every test file that shares this module calls diagrams.
pub const CLAMP_AND_COLLATZ: &str = "ActivityDiagram Clamp(int v, int low, int high)
{
    swimlane L
    {
        start S { => test; }
        decision test
        {
            [v < low] => below;
            [v > high] => above;
            [] => inside;
        }
        final below return low;
        final above return high;
        final inside return v;
    }
}

ActivityDiagram CollatzSteps(int n)
{
    var int steps = 0;
    var int x = n;
    swimlane L
    {
        start S { => test; }
        decision test
        {
            [x <= 1] => done;
            [x % 2 == 0] => half;
            [] => triple;
        }
        action half { x = x / 2; steps++; => test; }
        action triple { x = 3 * x + 1; steps++; => test; }
        final done return steps;
    }
}

ActivityDiagram ClampedSteps(int n)
{
    var int steps;
    swimlane L
    {
        start S { => count; }
        action count { steps = call behavior Clamp(call behavior CollatzSteps(n), 0, 100); => f; }
        final f return steps;
    }
}
";

/// What `CollatzSteps(x)` of [`CLAMP_AND_COLLATZ`] returns, computed in Rust.
#[allow(dead_code)] // Not every test file that shares this module calls diagrams.
pub fn collatz_steps(mut x: i32) -> i32 {
    let mut steps = 0;
    while x > 1 {
        x = if x % 2 == 0 { x / 2 } else { 3 * x + 1 };
        steps += 1;
    }
    steps
}
