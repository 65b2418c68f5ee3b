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
    collections::VecDeque,
    sync::atomic::{AtomicBool, Ordering},
    thread::{JoinHandle, Scope, ScopedJoinHandle},
    time::{Duration, Instant},
};

use gudsl_model::{ast::ClassKind, hir::pipeline::PipelinePlan};
pub(crate) use gudsl_runtime::executor;
use gudsl_runtime::{executor::Reads, Executor, Gpu, Work};

pub use crate::output::OutputDir;
use apart::{Mode, Processed, Written};
pub use components::{behaviors, Behaviors};
use components::{Component, Inputs, Outputs};
use data::Item;
pub use error::{ErrorKind, PipelineError};
pub use on_graph::annotate;
pub use preparations::{model_dir, Preparations};
pub use prepare::prepare;
pub use preview::Preview;
pub use replay::StageKey;
pub use report::{report_json, summary, table, write_report, Figure, Flow, PipelineReport, StageTime};
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

/// Where a frame is: the run's device, the devices of stages that process apart, the
/// bindings' queues, the output folder, the stages' times, the frame's index.
struct At<'a, 'g> {
    device: &'a mut Executor<'g>,
    devices: &'a mut [Option<Executor<'g>>],
    queues: &'a mut [VecDeque<Item>],
    output: &'a mut OutputDir,
    times: &'a mut [StageTime],
    frame: usize,
    cancel: &'a AtomicBool,
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
    /// Command buffers submitted to the GPU in this run.
    submissions: usize,
    /// The wall time of each frame of this run.
    frame_times: Vec<Duration>,
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
            })
            .collect();
        self.flows = self.plan.bindings.iter().map(|b| self.flow(b)).collect();
        self.submissions = 0;
        self.frame_times.clear();
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
            submissions: self.submissions,
            frame_times: std::mem::take(&mut self.frame_times),
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

    fn frames_loop<'g>(
        &mut self,
        device: &mut Executor<'g>,
        output: &mut OutputDir,
        frames: usize,
        times: &mut [StageTime],
        observer: &mut dyn PipelineObserver,
        cancel: &AtomicBool,
    ) -> Result<(), PipelineError> {
        // Items waiting on each binding: a frame's own, or a buffered port's queue.
        let mut queues: Vec<VecDeque<Item>> = vec![VecDeque::new(); self.plan.bindings.len()];
        // The devices of the stages that process apart, kept from frame to frame.
        let mut devices: Vec<Option<Executor<'g>>> = self.modes.iter().map(|_| None).collect();
        for frame in 0..frames {
            let frame_started = Instant::now();
            if cancel.load(Ordering::Relaxed) {
                return Err(self.error(
                    None,
                    ErrorKind::Cancelled,
                    format!("cancelled after {frame} of {frames} frames"),
                ));
            }
            let mut at = At { device, devices: &mut devices, queues: &mut queues, output, times, frame, cancel };
            let reads = std::thread::scope(|scope| {
                let mut running = Vec::new();
                let mut outcome = self.stages(scope, &mut at, &mut running).and_then(|()| {
                    at.device
                        .end_frame()
                        .map_err(|e| self.error(None, ErrorKind::Failed, format!("frame {frame}: {e}")))
                });
                // Nothing runs on past its frame, even a failed one: every thread is joined,
                // and the first problem is the frame's.
                for (index, thread) in running {
                    let joined = self.take_back(index, thread, &mut at);
                    outcome = outcome.and_then(|reads| joined.map(|()| reads));
                }
                outcome
            });
            let (reads, kernel_times) = reads?;
            for (stage, time) in kernel_times {
                at.times[stage].device += time;
            }
            self.count(at.device.take_work(), at.times);
            self.finish_reads(&mut at, &reads)?;
            self.frame_times.push(frame_started.elapsed());
            observer.frame(frame, frames);
        }
        Ok(())
    }

    /// Each stage's `finish_frame` on frame `at.frame`'s reads, in the plan's order: an `async`
    /// writer's on its thread, a replayed stage's given again; what a stage gives then arrives
    /// next frame.
    fn finish_reads(&mut self, at: &mut At<'_, '_>, reads: &Reads) -> Result<(), PipelineError> {
        let frame = at.frame;
        for index in 0..at.times.len() {
            let time = &mut at.times[index];
            if time.failed.is_some() {
                continue;
            }
            let mode = self.modes[index];
            match mode {
                // Joined before this frame's `process`.
                Mode::WritesApart => {
                    let component = self.components[index].take().expect("joined");
                    let thread = apart::write(component, index, frame, reads.clone(), at.output.fork());
                    self.writers[index] = Some(thread);
                    continue;
                }
                Mode::ProcessesApart => continue, // its finish_frame ran on its thread
                Mode::InOrder if self.replayed(at.device, index, at.queues, frame, true) => continue,
                Mode::InOrder => {}
            }
            let started = Instant::now();
            let mut ctx =
                components::Ctx { device: at.device, stage: index, frame, output: at.output, cancel: at.cancel };
            let produced = self.components[index]
                .as_mut()
                .expect("joined")
                .finish_frame(&mut ctx, reads)
                .map_err(|message| self.error(Some(index), ErrorKind::Failed, message));
            time.host += started.elapsed();
            let Some(produced) = self.sink_alone_or(index, time, produced)? else { continue };
            self.record(at.device, (index, frame), &produced, true);
            // What a stage gives after the frame's reads arrives next frame.
            self.deliver(at.device, index, produced, at.queues, frame, true);
        }
        Ok(())
    }

    /// Each stage's `process` in frame `at.frame`, in the plan's order, but a stage that
    /// processes apart goes on its thread in `scope` (`running`) and the stages that do not
    /// wait for it go on meanwhile; when every stage left waits for one, the first started is
    /// joined.
    fn stages<'scope, 'g: 'scope>(
        &mut self,
        scope: &'scope Scope<'scope, '_>,
        at: &mut At<'_, 'g>,
        running: &mut Vec<(usize, ScopedJoinHandle<'scope, Processed<'g>>)>,
    ) -> Result<(), PipelineError> {
        let mut waiting: Vec<usize> = (0..self.plan.stages.len()).collect();
        let mut done = vec![false; waiting.len()];
        while !waiting.is_empty() {
            let index = match waiting.iter().position(|&s| self.providers_done(s, &done)) {
                Some(ready) => waiting.remove(ready),
                None if !running.is_empty() => {
                    let (index, thread) = running.remove(0);
                    self.take_back(index, thread, at)?;
                    done[index] = true;
                    continue;
                }
                None => waiting.remove(0), // a cycle the plan reported: it cannot run anyway
            };
            let frame = at.frame;
            if at.cancel.load(Ordering::Relaxed) {
                let stage = &self.plan.stages[index].instance;
                return Err(self.error(
                    None,
                    ErrorKind::Cancelled,
                    format!("cancelled in frame {frame}, before {stage}"),
                ));
            }
            let inputs = self.take_inputs(index, at.queues, frame);
            let joined = self.join(index, at.output, &mut at.times[index]);
            self.sink_alone(index, &mut at.times[index], joined)?;
            if at.times[index].failed.is_some() || self.replayed(at.device, index, at.queues, frame, false) {
                done[index] = true;
                continue;
            }
            let component = self.components[index].as_mut().expect("joined");
            if component.frames().is_none() && inputs.is_empty() {
                done[index] = true;
                continue;
            }
            at.times[index].items += inputs.len().max(1);
            if self.modes[index] == Mode::ProcessesApart {
                // What it reads is submitted before its own work.
                at.device.flush().map_err(|e| self.error(Some(index), ErrorKind::Failed, e.to_string()))?;
                let component = self.components[index].take().expect("joined");
                let own = at.devices[index].take().unwrap_or_else(|| Executor::new(at.device.gpu()));
                let fork = at.output.fork();
                running.push((index, apart::process(scope, component, own, (index, frame), inputs, fork)));
                continue;
            }
            let started = Instant::now();
            let mut ctx =
                components::Ctx { device: at.device, stage: index, frame, output: at.output, cancel: at.cancel };
            let produced =
                component.process(&mut ctx, &inputs).map_err(|message| match at.cancel.load(Ordering::Relaxed) {
                    // Work that gave up because the run was cancelled (the simulator, inside a frame).
                    true => {
                        let stage = &self.plan.stages[index].instance;
                        self.error(None, ErrorKind::Cancelled, format!("cancelled in frame {frame}, in {stage}"))
                    }
                    false => self.error(Some(index), ErrorKind::Failed, message),
                });
            at.times[index].host += started.elapsed();
            let Some(produced) = self.sink_alone_or(index, &mut at.times[index], produced)? else {
                done[index] = true;
                continue;
            };
            self.record(at.device, (index, frame), &produced, false);
            self.deliver(at.device, index, produced, at.queues, frame, false);
            done[index] = true;
        }
        Ok(())
    }

    /// Whether every stage that gives stage `index` this frame's items is done with the frame.
    fn providers_done(&self, index: usize, done: &[bool]) -> bool {
        self.plan
            .bindings
            .iter()
            .filter(|b| b.processor.stage == index && !b.is_buffered)
            .all(|b| done[b.provider.stage])
    }

    /// Stage `index`'s frame back from its thread: its component and device, its files, its
    /// times, what it gave delivered.
    fn take_back<'g>(
        &mut self,
        index: usize,
        thread: ScopedJoinHandle<'_, Processed<'g>>,
        at: &mut At<'_, 'g>,
    ) -> Result<(), PipelineError> {
        let processed = thread.join().map_err(|panic| {
            let why = apart::panic_message(&*panic);
            // Its component is lost with the thread: this pipeline cannot run again.
            self.error(Some(index), ErrorKind::Failed, format!("its thread panicked: {why}"))
        })?;
        self.components[index] = Some(processed.component);
        let mut own = processed.device;
        self.count(own.take_work(), at.times);
        at.devices[index] = Some(own);
        at.output.absorb(processed.output);
        let time = &mut at.times[index];
        time.host += processed.took;
        time.device += processed.kernel_times.iter().map(|(_, t)| *t).sum::<Duration>();
        let (given, later) = processed.result.map_err(|message| self.error(Some(index), ErrorKind::Failed, message))?;
        self.deliver(at.device, index, given, at.queues, at.frame, false);
        self.deliver(at.device, index, later, at.queues, at.frame, true);
        Ok(())
    }

    /// `work` added to the run's counts: each dispatch to its stage's.
    fn count(&mut self, work: Work, times: &mut [StageTime]) {
        for stage in work.dispatches {
            times[stage].dispatches += 1;
        }
        self.submissions += work.submissions;
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
        time.host += written.took;
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

    /// The items for stage `index` this frame, by port: an unbuffered binding's items of this
    /// frame, a buffered one's of earlier frames.
    fn take_inputs(&self, index: usize, queues: &mut [VecDeque<Item>], frame: usize) -> Inputs {
        let mut inputs = Inputs::default();
        for (binding, queue) in self.plan.bindings.iter().zip(queues.iter_mut()) {
            if binding.processor.stage != index {
                continue;
            }
            while queue.front().is_some_and(|item| item.frame <= frame) {
                let item = queue.pop_front().expect("checked");
                inputs.push(&binding.processor.port, item);
            }
        }
        inputs
    }

    /// Puts what stage `index` produced in `frame` on the bindings from its ports: for this
    /// frame, or the next when it came after the frame's reads (`after_reads`) or goes through a
    /// buffered port — there with its images copied (the producer writes its buffers again next
    /// frame), a full queue dropping its oldest item.
    fn deliver(
        &mut self,
        device: &mut Executor,
        index: usize,
        produced: Outputs,
        queues: &mut [VecDeque<Item>],
        frame: usize,
        after_reads: bool,
    ) {
        let producer = &self.plan.stages[index].instance;
        for (port, data) in produced {
            let described = data.describe();
            for ((binding, queue), flow) in self.plan.bindings.iter().zip(queues.iter_mut()).zip(&mut self.flows) {
                if binding.provider.stage != index || binding.provider.port != port {
                    continue;
                }
                flow.items += 1;
                flow.carries = Some(described.clone());
                let data = if binding.is_buffered { data::detached(device, &data) } else { data.clone() };
                let at = frame + usize::from(binding.is_buffered || after_reads);
                if binding.is_buffered && queue.len() >= binding.buffer_size {
                    queue.pop_front();
                }
                queue.push_back(Item { data, producer: producer.clone(), frame: at });
            }
        }
    }

    /// In a preview, whether stage `index` replays the kept run: then what it gave in `frame`
    /// (during the frame, or `later`, after its reads) is delivered as it was then.
    fn replayed(
        &mut self,
        device: &mut Executor,
        index: usize,
        queues: &mut [VecDeque<Item>],
        frame: usize,
        later: bool,
    ) -> bool {
        let Some(gave) = self.replay.as_ref().and_then(|replay| replay.gave(index, frame)) else { return false };
        let items = if later { gave.later.clone() } else { gave.given.clone() };
        self.deliver(device, index, items, queues, frame, later);
        true
    }

    /// In a preview, records what stage `index` gave in a frame for the next preview to replay.
    fn record(&mut self, device: &mut Executor, at: (usize, usize), produced: &Outputs, later: bool) {
        if let Some(replay) = self.replay.as_mut() {
            replay.record(device, at, produced, later);
        }
    }

    fn error(&self, stage: Option<usize>, kind: ErrorKind, message: String) -> PipelineError {
        let stage = stage.map(|s| &self.plan.stages[s]);
        PipelineError { kind, stage: stage.map(|s| s.instance.clone()), range: stage.map(|s| s.range), message }
    }
}
