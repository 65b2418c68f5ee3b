//! The frame loop of a [`PreparedPipeline`]: each frame's stages in the plan's order (those
//! that process apart on threads of their own), its one submission, then each stage's
//! `finish_frame` on the frame's reads and what it gives delivered; frames overlap on a GPU
//! where no stage needs a frame's reads for the next.

use std::{
    collections::VecDeque,
    sync::atomic::{AtomicBool, Ordering},
    thread::{Scope, ScopedJoinHandle},
    time::{Duration, Instant},
};

use gudsl_runtime::{
    executor::{InFlight, Reads},
    Executor, Work,
};

use super::{
    apart::{self, Mode, Processed},
    components::{self, Inputs, Outputs},
    data::{self, Item},
    ErrorKind, FrameSpan, FrameWork, OutputDir, PipelineError, PipelineObserver, PreparedPipeline, StageTime,
};

/// The run's progress: told each frame done; when the frames began, from the loop's start.
struct Progress<'o> {
    observer: &'o mut dyn PipelineObserver,
    frames: usize,
    start: Instant,
    started: Vec<Duration>,
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
    /// Whether frames overlap in this run.
    overlapped: bool,
    /// The frame each sink that failed in its `process` failed in: the frames before it still
    /// finish (overlapped, the next frame's `process` runs before a frame's `finish_frame`).
    failed_in: &'a mut [Option<usize>],
}

impl PreparedPipeline {
    /// Runs `frames` frames. Where frames overlap ([`PreparedPipeline::overlaps`]), frame n+1
    /// is recorded and submitted before frame n's reads are waited for and finished, so the
    /// host records while the GPU works; a frame that fails or is cancelled still finishes the
    /// frame before it.
    pub(super) fn frames_loop<'g>(
        &mut self,
        device: &mut Executor<'g>,
        output: &mut OutputDir,
        frames: usize,
        times: &mut [StageTime],
        observer: &mut dyn PipelineObserver,
        cancel: &AtomicBool,
    ) -> Result<(), PipelineError> {
        let overlapped = self.overlaps(device.gpu().is_some());
        // Items waiting on each binding: a frame's own, or a buffered port's queue.
        let mut queues: Vec<VecDeque<Item>> = vec![VecDeque::new(); self.plan.bindings.len()];
        // The devices of the stages that process apart, kept from frame to frame.
        let mut devices: Vec<Option<Executor<'g>>> = self.modes.iter().map(|_| None).collect();
        let mut failed_in = vec![None; self.plan.stages.len()];
        let (devices, queues, failed_in) = (&mut devices, &mut queues, &mut failed_in);
        let mut at = At { device, devices, queues, output, times, frame: 0, cancel, overlapped, failed_in };
        let mut progress = Progress { observer, frames, start: Instant::now(), started: Vec::new() };
        // The frame submitted before this one, its reads not yet finished.
        let mut in_flight: Option<InFlight> = None;
        for frame in 0..frames {
            at.frame = frame;
            progress.started.push(progress.start.elapsed());
            let submitted = self.record_frame(&mut at, frames);
            if let Some(before) = in_flight.take() {
                self.complete(&mut at, frame - 1, before, &mut progress)?;
            }
            match submitted? {
                submitted if overlapped => in_flight = Some(submitted),
                submitted => self.complete(&mut at, frame, submitted, &mut progress)?,
            }
        }
        match in_flight {
            Some(last) => self.complete(&mut at, frames - 1, last, &mut progress),
            None => Ok(()),
        }
    }

    /// Whether a run's frames overlap: on a GPU (`on_gpu`), unless a stage needs a frame's
    /// reads for the next, one processes apart (on a device of its own), one replays (a
    /// preview's), or it was told to run one frame at a time.
    pub(super) fn overlaps(&self, on_gpu: bool) -> bool {
        let feeds_back = self.components.iter().flatten().any(|component| component.feeds_back());
        let apart = self.modes.contains(&Mode::ProcessesApart);
        on_gpu && self.overlap && !feeds_back && !apart && self.replay.is_none()
    }

    /// Frame `at.frame`'s stages recorded and submitted (the stages that process apart joined
    /// back), its reads on their way.
    fn record_frame(&mut self, at: &mut At<'_, '_>, frames: usize) -> Result<InFlight, PipelineError> {
        let frame = at.frame;
        if at.cancel.load(Ordering::Relaxed) {
            return Err(self.error(None, ErrorKind::Cancelled, format!("cancelled after {frame} of {frames} frames")));
        }
        let submitted = std::thread::scope(|scope| {
            let mut running = Vec::new();
            let mut outcome = self.stages(scope, at, &mut running).and_then(|()| {
                at.device.submit_frame().map_err(|e| self.error(None, ErrorKind::Failed, format!("frame {frame}: {e}")))
            });
            // Nothing runs on past its frame, even a failed one: every thread is joined, and
            // the first problem is the frame's.
            for (index, thread) in running {
                let joined = self.take_back(index, thread, at);
                outcome = outcome.and_then(|submitted| joined.map(|()| submitted));
            }
            outcome
        });
        self.count(at.device.take_work(), at.times, frame);
        submitted
    }

    /// Frame `frame`, submitted: its reads waited for, its stages' GPU times added, each stage's
    /// `finish_frame` on them, when it began and was done kept.
    fn complete(
        &mut self,
        at: &mut At<'_, '_>,
        frame: usize,
        submitted: InFlight,
        progress: &mut Progress<'_>,
    ) -> Result<(), PipelineError> {
        let collected = at.device.collect(submitted);
        let (reads, kernel_times) =
            collected.map_err(|e| self.error(None, ErrorKind::Failed, format!("frame {frame}: {e}")))?;
        for (stage, time) in kernel_times {
            at.times[stage].add(frame, FrameWork { device: time, ..FrameWork::default() });
        }
        self.finish_reads(at, frame, &reads)?;
        let span = FrameSpan { started: progress.started[frame], done: progress.start.elapsed() };
        self.frame_spans.push(span);
        progress.observer.frame(frame, progress.frames);
        Ok(())
    }

    /// Each stage's `finish_frame` on frame `frame`'s reads, in the plan's order: an `async`
    /// writer's on its thread, a replayed stage's given again; what a stage gives then arrives
    /// next frame.
    fn finish_reads(&mut self, at: &mut At<'_, '_>, frame: usize, reads: &Reads) -> Result<(), PipelineError> {
        for index in 0..at.times.len() {
            let time = &mut at.times[index];
            // A sink that failed in a later frame's `process` still finishes this frame.
            let failed_later = at.failed_in[index].is_some_and(|failed| failed > frame);
            if time.failed.is_some() && !failed_later {
                continue;
            }
            let mode = self.modes[index];
            match mode {
                Mode::WritesApart => {
                    // Its writer of the frame before is joined before its next `process`,
                    // which overlapped frames may not have reached.
                    let joined = self.join(index, at.output, time);
                    if self.sink_alone_or(index, time, joined)?.is_none() {
                        continue;
                    }
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
            time.add_host(frame, started.elapsed());
            let Some(produced) = self.sink_alone_or(index, time, produced)? else { continue };
            // Overlapped, the next frame is recorded already: only a stage that `feeds_back`
            // may give after the reads, and such a stage keeps the run one frame at a time.
            debug_assert!(!at.overlapped || produced.is_empty(), "a stage gave after its reads in an overlapped run");
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
            at.times[index].add_host(frame, started.elapsed());
            let Some(produced) = self.sink_alone_or(index, &mut at.times[index], produced)? else {
                at.failed_in[index] = Some(frame);
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
        self.count(own.take_work(), at.times, at.frame);
        at.devices[index] = Some(own);
        at.output.absorb(processed.output);
        let time = &mut at.times[index];
        let device = processed.kernel_times.iter().map(|(_, t)| *t).sum::<Duration>();
        time.add(at.frame, FrameWork { host: processed.took, device, dispatches: 0 });
        let (given, later) = processed.result.map_err(|message| self.error(Some(index), ErrorKind::Failed, message))?;
        self.deliver(at.device, index, given, at.queues, at.frame, false);
        self.deliver(at.device, index, later, at.queues, at.frame, true);
        Ok(())
    }

    /// `work` (for frame `frame`) added to the run's counts: each dispatch to its stage's.
    fn count(&mut self, work: Work, times: &mut [StageTime], frame: usize) {
        for stage in work.dispatches {
            times[stage].add(frame, FrameWork { dispatches: 1, ..FrameWork::default() });
        }
        if self.submissions.len() <= frame {
            self.submissions.resize(frame + 1, 0);
        }
        self.submissions[frame] += work.submissions;
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
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::AtomicBool;

    use gudsl_model::AnalysisHost;
    use gudsl_runtime::Gpu;

    use super::*;
    use crate::pipeline::{components::Component, PipelineReport, Preparations};

    /// Cancels the run once frame `after` is done.
    struct CancelAfter<'c>(usize, &'c AtomicBool);

    impl PipelineObserver for CancelAfter<'_> {
        fn frame(&mut self, index: usize, _frames: usize) {
            if index == self.0 {
                self.1.store(true, Ordering::Relaxed);
            }
        }
    }

    /// The tapped chapter 4 sample (no stage feeds back), 4 small frames.
    fn taps(one_frame_at_a_time: bool) -> PreparedPipeline {
        let text = include_str!("../../../samples/pipelines/ch4_motion_taps.gudsl")
            .replace("speed = 1, frames = 2", "speed = 1, frames = 4, width = 64, height = 48");
        let (host, _) = AnalysisHost::with_files([(dir().join("taps.gudsl").display().to_string(), text)]);
        let analysis = host.analysis();
        let plan = analysis.pipeline_plan("MotionTapsPipeline").unwrap().expect("a pipeline");
        let mut prepared = Preparations::default().take_for(&analysis, &plan).unwrap().expect("it runs");
        if one_frame_at_a_time {
            prepared.one_frame_at_a_time();
        }
        prepared
    }

    fn dir() -> std::path::PathBuf {
        std::env::temp_dir().join(format!("gudsl-frames-{}", std::process::id()))
    }

    /// `prepared` run on `gpu` into the folder `out`, cancelled once frame `cancel_after` is done.
    fn run_taps(
        mut prepared: PreparedPipeline,
        gpu: &Gpu,
        out: &str,
        cancel_after: usize,
    ) -> (PipelineReport, std::path::PathBuf) {
        let folder = dir().join(out);
        let mut output = OutputDir::named(&folder).unwrap();
        let cancel = AtomicBool::new(false);
        let report = prepared.run(Some(gpu), &mut output, None, &mut CancelAfter(cancel_after, &cancel), &cancel);
        (report, folder)
    }

    /// The tapped sample, cancelled once frame 1 is done; into `out`.
    fn cancelled_taps(gpu: &Gpu, one_frame_at_a_time: bool, out: &str) -> (PipelineReport, std::path::PathBuf) {
        run_taps(taps(one_frame_at_a_time), gpu, out, 1)
    }

    /// A sink that fails in its `process` of frame `.1`, else does what `.0` does.
    struct FailsAt(Box<dyn Component>, usize);

    impl Component for FailsAt {
        fn process(&mut self, ctx: &mut components::Ctx, inputs: &Inputs) -> Result<Outputs, String> {
            if ctx.frame == self.1 {
                return Err(format!("made to fail in frame {}", self.1));
            }
            self.0.process(ctx, inputs)
        }

        fn finish_frame(&mut self, ctx: &mut components::Ctx, reads: &Reads) -> Result<Outputs, String> {
            self.0.finish_frame(ctx, reads)
        }
    }

    /// A sink that fails in frame 2's `process` — overlapped, before frame 1's `finish_frame` —
    /// still writes frame 1; it then runs no more, and the others write every frame.
    #[test]
    fn a_sink_that_fails_in_the_next_frame_still_finishes_the_frame_in_flight() {
        let Some(gpu) = Gpu::for_tests() else { return };
        for one_frame_at_a_time in [false, true] {
            let mut prepared = taps(one_frame_at_a_time);
            let sink = prepared.plan.stages.iter().position(|s| s.instance == "CompensatedDepth").unwrap();
            let failing = FailsAt(prepared.components[sink].take().unwrap(), 2);
            prepared.components[sink] = Some(Box::new(failing));
            let (report, folder) = run_taps(prepared, &gpu, &format!("sink-fails-{one_frame_at_a_time}"), usize::MAX);
            assert!(report.outcome.is_ok(), "{:?}", report.outcome);
            assert_eq!(report.overlapped, !one_frame_at_a_time);
            let failed = report.stages[sink].failed.as_ref().expect("the sink failed");
            assert!(failed.message.contains("made to fail in frame 2"), "{}", failed.message);
            for frame in 0..4 {
                let written = folder.join(format!("CompensatedDepth/distance_{frame:04}.npy")).is_file();
                assert_eq!(written, frame < 2, "CompensatedDepth's frame {frame}");
                let other = folder.join(format!("UncompensatedDepth/distance_{frame:04}.npy")).is_file();
                assert!(other, "UncompensatedDepth's frame {frame}");
            }
        }
    }

    /// A run cancelled while a frame is in flight finishes that frame: three frames of four
    /// written (the control, one frame at a time, two); the error says how many ran.
    #[test]
    fn a_cancelled_run_finishes_the_frame_in_flight() {
        let Some(gpu) = Gpu::for_tests() else { return };
        for (one_frame_at_a_time, done) in [(false, 3), (true, 2)] {
            let (report, folder) = cancelled_taps(&gpu, one_frame_at_a_time, &format!("cancelled-{done}"));
            assert_eq!(report.overlapped, !one_frame_at_a_time);
            let error = report.outcome.as_ref().expect_err("cancelled");
            assert_eq!(error.kind, ErrorKind::Cancelled);
            assert_eq!(error.message, format!("cancelled after {done} of 4 frames"));
            assert_eq!(report.frame_spans.len(), done);
            for frame in 0..4 {
                let written = folder.join(format!("CompensatedDepth/distance_{frame:04}.npy")).is_file();
                assert_eq!(written, frame < done, "frame {frame} of {done}");
                let flow = folder.join(format!("Flows/flow_{frame:04}.png")).is_file();
                assert_eq!(flow, frame < done, "frame {frame}'s flow of {done}");
            }
        }
    }
}
