//! End-to-end tests of `gudsl run` on pipelines of the workspace's own components: chapter
//! 11.5's example (Listings 26–28: two cameras, a mean filter running Listing 15's activity
//! diagram as generated WGSL, a viewer colouring its images with a device diagram of its own)
//! runs on lavapipe and its images equal the same chain through the runtime's Rust API — the
//! simulator, its demodulation and grey-image kernels, Listing 15 as a person writes it in WGSL
//! (`runtime/src/listings`) and the viewer's colouring in Rust — byte for byte; and components
//! that cannot run are refused with a message that says why: a diagram parameter no field
//! gives (E0405, in `gudsl check` too), a host diagram where a device diagram belongs, a call
//! inside a branch, a sink that extends no library sink, a run without a GPU. A depth filter of
//! the workspace runs its diagram on the depth image's buffers, equal to the Rust API's.
//! Listing 28's flat form (an instance's port instances and bindings without braces) checks
//! clean and runs to the same pictures.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, repo, temp_dir};
use gudsl_formats::arrays;
use gudsl_runtime::{
    camera::Intrinsics,
    listings,
    sim::{simulate, Camera, Motion, Scene},
    ChainRun, DeviceImage, Gpu, Kernel, Pipeline, Program, Resource, Shape, TexelFormat,
};

const SAMPLE: &str = "samples/pipelines/ch11_component_example.gudsl";

fn gpu() -> bool {
    std::env::var_os("GUDSL_NO_GPU").is_none()
}

/// `gudsl` with `args`: exit code, stdout and stderr together.
fn run(args: &[&str]) -> (Option<i32>, String) {
    let out = gudsl().args(args).output().unwrap();
    let text = format!("{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out.status.code(), text)
}

/// A camera of the sample (`width × height`, the library's defaults otherwise) through the
/// Rust API: frame 0 demodulated, its amplitude as a grey image, Listing 15's hand-written mean
/// filter (kernel size 5), the viewer's colouring; RGBA8 texels, row after row.
fn rust_api(gpu: &Gpu, width: usize, height: usize) -> Vec<u8> {
    let camera = Camera { intrinsics: Intrinsics::camcube_at(width, height), ..Camera::default() };
    let frame = simulate(&Scene::sphere(), Motion::Still, &camera, 0);
    let mut p = Pipeline::new();
    let raw = p.source("raw", Shape { width, height, planes: 8 });
    let amplitude = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[1];
    let grey = p.step(Kernel::GreyImage { gain: 0.05 }, &[amplitude]).unwrap()[0];
    p.sink(grey).unwrap();
    let planes = ChainRun::new(Some(gpu), &p).run(&[frame.raw]).unwrap().remove(0);
    let n = width * height;
    let texels: Vec<u8> =
        (0..n).flat_map(|i| (0..4).map(move |c| (c, i))).map(|(c, i)| planes.data[c * n + i] as u8).collect();

    let size = [width as u32, height as u32, 1];
    let image = || DeviceImage::new(gpu, "image", TexelFormat::Rgba8Uint, 2, size).unwrap();
    let (input, output) = (image(), image());
    input.write(gpu, &texels).unwrap();
    let mean = Program::new(gpu, "mean", listings::MEAN_WGSL, listings::ENTRY_POINT, &listings::BINDINGS).unwrap();
    let params = listings::mean_params(5, size[0], size[1]);
    let resources = [(0, Resource::Uniform(&params)), (1, Resource::Image(&input)), (2, Resource::Image(&output))];
    mean.dispatch(gpu, &[], &resources, listings::workgroups(size[0], size[1])).unwrap();
    let filtered = output.read(gpu).unwrap();
    filtered
        .chunks(4)
        .flat_map(|texel| {
            let grey = texel[0] as i32;
            let (red, blue) = if grey < 128 { (2 * grey, 255 - 2 * grey) } else { (255, 0) };
            [red as u8, grey as u8, blue as u8, 255]
        })
        .collect()
}

#[test]
fn the_component_example_runs_and_equals_the_rust_api() {
    if !gpu() {
        return;
    }
    let out = temp_dir("example");
    let (code, text) = run(&["run", &repo(SAMPLE), "--frames", "1", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.contains("ran ComponentExamplePipeline (1 frames)"), "{text}");
    assert!(text.lines().any(|l| l.starts_with("MeanFilter1 ") && l.contains("ComponentExampleClasses.MeanFilter")));

    let gpu = Gpu::for_tests().expect("an adapter");
    for (camera, width, height) in [("Camera1", 640, 480), ("Camera2", 200, 200)] {
        let written = image::open(out.join(format!("Viewer1/{camera}_0000.png"))).unwrap();
        assert_eq!(written.color(), image::ColorType::Rgba8, "{camera}");
        assert_eq!((written.width(), written.height()), (width as u32, height as u32), "{camera}");
        let expected = rust_api(&gpu, width, height);
        let written = written.into_rgba8().into_raw();
        let differ = written.iter().zip(&expected).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{camera}: {differ} channel values differ from the Rust API's");
        // Not a blank picture: the sphere is brighter than the wall, the border is marked.
        let greens: std::collections::BTreeSet<u8> = written.chunks(4).map(|t| t[1]).collect();
        assert!(greens.len() > 20, "{camera}: {} grey levels", greens.len());
    }
}

/// The sample with `edits` (pattern → replacement, each must apply) in a scratch folder.
fn edited(dir: &std::path::Path, name: &str, edits: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    for (pattern, replacement) in edits {
        assert!(text.contains(pattern), "{pattern}");
        text = text.replace(pattern, replacement);
    }
    let path = dir.join(format!("{name}.gudsl"));
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// The sample with Listing 28's flat form: its instances' port instances and bindings follow
/// them without braces.
fn flat_form(dir: &std::path::Path) -> String {
    let text = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    let start = text.find("ComponentInstanceDiagram").unwrap();
    let end = start + text[start..].find("\n}\n").unwrap();
    let diagram: Vec<&str> = text[start..end].lines().filter(|l| !matches!(*l, "    {" | "    }")).collect();
    let flat = format!("{}{}{}", &text[..start], diagram.join("\n"), &text[end..]);
    assert_ne!(flat, text);
    let path = dir.join("flat.gudsl");
    std::fs::write(&path, flat).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn the_flat_form_of_listing_28_checks_and_runs_as_the_braced_one() {
    let dir = temp_dir("flat");
    let file = flat_form(&dir);
    let (code, text) = run(&["check", &file]);
    assert_eq!(code, Some(0), "{text}");
    if !gpu() {
        return;
    }
    let (braced_out, flat_out) = (dir.join("braced"), dir.join("flat"));
    for (model, out) in [(repo(SAMPLE), &braced_out), (file, &flat_out)] {
        let (code, text) = run(&["run", &model, "--frames", "1", "-o", out.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{text}");
    }
    for camera in ["Camera1", "Camera2"] {
        let picture = |out: &std::path::Path| std::fs::read(out.join(format!("Viewer1/{camera}_0000.png"))).unwrap();
        assert!(picture(&flat_out) == picture(&braced_out), "{camera}: the flat form's picture differs");
    }
}

#[test]
fn components_that_cannot_run_are_refused_with_the_reason() {
    let dir = temp_dir("refused");
    let out = dir.join("out");
    let out = out.to_str().unwrap();

    // Listing 15 takes `kernelSize`; without a field of that name nothing gives it (E0405).
    let file = edited(&dir, "no_field", &[("        public int kernelSize = 5;\n", "")]);
    let (code, text) = run(&["check", &file]);
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("E0405") && text.contains("`ComponentExampleClasses.MeanFilter` has no field `kernelSize`"),
        "{text}"
    );
    let (code, text) = run(&["run", &file, "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("E0405") && text.contains("takes `int kernelSize`"), "{text}");

    // A host activity diagram is no kernel.
    let host = "\nActivityDiagram AdHostExample()\n{\n    swimlane Host\n    {\n        start S { => done; }\n        final done;\n    }\n}\n";
    let file = edited(
        &dir,
        "host_diagram",
        &[
            ("call behavior AdFilterMeanExample;", "call behavior AdHostExample;"),
            ("// Listing 15's mean", &format!("{host}\n// Listing 15's mean")),
        ],
    );
    let (code, text) = run(&["run", &file, "--diagram", "ComponentExamplePipeline", "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("`AdHostExample` is not a device diagram"), "{text}");

    // A call inside a branch would not run as written.
    let file = edited(
        &dir,
        "branch",
        &[("call behavior AdFilterMeanExample;", "if (kernelSize > 1) { call behavior AdFilterMeanExample; }")],
    );
    let (code, text) = run(&["run", &file, "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("with arguments or inside a branch or loop"), "{text}");

    // A sink of the workspace that extends no library sink keeps nothing.
    let file = edited(&dir, "sink", &[("public sink Viewer extends ImageViewer", "public sink Viewer")]);
    let (code, text) = run(&["run", &file, "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("extends no sink of the ToF library"), "{text}");
    assert!(!dir.join("out").exists(), "nothing written for a refused pipeline");

    // Generated device code needs a GPU: on the CPU reference the run stops at the filter —
    // also where the filter runs on a thread of its own (its port `async`), failing there.
    let (code, text) = run(&["run", &repo(SAMPLE), "--cpu", "--frames", "1", "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("`MeanFilter1` runs device diagrams") && text.contains("need a GPU adapter"), "{text}");
    let port = "        port MeanImageProcessorPort";
    let file = edited(&dir, "async-cpu", &[(port, "        async port MeanImageProcessorPort")]);
    let (code, text) = run(&["run", &file, "--cpu", "--frames", "2", "-o", out]);
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("ComponentExampleClasses.MeanFilter (async)"), "{text}");
    assert!(text.contains("`MeanFilter1`: `MeanFilter1` runs device diagrams"), "{text}");
}

/// A depth filter of the workspace: its `process` scales the distance by its field `factor` in a
/// device diagram on the depth image's buffers.
const DEPTH_FILTER: &str = r#"ClassDiagram DepthComponents
{
    import ToF.*;

    public filter Halve implements IDepthImageProcessor, IDepthImageProvider
    {
        public float factor = 0.5;

        public bool process(ConstIObjectParametersPtr parameters)
        {
            call behavior AdScaleDistance;
            return true;
        }
    }

    ClassDiagram Gpu
    {
        import OpenCL.GPU.*;

        public class DepthKernels implements OpenCL
        {
            public void scale(global ref float distance, global ref float scaled, float factor);
        }
    }
}

ComponentDiagram DepthComponentDiagram
{
    filter DepthComponents.Halve
    {
        port DepthIn ( processor depth : ToF.IDepthImageProcessor );
        port DepthOut ( provider depth : ToF.IDepthImageProvider );
    }
}

ActivityDiagram AdScaleDistance(global ref float distance, global ref float scaled, float factor)
{
    import OpenCL.GPU.*;

    swimlane P1, owner DepthComponents.Gpu.DepthKernels
    {
        start S1 { => scale; }

        action scale
        {
            var int i = get_global_id(1) * get_global_size(0) + get_global_id(0);
            scaled[i] = distance[i] * factor;
            => f;
        }

        final f;
    }
}

ComponentInstanceDiagram DepthScale
{
    import ToF.*;

    Camera instantiates SimulatedCamera (frames = 1)
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }

    Demod instantiates Demodulation ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Half.In.depth ]
    }

    Half instantiates DepthComponents.Halve ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Depth.In.depth ]
    }

    Depth instantiates NpyWriter (amplitude = false)
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#;

#[test]
fn a_filter_of_your_own_runs_its_diagram_on_depth_images() {
    if !gpu() {
        return;
    }
    let dir = temp_dir("depth");
    std::fs::write(dir.join("depth.gudsl"), DEPTH_FILTER).unwrap();
    let out = dir.join("out");
    let file = dir.join("depth.gudsl");
    let (code, text) = run(&["run", file.to_str().unwrap(), "--diagram", "DepthScale", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{text}");
    assert!(text.lines().any(|l| l.starts_with("Half ") && l.contains("DepthComponents.Halve")), "{text}");

    // The same on the Rust API: the demodulated distance, halved in f32.
    let gpu = Gpu::for_tests().expect("an adapter");
    let frame = simulate(&Scene::sphere(), Motion::Still, &Camera::default(), 0);
    let mut p = Pipeline::new();
    let raw = p.source("raw", Shape { width: 200, height: 200, planes: 8 });
    let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[raw]).unwrap()[3];
    p.sink(distance).unwrap();
    let distance = ChainRun::new(Some(&gpu), &p).run(&[frame.raw]).unwrap().remove(0);
    let written =
        arrays::read(&gudsl_files::Folder::open(&out).unwrap(), &out.join("Depth/distance_0000.npy")).unwrap();
    assert_eq!(written.shape, [200, 200]);
    let differ = written.values.iter().zip(&distance.data).filter(|(w, d)| w.to_bits() != (*d * 0.5).to_bits()).count();
    assert_eq!(differ, 0, "{differ} distances differ from the Rust API's halved ones");
    assert!(distance.data.iter().any(|d| *d > 1.0), "a scene in view");

    // A diagram that reads a buffer no plane is named after is refused with the planes' names.
    let bad = DEPTH_FILTER
        .replace("global ref float distance,", "global ref float depth,")
        .replace("distance[i]", "depth[i]");
    std::fs::write(dir.join("bad.gudsl"), bad).unwrap();
    let file = dir.join("bad.gudsl");
    let (code, text) = run(&["run", file.to_str().unwrap(), "--diagram", "DepthScale", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("it reads a buffer `depth`; a depth image's planes are distance, amplitude, intensity"),
        "{text}"
    );
}

#[test]
fn an_async_filter_runs_on_a_thread_of_its_own_and_gives_what_it_would_in_order() {
    if !gpu() {
        return; // its diagram is WGSL
    }
    let dir = temp_dir("async-filter");
    let args = ["--frames", "2"];
    let ran = |file: &str, out: &std::path::Path| {
        let (code, text) = run(&[&["run", file, "-o", out.to_str().unwrap()], args.as_slice()].concat());
        assert_eq!(code, Some(0), "{text}");
        text
    };
    let in_order = ran(&repo(SAMPLE), &dir.join("in-order"));
    // Sec. 11.3.3: the filter's processor port `async` (the caller goes on at once).
    let port = "        port MeanImageProcessorPort";
    let file = edited(&dir, "async", &[(port, "        async port MeanImageProcessorPort")]);
    let apart = ran(&file, &dir.join("apart"));
    let mean_filter = |text: &str| text.lines().find(|l| l.starts_with("MeanFilter1 ")).unwrap_or_default().to_string();
    assert!(mean_filter(&apart).contains("ComponentExampleClasses.MeanFilter (async)"), "{apart}");
    assert!(!mean_filter(&in_order).contains("(async)"), "{in_order}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("apart/report.json")).unwrap()).unwrap();
    let stage =
        |name: &str| report["stages"].as_array().unwrap().iter().find(|s| s["instance"] == name).unwrap().clone();
    assert_eq!((stage("MeanFilter1")["async"].clone(), stage("Camera1")["async"].clone()), (true.into(), false.into()));
    // Its diagram ran on its own device and thread: the pictures are the same, byte for byte.
    for frame in 0..2 {
        for camera in ["Camera1", "Camera2"] {
            let name = format!("Viewer1/{camera}_{frame:04}.png");
            let (a, b) =
                (std::fs::read(dir.join("in-order").join(&name)), std::fs::read(dir.join("apart").join(&name)));
            assert!(a.unwrap() == b.unwrap(), "{name} differs");
        }
    }
}
