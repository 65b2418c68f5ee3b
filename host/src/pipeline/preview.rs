//! The live preview of a pipeline: run again on a window of its first frames each time its
//! model changes, on one device kept from run to run, every stage in order (a window is too
//! short for `async` stages to gain anything), and only the stages the change reached run —
//! the others replay what they gave in the last whole preview ([`replay`](super::replay)).

use std::sync::atomic::AtomicBool;

use gudsl_runtime::Gpu;

use super::{
    apart::Mode,
    replay::{Kept, Replay},
    OutputDir, PipelineObserver, PipelineReport, PreparedPipeline,
};

/// A pipeline's preview: its device, and what its last whole run gave.
pub struct Preview {
    gpu: Option<Gpu>,
    kept: Kept,
}

impl Preview {
    /// A preview on `gpu` (the CPU reference without one), with nothing kept yet.
    pub fn new(gpu: Option<Gpu>) -> Preview {
        Preview { gpu, kept: Kept::default() }
    }

    /// Runs `prepared` on its first `window` frames (at least one, at most its frames),
    /// writing under `output`, stopping when `cancel` is set. What a whole run gave is kept
    /// for the next; a cancelled or failed one keeps the last. The report's stages say which
    /// replayed ([`PipelineReport::replayed`]).
    pub fn run(
        &mut self,
        mut prepared: PreparedPipeline,
        window: usize,
        output: &mut OutputDir,
        cancel: &AtomicBool,
    ) -> PipelineReport {
        let frames = window.clamp(1, prepared.frames.max(1));
        prepared.modes.iter_mut().for_each(|mode| *mode = Mode::InOrder);
        prepared.replay = Some(Replay::after(&self.kept, &prepared.plan, &prepared.keys, frames));
        let mut report = prepared.run(self.gpu.as_ref(), output, Some(frames), &mut Quiet, cancel);
        let replay = prepared.replay.take().expect("set above");
        report.figures.extend(replay.figures(&self.kept, &prepared.plan));
        let position = |stage: &str| prepared.plan.stages.iter().position(|s| s.instance == stage);
        report.figures.sort_by_key(|figure| position(&figure.stage));
        if report.outcome.is_ok() {
            let kept = std::mem::take(&mut self.kept);
            self.kept = replay.keep(kept, (&prepared.plan, &prepared.keys), frames, &report.figures);
        }
        report
    }
}

/// An observer told no progress: a preview's (it is one window long), a test's.
pub(super) struct Quiet;

impl PipelineObserver for Quiet {
    fn frame(&mut self, _: usize, _: usize) {}
}

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use gudsl_model::AnalysisHost;

    use super::*;
    use crate::pipeline::Preparations;

    /// Chapter 4's sample, small, with motion compensation's threshold `theta` and the camera's
    /// `speed`.
    fn model(theta: u32, speed: u32) -> String {
        include_str!("../../../samples/pipelines/ch4_motion_compensation.gudsl")
            .replace("speed = 1, frames = 6", &format!("speed = {speed}, frames = 6, width = 64, height = 48"))
            .replace("threshold = 1,", &format!("threshold = {theta},"))
    }

    fn dir() -> PathBuf {
        std::env::temp_dir().join(format!("gudsl-preview-{}", std::process::id()))
    }

    fn prepared(text: String) -> PreparedPipeline {
        let (host, _) = AnalysisHost::with_files([(dir().join("ch4.gudsl").display().to_string(), text)]);
        let analysis = host.analysis();
        let plan = analysis.pipeline_plan("MotionCompensationPipeline").unwrap().expect("a pipeline");
        Preparations::default().take_for(&analysis, &plan).unwrap().expect("it runs")
    }

    /// Previews `text` on its first 2 frames, into the folder `out`.
    fn preview(live: &mut Preview, text: String, out: &str) -> PipelineReport {
        let mut output = OutputDir::named(&dir().join(out)).unwrap();
        let report = live.run(prepared(text), 2, &mut output, &AtomicBool::new(false));
        assert!(report.outcome.is_ok(), "{:?}", report.outcome);
        report
    }

    fn figures(report: &PipelineReport) -> Vec<(String, String, f64)> {
        report.figures.iter().map(|f| (f.stage.clone(), f.name.clone(), f.value)).collect()
    }

    fn replayed(report: &PipelineReport) -> Vec<&str> {
        report.replayed().collect()
    }

    fn mean_cm(report: &PipelineReport, series: &str) -> f64 {
        let name = format!("{series} mean_cm");
        report.figures.iter().find(|f| f.name == name).map(|f| f.value).expect("measured")
    }

    /// A parameter of motion compensation runs it and what is downstream of it, and the camera,
    /// the black image correction and the uncompensated chain replay the last preview; the
    /// figures are those of a preview that ran everything (the control).
    #[test]
    fn a_later_stage_s_parameter_runs_only_what_is_downstream_of_it() {
        let mut live = Preview::new(None);
        let first = preview(&mut live, model(1, 1), "first");
        assert!(replayed(&first).is_empty(), "{:?}", replayed(&first));
        assert_eq!(first.frames, 2);
        let tuned = preview(&mut live, model(40, 1), "tuned");
        assert_eq!(replayed(&tuned), ["Camera", "Black", "Uncompensated"]);
        assert_eq!(mean_cm(&tuned, "Uncompensated"), mean_cm(&first, "Uncompensated"));
        assert_ne!(mean_cm(&tuned, "Compensated"), mean_cm(&first, "Compensated"));
        let control = preview(&mut Preview::new(None), model(40, 1), "control");
        assert!(replayed(&control).is_empty());
        assert_eq!(figures(&tuned), figures(&control));
        assert!(tuned.outputs.iter().any(|p| p.extension().is_some_and(|e| e == "png")), "the sinks ran");
        // A camera's parameter reaches every stage.
        let moved = preview(&mut live, model(40, 2), "moved");
        assert!(replayed(&moved).is_empty(), "{:?}", replayed(&moved));
        assert_ne!(mean_cm(&moved, "Uncompensated"), mean_cm(&tuned, "Uncompensated"));
    }

    /// A cancelled preview keeps what the last whole one gave: the next replays from it.
    #[test]
    fn a_cancelled_preview_keeps_the_last_whole_one() {
        let mut live = Preview::new(None);
        preview(&mut live, model(1, 1), "whole");
        let mut output = OutputDir::named(&dir().join("cancelled")).unwrap();
        let cancelled = live.run(prepared(model(40, 2)), 2, &mut output, &AtomicBool::new(true));
        assert!(cancelled.outcome.is_err());
        let again = preview(&mut live, model(20, 1), "again");
        assert_eq!(replayed(&again), ["Camera", "Black", "Uncompensated"]);
    }
}
