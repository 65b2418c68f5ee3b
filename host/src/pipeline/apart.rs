//! Stages that run beside the frame, as `async` ports ask (Sec. 11.3.3, 11.4.3: the caller
//! goes on at once): a sink's encoding and writing after the frame's reads, on a thread that
//! lives into the next frame; a filter's whole frame (its kernels recorded and submitted on a
//! device of its own, its reads, its host work), on a thread while the frame's other stages go
//! on, joined when a stage needs what it gives.

use std::{
    sync::atomic::AtomicBool,
    thread::{JoinHandle, Scope, ScopedJoinHandle},
    time::{Duration, Instant},
};

use super::{
    components::{Component, Ctx, Inputs, Outputs},
    executor::{Executor, Reads},
    OutputDir,
};

/// How a stage runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// In the frame's order, on the run's thread.
    InOrder,
    /// A sink bound through an `async` port: its work after the frame's reads on a thread.
    WritesApart,
    /// A filter bound through an `async` port: its frame on a thread.
    ProcessesApart,
}

/// The cancellation a stage apart sees: none. Its frame finishes (it is joined before the run
/// ends); a cancelled run stops before the next stage and the next frame.
static NOT_CANCELLED: AtomicBool = AtomicBool::new(false);

/// What an `async` sink's writer thread hands back.
pub struct Written {
    pub component: Box<dyn Component>,
    pub output: OutputDir,
    /// The frame it wrote.
    pub frame: usize,
    pub took: Duration,
    pub result: Result<(), String>,
}

/// An `async` sink's work after frame `frame`'s reads (it gives nothing and needs no device:
/// it encodes and writes), on a thread of its own.
pub fn write(
    mut component: Box<dyn Component>,
    stage: usize,
    frame: usize,
    reads: Reads,
    mut output: OutputDir,
) -> JoinHandle<Written> {
    std::thread::spawn(move || {
        let started = Instant::now();
        let mut device = Executor::new(None);
        let mut ctx = Ctx { device: &mut device, stage, frame, output: &mut output, cancel: &NOT_CANCELLED };
        let result = component.finish_frame(&mut ctx, &reads).map(|_| ());
        Written { component, output, frame, took: started.elapsed(), result }
    })
}

/// What an `async` filter's thread hands back.
pub struct Processed<'g> {
    pub component: Box<dyn Component>,
    pub device: Executor<'g>,
    pub output: OutputDir,
    pub took: Duration,
    /// Its kernels' GPU times, by stage (its own).
    pub kernel_times: Vec<(usize, Duration)>,
    /// What `process` gave (this frame's items) and what `finish_frame` gave (next frame's).
    pub result: Result<(Outputs, Outputs), String>,
}

/// The whole of an `async` filter's frame on a thread in `scope`: `process` on `inputs`
/// recorded on `device` (its own; the frame's work it reads was submitted before), the work
/// submitted and its reads back, then `finish_frame`.
pub fn process<'scope, 'g: 'scope>(
    scope: &'scope Scope<'scope, '_>,
    mut component: Box<dyn Component>,
    mut device: Executor<'g>,
    (stage, frame): (usize, usize),
    inputs: Inputs,
    mut output: OutputDir,
) -> ScopedJoinHandle<'scope, Processed<'g>> {
    scope.spawn(move || {
        let started = Instant::now();
        let mut ctx = Ctx { device: &mut device, stage, frame, output: &mut output, cancel: &NOT_CANCELLED };
        let mut kernel_times = Vec::new();
        let result = component.process(&mut ctx, &inputs).and_then(|given| {
            let (reads, times) = ctx.device.end_frame().map_err(|e| format!("frame {frame}: {e}"))?;
            kernel_times = times;
            Ok((given, component.finish_frame(&mut ctx, &reads)?))
        });
        Processed { component, device, output, took: started.elapsed(), kernel_times, result }
    })
}

/// A thread's panic message.
pub fn panic_message(panic: &(dyn std::any::Any + Send)) -> &str {
    panic
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| panic.downcast_ref::<&str>().copied())
        .unwrap_or("no message")
}
