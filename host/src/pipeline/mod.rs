//! ToF pipelines modelled as component-instance diagrams, run on the runtime: each stage of the
//! model's [`PipelinePlan`] becomes a component of the bundled `ToF` library
//! (`components/`), frames flow through them in the plan's order, their images stay on the
//! GPU between stages (the runtime's [`Executor`]: one encoder a frame, kernels bound once, one
//! readback at the end of a frame for everything the sinks and stages asked for), and what the sinks write
//! goes under one output folder only.
//!
//! Frames are ticks: every source gives one item a frame (until its frames are done), a filter
//! processes each item that arrived on its ports this frame, a binding into a `buffered` port
//! delivers its items a frame later (queueing up to its buffer size), so such a binding may
//! close a loop (chapter 5.4). A stage bound through an `async` port does not block its
//! producers (Sec. 11.4.3, [`apart`]): a sink's work after the frame's reads (encoding, writing
//! files) runs on a thread while the next frame goes on, a filter's frame on a thread while the
//! stages that do not wait for it go on.

mod apart;
mod carries;
mod components;
pub mod data;
mod error;
mod files;
mod frames;
mod fusion;
mod on_graph;
mod preparations;
mod prepare;
mod preview;
mod replay;
mod report;
mod sizes;
mod study;
mod walls;

use std::{
    sync::atomic::AtomicBool,
    thread::JoinHandle,
    time::{Duration, Instant},
};

use gudsl_model::{ast::ClassKind, hir::pipeline::PipelinePlan};
pub(crate) use gudsl_runtime::executor;
use gudsl_runtime::{Executor, Gpu};

pub use crate::output::OutputDir;
use apart::{Mode, Written};
use components::Component;
pub use components::{behaviors, Behaviors};
pub use error::{ErrorKind, PipelineError};
pub use on_graph::annotate;
pub use preparations::{model_dir, Preparations};
pub use prepare::prepare;
pub use preview::Preview;
pub use replay::StageKey;
pub use report::{
    report_json, summary, table, write_report, Figure, Flow, FrameSpan, FrameWork, PipelineReport, StageTime,
};
pub use study::{rows_beneath, study_table, write_study, StudyRow};
pub use walls::calibration_walls;

/// The GPU a pipeline runs on: the first adapter, its kernels timed where it has timestamp
/// queries; `None`, the CPU reference, with `cpu` or when there is no adapter (`no_adapter`
/// told why).
pub fn gpu(cpu: bool, no_adapter: impl FnOnce(String)) -> Option<Gpu> {
    if cpu {
        return None;
    }
    Gpu::with_timestamps().map_err(|error| no_adapter(error.to_string())).ok()
}

/// Told about a run's progress.
pub trait PipelineObserver {
    /// Frame `index` (from 0) of `frames` is done.
    fn frame(&mut self, index: usize, frames: usize);
}

/// A plan with a component for each stage, ready to run.
pub struct PreparedPipeline {
    plan: PipelinePlan,
    /// Each stage's component, `None` while a writer thread has it.
    components: Vec<Option<Box<dyn Component>>>,
    /// The `async` sinks' writers at work.
    writers: Vec<Option<JoinHandle<Written>>>,
    /// How each stage runs: in order, or apart (bound through an `async` port).
    modes: Vec<Mode>,
    frames: usize,
    /// Settings that cannot act in it (E0406 warnings); it runs nonetheless.
    pub warnings: Vec<PipelineError>,
    /// What each stage's items depend on, for a preview's replay.
    keys: Vec<replay::StageKey>,
    /// In a preview: the stages that replay a kept run, and what the others give, recorded.
    replay: Option<replay::Replay>,
    /// What each binding carried in this run.
    flows: Vec<Flow>,
    /// Command buffers submitted to the GPU in this run, by frame.
    submissions: Vec<usize>,
    /// When each frame of this run began and was done.
    frame_spans: Vec<FrameSpan>,
    /// Whether frames may overlap on a GPU (on unless [`PreparedPipeline::one_frame_at_a_time`]).
    overlap: bool,
    /// For each stage, the stages its kernel runs inside ([`fusion`]; none: its own).
    fused_into: Vec<Vec<usize>>,
}

impl PreparedPipeline {
    /// The diagram it runs (fully qualified).
    pub fn diagram(&self) -> &str {
        &self.plan.diagram
    }

    /// What each stage's items depend on: two pipelines with the same keys give the same.
    pub fn keys(&self) -> &[StageKey] {
        &self.keys
    }

    /// The frames the sources give (the longest source).
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Runs its frames one after another, never the next recorded while the GPU works on
    /// one (the same results, slower: for comparing).
    pub fn one_frame_at_a_time(&mut self) {
        self.overlap = false;
    }

    /// Runs each stage's own kernels, none inside another's (the same results, more dispatches:
    /// for comparing).
    pub fn unfused(&mut self) {
        self.fuse(false);
    }

    /// Runs stages' kernels inside the stages they feed where [`fusion`] allows it (`fuse`),
    /// or none; the components told, the replay's keys kept in step.
    fn fuse(&mut self, fuse: bool) {
        self.fused_into = fusion::decide(&self.plan, &mut self.components, &self.modes, fuse);
        for (key, inside) in self.keys.iter_mut().zip(&self.fused_into) {
            key.runs_inside(inside);
        }
    }

    /// The same pipeline placed where `plan` (its plan but for the ranges) sits: its errors
    /// point there.
    pub(crate) fn move_to(&mut self, plan: &PipelinePlan) {
        self.plan = plan.clone();
    }

    /// Runs at most `frames` frames (all without) on `gpu` (the CPU reference without one),
    /// writing under `output`; stops between frames when `cancel` is set.
    pub fn run(
        &mut self,
        gpu: Option<&Gpu>,
        output: &mut OutputDir,
        frames: Option<usize>,
        observer: &mut dyn PipelineObserver,
        cancel: &AtomicBool,
    ) -> PipelineReport {
        let frames = frames.map_or(self.frames, |n| n.min(self.frames));
        let start = Instant::now();
        let mut stages: Vec<StageTime> = self
            .plan
            .stages
            .iter()
            .zip(&self.modes)
            .enumerate()
            .map(|(index, (s, mode))| StageTime {
                instance: s.instance.clone(),
                class: s.class.clone(),
                host: Duration::ZERO,
                device: Duration::ZERO,
                dispatches: 0,
                items: 0,
                source: self.components[index].as_ref().is_some_and(|c| c.frames().is_some()),
                apart: *mode != Mode::InOrder,
                failed: None,
                replayed: self.replay.as_ref().is_some_and(|replay| replay.replays(index)),
                frames: Vec::new(),
                fused_into: self.fused_into[index].iter().map(|&s| self.plan.stages[s].instance.clone()).collect(),
            })
            .collect();
        self.flows = self.plan.bindings.iter().map(|b| self.flow(b)).collect();
        self.submissions.clear();
        self.frame_spans.clear();
        let mut device = Executor::new(gpu);
        let loading = Instant::now();
        let outcome = self.load(&mut stages);
        let loading = loading.elapsed();
        let outcome =
            outcome.and_then(|()| self.frames_loop(&mut device, output, frames, &mut stages, observer, cancel));
        // Nothing goes on writing after a run, even a cancelled or failed one: every writer is
        // joined, and the first problem is the run's.
        let mut outcome = outcome;
        for (index, time) in stages.iter_mut().enumerate() {
            let joined = self.join(index, output, time);
            let joined = self.sink_alone(index, time, joined);
            if outcome.is_ok() {
                outcome = joined;
            }
        }
        // What the sinks write once is written after a failed or cancelled run too: the
        // frames that ran are not lost.
        let finished = self.finish(output, &mut stages);
        let outcome = outcome.and(finished);
        let figures = self.figures(&stages);
        PipelineReport {
            diagram: self.plan.diagram.clone(),
            setting: Vec::new(),
            device: gpu.map_or_else(|| "the CPU reference".to_string(), Gpu::describe),
            frames,
            total: start.elapsed(),
            loading,
            stages,
            outputs: output.written().to_vec(),
            figures,
            flows: std::mem::take(&mut self.flows),
            frame_submissions: std::mem::take(&mut self.submissions),
            frame_spans: std::mem::take(&mut self.frame_spans),
            overlapped: self.overlaps(gpu.is_some()),
            outcome,
        }
    }

    /// Nothing yet carried through `binding`.
    fn flow(&self, binding: &gudsl_model::hir::pipeline::PlanBinding) -> Flow {
        let instance = |stage: usize| self.plan.stages[stage].instance.clone();
        Flow {
            provider: instance(binding.provider.stage),
            provider_port: format!("{}.{}", binding.provider.port_instance, binding.provider.connector),
            processor: instance(binding.processor.stage),
            processor_port: format!("{}.{}", binding.processor.port_instance, binding.processor.connector),
            items: 0,
            carries: None,
        }
    }

    /// What the stages that did not fail measured.
    fn figures(&self, times: &[StageTime]) -> Vec<Figure> {
        let replays = |index| self.replay.as_ref().is_some_and(|replay| replay.replays(index));
        let measured = self.components.iter().zip(times).enumerate();
        let measured = measured.filter(|(index, (_, time))| time.failed.is_none() && !replays(*index));
        let by_stage = measured.filter_map(|(_, (component, time))| Some((component.as_ref()?, &time.instance)));
        by_stage
            .flat_map(|(component, stage)| {
                component.figures().into_iter().map(|(name, value)| Figure { stage: stage.clone(), name, value })
            })
            .collect()
    }

    /// Stage `index`'s component back from its writer, if one has it: its files listed in
    /// `output`, its time in `time`, its failure returned.
    fn join(&mut self, index: usize, output: &mut OutputDir, time: &mut StageTime) -> Result<(), PipelineError> {
        let Some(writer) = self.writers[index].take() else { return Ok(()) };
        let written = writer.join().map_err(|panic| {
            let why = apart::panic_message(&*panic);
            // Its component is lost with the thread: this pipeline cannot run again.
            self.error(Some(index), ErrorKind::Failed, format!("its writer thread panicked: {why}"))
        })?;
        self.components[index] = Some(written.component);
        output.absorb(written.output);
        time.add_host(written.frame, written.took);
        written.result.map_err(|message| self.error(Some(index), ErrorKind::Failed, message))
    }

    /// Before the first frame: the files the components read.
    fn load(&mut self, times: &mut [StageTime]) -> Result<(), PipelineError> {
        for (index, time) in times.iter_mut().enumerate() {
            if self.replay.as_ref().is_some_and(|replay| replay.replays(index)) {
                continue; // its files were read for the run it replays
            }
            let started = Instant::now();
            let Some(component) = self.components[index].as_mut() else {
                let message = "its component was lost when its writer panicked in an earlier run".to_string();
                return Err(self.error(Some(index), ErrorKind::Failed, message));
            };
            let loaded = component.load().map_err(|message| self.error(Some(index), ErrorKind::Input, message));
            time.host += started.elapsed();
            self.sink_alone(index, time, loaded)?;
        }
        Ok(())
    }

    /// After the last frame: what sinks write once (a plot, the last cloud). Components lost
    /// with a panicked thread and failed sinks write nothing more.
    fn finish(&mut self, output: &mut OutputDir, times: &mut [StageTime]) -> Result<(), PipelineError> {
        for (index, time) in times.iter_mut().enumerate() {
            let Some(component) = self.components[index].as_mut().filter(|_| time.failed.is_none()) else {
                continue;
            };
            let started = Instant::now();
            let finished =
                component.finish_run(output).map_err(|message| self.error(Some(index), ErrorKind::Output, message));
            time.host += started.elapsed();
            self.sink_alone(index, time, finished)?;
        }
        Ok(())
    }

    /// A sink's failure is its own: kept on its stage (it runs no more this run) while the run
    /// goes on; anything else's, and a cancellation, stops the run.
    fn sink_alone(
        &self,
        index: usize,
        time: &mut StageTime,
        result: Result<(), PipelineError>,
    ) -> Result<(), PipelineError> {
        self.sink_alone_or(index, time, result).map(|_| ())
    }

    /// [`Self::sink_alone`] for a result with a value: `None` when the sink failed.
    fn sink_alone_or<T>(
        &self,
        index: usize,
        time: &mut StageTime,
        result: Result<T, PipelineError>,
    ) -> Result<Option<T>, PipelineError> {
        match result {
            Ok(value) => Ok(Some(value)),
            Err(error) if self.plan.stages[index].kind == ClassKind::Sink && error.kind != ErrorKind::Cancelled => {
                time.failed = Some(error);
                Ok(None)
            }
            Err(error) => Err(error),
        }
    }

    fn error(&self, stage: Option<usize>, kind: ErrorKind, message: String) -> PipelineError {
        let stage = stage.map(|s| &self.plan.stages[s]);
        PipelineError { kind, stage: stage.map(|s| s.instance.clone()), range: stage.map(|s| s.range), message }
    }
}
