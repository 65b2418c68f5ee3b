//! End-to-end tests of `gudsl run` on ToF pipelines (component-instance diagrams): the chapter 4
//! sample runs on lavapipe, its depth images equal the same pipeline assembled through the
//! runtime's Rust API bit for bit (ρ's restriction from the previous frame included), its
//! accuracy report shows the compensation; and bad pipelines are refused with their
//! diagnostics and exit codes: an unbound input (E0401), a black image file that does not exist
//! (E0404), an output folder that cannot be made.

#[path = "support/cli.rs"]
mod cli;

use std::path::Path;

use cli::{gudsl, repo, temp_dir};
use gudsl_runtime::{
    kernels::motion::mean_direction,
    npy,
    sim::{simulate, Camera, Motion, Scene},
    Gpu, GpuPipeline, Kernel, Pipeline, Shape,
};

const SAMPLE: &str = "samples/pipelines/ch4_motion_compensation.gudsl";

fn gpu() -> bool {
    std::env::var_os("GUDSL_NO_GPU").is_none()
}

fn run(args: &[&str]) -> (Option<i32>, String, String) {
    let out = gudsl().arg("run").args(args).output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A refused run's diagnostics (on stdout, as `gudsl check` prints them) and messages (stderr).
fn refused(args: &[&str]) -> (Option<i32>, String) {
    let (code, stdout, stderr) = run(args);
    (code, format!("{stdout}\n{stderr}"))
}

/// The sample's compensated chain through the runtime's API: frames 0 and 1's distances.
fn rust_api(gpu: &Gpu) -> Vec<Vec<f32>> {
    let camera = Camera::default();
    let motion = Motion::Translation([0.01, 0.0, 0.0]);
    let mut direction = None;
    let mut distances = Vec::new();
    for frame in 0..2 {
        let simulated = simulate(&Scene::sphere(), motion, &camera, frame);
        let mut p = Pipeline::new();
        let shape = Shape { width: 200, height: 200, planes: 8 };
        let (raw, black) = (p.source("raw", shape), p.source("black", shape));
        let raw = p.step(Kernel::SubtractBlack, &[raw, black]).unwrap()[0];
        let mask = p.step(Kernel::DetectMotion { theta: 0.01 * 65535.0 }, &[raw]).unwrap()[1];
        let restriction = direction.map(|mean| (mean, 45f32.to_radians()));
        let flow = p.step(Kernel::MatchBlocks { window: 5, restriction }, &[raw, mask]).unwrap()[0];
        let corrected = p.step(Kernel::CorrectRaw, &[raw, flow]).unwrap()[0];
        let distance = p.step(Kernel::Demodulate { modulation_hz: 20.0e6 }, &[corrected]).unwrap()[3];
        p.sink(distance).unwrap();
        p.sink(flow).unwrap();
        let out = GpuPipeline::new(gpu, &p).run(&[simulated.raw, simulated.black]).unwrap();
        direction = mean_direction(&out[1]);
        distances.push(out[0].data.clone());
    }
    distances
}

#[test]
fn the_chapter_4_sample_runs_and_equals_the_rust_api() {
    if !gpu() {
        return;
    }
    let out = temp_dir("pipeline-ch4");
    let (code, stdout, stderr) = run(&[&repo(SAMPLE), "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("ran MotionCompensationPipeline (2 frames)"), "{stdout}");
    assert!(stdout.lines().any(|l| l.starts_with("Motion ") && l.contains("ToF.MotionCompensation")), "{stdout}");
    assert!(stderr.contains("frame 2/2"), "progress: {stderr}");

    let gpu = Gpu::for_tests().expect("an adapter");
    let expected = rust_api(&gpu);
    for (frame, expected) in expected.iter().enumerate() {
        let (shape, values) = npy::load(&out.join(format!("Depth/distance_{frame:04}.npy"))).unwrap();
        assert_eq!(shape, [200, 200]);
        let same = values.iter().zip(expected).all(|(a, b)| a.to_bits() == b.to_bits());
        assert!(same, "frame {frame}: the pipeline's distances differ from the Rust API's");
    }

    let csv = std::fs::read_to_string(out.join("Accuracy/accuracy.csv")).unwrap();
    let mean = |series: &str| -> f64 {
        let rows: Vec<f64> = csv
            .lines()
            .filter(|l| l.contains(&format!(",{series},")))
            .map(|l| l.split(',').nth(3).unwrap().parse().unwrap())
            .collect();
        assert_eq!(rows.len(), 2, "{series} in\n{csv}");
        rows.iter().sum::<f64>() / 2.0
    };
    let (before, after) = (mean("Uncompensated"), mean("Compensated"));
    assert!(after < 0.7 * before, "compensation: {before:.2} cm -> {after:.2} cm");
    for file in ["Accuracy/accuracy.svg", "Accuracy/accuracy.png", "Images/preview_0001.png", "report.json"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let distance = image::open(out.join("Images/distance_0000.png")).unwrap();
    assert_eq!(distance.color(), image::ColorType::L16);
}

/// A pipeline file in a scratch folder, `body` inside `ComponentInstanceDiagram Bad`.
fn pipeline(dir: &Path, body: &str) -> String {
    let path = dir.join("bad.gudsl");
    std::fs::write(&path, format!("ComponentInstanceDiagram Bad\n{{\n    import ToF.*;\n{body}\n}}\n")).unwrap();
    path.to_str().unwrap().to_string()
}

const CAMERA: &str = "
    Camera instantiates SimulatedCamera (frames = 1)
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Black.In.frame ]
    }";

/// The camera and a black-image correction with `values`, whose output goes nowhere (fine).
fn camera_and_black(values: &str) -> String {
    format!(
        "{CAMERA}
    Black instantiates BlackImageCorrection ({values})
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
    }}"
    )
}

#[test]
fn bad_pipelines_are_refused_with_their_diagnostics() {
    let dir = temp_dir("pipeline-bad");
    // A filter whose output goes nowhere is fine; a sink with no input is not (E0401).
    let file = pipeline(&dir, &format!("{}\n    Writer instantiates NpyWriter ( )", camera_and_black(" ")));
    let (code, stderr) = refused(&[&file, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("E0401") && stderr.contains("`Writer` receives nothing on `DepthIn.depth`"), "{stderr}");
    assert!(!dir.join("out").exists(), "nothing written for a refused pipeline");

    // A black image that does not exist (E0404, exit code 2), at its parameter.
    let file = pipeline(&dir, &camera_and_black("channelA = \"missing_a.npy\", channelB = \"missing_b.npy\""));
    let (code, stderr) = refused(&[&file, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("E0404") && stderr.contains("missing_a.npy does not exist"), "{stderr}");
    assert!(stderr.contains("(4, H, W)"), "the expected shape: {stderr}");

    if !gpu() {
        return;
    }
    // An output folder that cannot be made: a file is in its place.
    let file = pipeline(&dir, &camera_and_black(" "));
    let blocked = dir.join("blocked");
    std::fs::write(&blocked, "a file").unwrap();
    let (code, stderr) = refused(&[&file, "-o", blocked.join("out").to_str().unwrap()]);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("cannot create the output folder"), "{stderr}");
}
