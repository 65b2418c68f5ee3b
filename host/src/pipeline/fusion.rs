//! Fusion across stages: which stages' kernels run inside the kernels of the stages they feed.
//! One kind today: a black-image correction whose every binding out leads, in order, to a stage
//! that takes frames owing their black image (a demodulation; a motion compensation with a
//! phase calibration, in its normalization) gives its frames owing it
//! ([`RawFrame::black_owed`]), and each of those stages takes it off in its own first pass — a
//! dispatch, and a write and a read of the 8-plane frame, fewer a frame, the same results bit
//! for bit. Where anything else reads its frames (motion compensation's search without a
//! calibration reads each sample many times, a sink reads the corrected frame) it keeps its
//! own kernel. Decided once, where a pipeline is prepared; [`PreparedPipeline::unfused`] runs
//! each stage's own kernels.
//!
//! [`RawFrame::black_owed`]: super::data::RawFrame::black_owed
//! [`PreparedPipeline::unfused`]: super::PreparedPipeline::unfused

use gudsl_model::hir::pipeline::PipelinePlan;

use super::{apart::Mode, components::Component};

/// For each stage, the stages its kernel runs inside (none: it runs its own), with each
/// component told (`fuse` false: every stage runs its own).
pub fn decide(
    plan: &PipelinePlan,
    components: &mut [Option<Box<dyn Component>>],
    modes: &[Mode],
    fuse: bool,
) -> Vec<Vec<usize>> {
    (0..plan.stages.len())
        .map(|index| {
            let owe = fuse && feeds_only_stages_taking_owed_black(plan, components, modes, index);
            let owes = components[index].as_mut().is_some_and(|component| component.owe_black(owe));
            let mut inside: Vec<usize> = match owes {
                true => plan.bindings.iter().filter(|b| b.provider.stage == index).map(|b| b.processor.stage).collect(),
                false => Vec::new(),
            };
            inside.sort_unstable();
            inside.dedup();
            inside
        })
        .collect()
}

/// Whether every binding out of stage `index` (one at least) is a plain one (neither `async`
/// nor buffered) into a stage that runs in order and takes frames owing their black image.
fn feeds_only_stages_taking_owed_black(
    plan: &PipelinePlan,
    components: &[Option<Box<dyn Component>>],
    modes: &[Mode],
    index: usize,
) -> bool {
    let mut out = plan.bindings.iter().filter(|b| b.provider.stage == index).peekable();
    out.peek().is_some()
        && out.all(|b| {
            let into = b.processor.stage;
            !b.is_async
                && !b.is_buffered
                && modes[into] == Mode::InOrder
                && components[into].as_ref().is_some_and(|component| component.takes_owed_black())
        })
}

#[cfg(test)]
mod tests {
    use std::{path::PathBuf, sync::atomic::AtomicBool};

    use gudsl_model::AnalysisHost;
    use gudsl_runtime::Gpu;

    use crate::pipeline::{
        preview::{Preview, Quiet},
        OutputDir, PipelineReport, Preparations, PreparedPipeline,
    };

    /// A camera's frames, their black image taken off, demodulated and written as `.npy`; with
    /// `tap`, the corrected frames written too (a `RawWriter` reads them as they are).
    fn model(tap: bool) -> String {
        let (binding, writer) = match tap {
            true => (
                "[ source Out.frame ==> target Raw.In.frame ]",
                "Raw instantiates RawWriter ( ) { In : RawIn ( processor frame = IRawFrameProcessor() ); }",
            ),
            false => ("", ""),
        };
        with(binding, writer)
    }

    /// [`model`] with motion compensation on the corrected frames too, its normalised channels
    /// written and its compensated frames demodulated (a stage that would take a frame owing
    /// its black image: none must reach it); with a phase calibration (`calibrated`) or without.
    fn motion_model(calibrated: bool) -> String {
        std::fs::create_dir_all(dir()).unwrap();
        let (width, height) = (64, 48);
        // f(X) = 0.5·√(X + 20) + 1.1·X + 3 for tap A, 1.3·X for tap B.
        let curves = [0.5, 20.0, 1.1, 3.0, 0.0, 0.0, 1.3, 0.0];
        let calibration: Vec<f32> = curves.iter().flat_map(|&v| vec![v; width * height]).collect();
        let path = dir().join("calibration.npy");
        gudsl_formats::arrays::write(&path, &[8, height, width], &calibration, gudsl_formats::arrays::Dtype::F32)
            .unwrap();
        let calibration = if calibrated { "phaseCalibration = \"calibration.npy\"" } else { "" };
        let raw_in = "In : RawIn ( processor frame = IRawFrameProcessor() );";
        let motion = format!(
            "Motion instantiates MotionCompensation ({calibration})
            {{
                {raw_in}
                Out : RawOut ( provider frame = IRawFrameProvider() );
                Normalized : NormalizedOut ( provider frame = IRawFrameProvider() );
                [ source Out.frame ==> target Compensated.In.frame ]
                [ source Normalized.frame ==> target Normalised.In.frame ]
            }}
            Compensated instantiates Demodulation ( )
            {{
                {raw_in}
                Out : DepthOut ( provider depth = IDepthImageProvider() );
                [ source Out.depth ==> target Depth.In.depth ]
            }}
            Normalised instantiates RawWriter ( ) {{ {raw_in} }}"
        );
        with("[ source Out.frame ==> target Motion.In.frame ]", &motion)
    }

    /// The camera, correction, demodulation and writer, with `binding` out of the correction
    /// and `stages` beside them.
    fn with(binding: &str, stages: &str) -> String {
        format!(
            "ComponentInstanceDiagram Fused
            {{
                import ToF.*;
                Camera instantiates SimulatedCamera (scene = Scene.Sphere, frames = 3, width = 64, height = 48)
                {{
                    Out : RawOut ( provider frame = IRawFrameProvider() );
                    [ source Out.frame ==> target Black.In.frame ]
                }}
                Black instantiates BlackImageCorrection ( )
                {{
                    In : RawIn ( processor frame = IRawFrameProcessor() );
                    Out : RawOut ( provider frame = IRawFrameProvider() );
                    [ source Out.frame ==> target Demod.In.frame ]
                    {binding}
                }}
                Demod instantiates Demodulation ( )
                {{
                    In : RawIn ( processor frame = IRawFrameProcessor() );
                    Out : DepthOut ( provider depth = IDepthImageProvider() );
                    [ source Out.depth ==> target Depth.In.depth ]
                }}
                Depth instantiates NpyWriter (amplitude = true)
                {{
                    In : DepthIn ( processor depth = IDepthImageProcessor() );
                }}
                {stages}
            }}"
        )
    }

    fn dir() -> PathBuf {
        std::env::temp_dir().join(format!("gudsl-fusion-{}", std::process::id()))
    }

    fn prepared(text: String) -> PreparedPipeline {
        let (host, _) = AnalysisHost::with_files([(dir().join("fused.gudsl").display().to_string(), text)]);
        let analysis = host.analysis();
        let plan = analysis.pipeline_plan("Fused").unwrap().expect("a pipeline");
        Preparations::default().take_for(&analysis, &plan).unwrap().expect("it runs")
    }

    /// `prepared` run on `gpu` (the CPU reference without) into `out`: its report and the files
    /// it wrote, by path under `out`.
    fn run(mut prepared: PreparedPipeline, gpu: Option<&Gpu>, out: &str) -> (PipelineReport, Vec<(PathBuf, Vec<u8>)>) {
        let folder = dir().join(out);
        let mut output = OutputDir::named(&folder).unwrap();
        let report = prepared.run(gpu, &mut output, None, &mut Quiet, &AtomicBool::new(false));
        assert!(report.outcome.is_ok(), "{:?}", report.outcome);
        let files = (report.outputs.iter())
            .map(|p| (p.strip_prefix(&folder).unwrap_or(p).to_path_buf(), std::fs::read(folder.join(p)).unwrap()))
            .collect();
        (report, files)
    }

    fn fused_into(report: &PipelineReport) -> Vec<(&str, Vec<&str>)> {
        let stages = report.stages.iter().filter(|s| !s.fused_into.is_empty());
        stages.map(|s| (s.instance.as_str(), s.fused_into.iter().map(String::as_str).collect())).collect()
    }

    /// Fed only by stages that take its frames owing their black image — a demodulation, and
    /// a motion compensation with a phase calibration — the correction runs inside their
    /// kernels: the same files byte for byte as each stage running its own kernel, one dispatch
    /// a frame fewer on a GPU; on the CPU reference alike.
    #[test]
    fn a_black_correction_feeding_only_stages_that_take_its_frames_owing_runs_inside_them() {
        let gpu = Gpu::for_tests();
        let cases = [
            (model(false), vec!["Demod"], 6, (3, 6)),
            // Demodulation, normalization, detection and matching, correction, demodulation; 3
            // frames of 6 files.
            (motion_model(true), vec!["Demod", "Motion"], 18, (15, 18)),
        ];
        for (text, inside, files, dispatches) in cases {
            for (gpu, on) in [(gpu.as_ref(), "gpu"), (None, "cpu")] {
                let out = format!("{}-{on}", inside.len());
                let (fused, fused_files) = run(prepared(text.clone()), gpu, &format!("fused-{out}"));
                let mut unfused = prepared(text.clone());
                unfused.unfused();
                let (apart, apart_files) = run(unfused, gpu, &format!("apart-{out}"));
                assert_eq!(fused_into(&fused), [("Black", inside.clone())]);
                let said = match inside.len() {
                    1 => "runs in Demod's kernel",
                    _ => "runs in Demod's and Motion's kernels",
                };
                assert!(crate::pipeline::table(&fused).contains(said), "{}", crate::pipeline::table(&fused));
                assert!(fused_into(&apart).is_empty());
                let names = |files: &[(PathBuf, Vec<u8>)]| files.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
                assert_eq!(fused_files.len(), files, "{:?}", names(&fused_files));
                assert_eq!(names(&fused_files), names(&apart_files));
                assert!(fused_files == apart_files, "{on} {inside:?}: the files differ");
                if gpu.is_some() {
                    assert_eq!((fused.dispatches(), apart.dispatches()), dispatches, "{inside:?}");
                    assert_eq!(fused.stages[1].dispatches, 0, "the correction's own kernel never ran");
                }
            }
        }
    }

    /// Where anything else reads the corrected frames (a sink; motion compensation's search
    /// without a calibration, here and in chapter 4's sample), the correction runs its own
    /// kernel.
    #[test]
    fn a_black_correction_read_by_anything_else_runs_its_own_kernel() {
        assert!(prepared(model(true)).fused_into.iter().all(Vec::is_empty));
        assert!(prepared(motion_model(false)).fused_into.iter().all(Vec::is_empty));
        let sample = include_str!("../../../samples/pipelines/ch4_motion_compensation.gudsl");
        let (host, _) = AnalysisHost::with_files([(dir().join("ch4.gudsl").display().to_string(), sample.into())]);
        let analysis = host.analysis();
        let plan = analysis.pipeline_plan("MotionCompensationPipeline").unwrap().expect("a pipeline");
        let ch4 = Preparations::default().take_for(&analysis, &plan).unwrap().expect("it runs");
        assert!(ch4.fused_into.iter().all(Vec::is_empty));
    }

    /// A preview whose correction ran inside the demodulation, then a tap added on its frames:
    /// the correction runs again, its own kernel (what it gave before owed the black image),
    /// and the tap writes what a preview that ran everything writes.
    #[test]
    fn a_tap_on_a_fused_correction_runs_it_again_in_a_preview() {
        let mut live = Preview::new(None);
        let preview = |live: &mut Preview, tap: bool, out: &str| {
            let mut output = OutputDir::named(&dir().join(out)).unwrap();
            let report = live.run(prepared(model(tap)), 2, &mut output, &AtomicBool::new(false));
            assert!(report.outcome.is_ok(), "{:?}", report.outcome);
            let raw: Vec<Vec<u8>> = (report.outputs.iter())
                .filter(|p| p.components().any(|c| c.as_os_str() == "Raw"))
                .map(|p| std::fs::read(dir().join(out).join(p)).unwrap())
                .collect();
            (report.replayed().map(String::from).collect::<Vec<_>>(), raw)
        };
        preview(&mut live, false, "first");
        let (replayed, raw) = preview(&mut live, true, "tapped");
        assert_eq!(replayed, ["Camera"]);
        let (_, control) = preview(&mut Preview::new(None), true, "control");
        assert!(!raw.is_empty() && raw == control, "the tap writes the corrected frames");
    }
}
