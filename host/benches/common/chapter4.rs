//! What the chapter 4 benchmarks share: the pipeline as a user writes it, on simulated or
//! recorded frames, its run in one process, and the recording of simulated frames.

#![allow(dead_code)] // each benchmark takes what it needs

use std::{
    path::Path,
    sync::atomic::AtomicBool,
    time::{Duration, Instant},
};

use gudsl_formats::arrays;
use gudsl_host::{
    access::Access,
    pipeline::{self, OutputDir, PipelineObserver},
};
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    hir::{pipeline::pipeline_plan, Fqn, Semantics},
    library,
};
use gudsl_runtime::{
    camera::Intrinsics,
    sim::{simulate, Camera, Motion, Scene},
    Gpu, Image,
};

/// Frames a run (the first one's cost cancels out: see above) when each is simulated.
pub const FRAMES: usize = 9;
/// Frames a run when they are recorded: more, as each is short and the difference of two runs'
/// times is what is measured.
pub const RECORDED_FRAMES: usize = 25;
pub const MOTION: Motion = Motion::Translation([0.01, 0.0, 0.0]);

/// Where the frames come from: the simulator, each frame (both sides simulate on the CPU), or
/// files recorded from it before the run (`ToF.RawFrameFile`, read before the first frame: the
/// pipeline's own cost alone).
#[derive(Clone, Copy)]
pub enum Frames<'a> {
    Simulated,
    Recorded(&'a Path),
}

impl Frames<'_> {
    /// Frames a run.
    pub fn count(self) -> usize {
        match self {
            Frames::Simulated => FRAMES,
            Frames::Recorded(_) => RECORDED_FRAMES,
        }
    }
}

/// The pipeline as a user writes it.
pub fn model(width: usize, height: usize, frames: usize, source: Frames) -> String {
    let (camera, black) = match source {
        Frames::Simulated => (
            format!("SimulatedCamera (motion = Motion.Translation, speed = 1, frames = {frames}, width = {width}, height = {height})"),
            "Black",
        ),
        Frames::Recorded(dir) => (
            format!("RawFrameFile (channelA = \"{}\", channelB = \"{}\", frames = {frames})", dir.join("a.npy").display(), dir.join("b.npy").display()),
            "Motion",
        ),
    };
    let black_stage = if black == "Black" {
        "Black instantiates BlackImageCorrection ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Motion.In.frame ]
    }"
    } else {
        ""
    };
    format!(
        "ComponentInstanceDiagram Bench
{{
    import ToF.*;
    Camera instantiates {camera}
    {{
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target {black}.In.frame ]
    }}
    {black_stage}
    Motion instantiates MotionCompensation (windowSize = 5, threshold = 1, directionRestriction = 0)
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }}
    Demod instantiates Demodulation (modulationFrequency = 20)
    {{
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Depth.In.depth ]
    }}
    Depth instantiates NpyWriter (amplitude = false)
    {{
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }}
}}
"
    )
}

struct Quiet;

impl PipelineObserver for Quiet {
    fn frame(&mut self, _index: usize, _frames: usize) {}
}

/// A whole run of the pipeline `Bench` of `text`, at most `frames` frames, without reading
/// its files.
pub fn run_model(gpu: Option<&Gpu>, text: &str, frames: Option<usize>, out: &Path) -> Duration {
    let started = Instant::now();
    let db = RootDatabase::default();
    let mut files = library::library_files(&db);
    files.push(SourceFile::new(&db, "bench.gudsl".into(), text.to_string()));
    let workspace = Workspace::new(&db, files);
    let plan = pipeline_plan(&db, workspace, Fqn::new(&db, "Bench".to_string())).clone().expect("the plan");
    assert!(plan.diagnostics.is_empty(), "{:?}", plan.diagnostics);
    let behaviors = pipeline::behaviors(&Semantics::new(&db, workspace), &plan);
    // The recordings it reads lie in the temporary folder.
    let files = Access::new(vec![std::env::temp_dir()], true).files(&std::env::temp_dir());
    let mut prepared = pipeline::prepare(&plan, &behaviors, &files).unwrap_or_else(|e| panic!("{e:?}"));
    let mut output = OutputDir::named(out).unwrap();
    let report = prepared.run(gpu, &mut output, frames, &mut Quiet, &AtomicBool::new(false));
    report.outcome.unwrap();
    started.elapsed() - report.loading
}

/// `RECORDED_FRAMES` simulated frames, recorded as channel files `a.npy` and `b.npy` in `dir`.
pub fn record(width: usize, height: usize, dir: &Path) {
    let camera = Camera { intrinsics: Intrinsics::camcube_at(width, height), ..Camera::default() };
    let frames: Vec<Image> = (0..RECORDED_FRAMES).map(|f| simulate(&Scene::sphere(), MOTION, &camera, f).raw).collect();
    std::fs::create_dir_all(dir).unwrap();
    for (name, first) in [("a.npy", 0), ("b.npy", 1)] {
        let data: Vec<f32> =
            frames.iter().flat_map(|f| (0..4).flat_map(move |p| f.plane(2 * p + first).to_vec())).collect();
        arrays::write(&dir.join(name), &[RECORDED_FRAMES, 4, height, width], &data, arrays::Dtype::U16).unwrap();
    }
}
