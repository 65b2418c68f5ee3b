//! The GPU executor: work recorded into one command encoder a frame over buffers made once (a
//! kernel bound to its inputs in a [`KernelSlot`] is re-encoded frame after frame), submitted at
//! the end of the frame, when every read asked for comes back through a staging buffer of the
//! frame's own in one mapping, with the GPU's clock around every pass by the stage it belongs
//! to (on a [`Gpu::with_timestamps`]); the next frame can be recorded and submitted before a
//! frame's reads are collected ([`Executor::submit_frame`], [`Executor::collect`]). Without an
//! adapter the same calls run each kernel's CPU reference and callers cannot tell the two apart.
//! ToF pipelines (`gudsl run`) run on it, and so do the kernel chains of [`crate::pipeline`]
//! ([`ChainRun`]).

use std::{sync::Arc, time::Duration};

use crate::{
    bound::BoundKernel, error::ChainError, pipeline::Pipeline, timing::Timing, DeviceBuffer, Gpu, Image, Kernel,
    Program, ProgramError, Resource, Shape,
};

/// An image where it lives: in host memory, or in a GPU buffer of f32 samples.
#[derive(Debug, Clone)]
pub enum Tensor {
    Cpu(Arc<Image>),
    Gpu { buffer: wgpu::Buffer, shape: Shape },
}

impl Tensor {
    pub fn shape(&self) -> Shape {
        match self {
            Tensor::Cpu(image) => Shape { width: image.width, height: image.height, planes: image.planes },
            Tensor::Gpu { shape, .. } => *shape,
        }
    }

    pub fn cpu(image: Image) -> Tensor {
        Tensor::Cpu(Arc::new(image))
    }

    /// Its GPU buffer as a [`Program`]'s resource; `None` for an image in host memory.
    pub fn device_buffer(&self) -> Option<DeviceBuffer> {
        match self {
            Tensor::Gpu { buffer, .. } => Some(DeviceBuffer::wrap(buffer)),
            Tensor::Cpu(_) => None,
        }
    }
}

/// The GPU time each stage's passes took in a frame, by stage.
pub type StageTimes = Vec<(usize, Duration)>;

/// The device work an executor did since it was last asked ([`Executor::take_work`]): each
/// compute pass it recorded (a dispatch), by the stage that recorded it, and the command
/// buffers it submitted. Both are counted on any adapter, timestamps or not, and stay zero on
/// the CPU reference.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Work {
    /// The stage of each dispatch, in the order recorded.
    pub dispatches: Vec<usize>,
    pub submissions: usize,
}

/// The GPU (or the CPU) and the frame's recording.
pub struct Executor<'g> {
    gpu: Option<&'g Gpu>,
    encoder: Option<wgpu::CommandEncoder>,
    /// Reads asked for the end of the frame.
    later: Vec<Tensor>,
    /// The frame being recorded.
    recording: u64,
    /// Staging buffers no frame in flight uses.
    spare: Vec<wgpu::Buffer>,
    timing: Option<Timing>,
    work: Work,
}

/// A kernel slot a stage keeps across frames: the kernel bound to the buffers it last ran on.
#[derive(Default)]
pub struct KernelSlot(Option<BoundKernel>);

/// A buffer a stage keeps across frames for data it uploads or keeps.
#[derive(Default)]
pub struct BufferSlot(Option<(wgpu::Buffer, Shape)>);

/// A read asked for at the end of the frame: its frame's recording and its index among the
/// frame's reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Later {
    recording: u64,
    index: usize,
}

/// A frame submitted, its reads on their way back ([`Executor::submit_frame`]).
pub struct InFlight {
    recording: u64,
    tensors: Vec<Tensor>,
    /// On a GPU, unless nothing was to be read: the staging buffer being mapped.
    mapping: Option<Mapping>,
}

/// A frame's staging buffer being mapped: the bytes of its images (the timestamps after
/// them), the stage of each timed pass, the submission that fills it.
struct Mapping {
    staging: wgpu::Buffer,
    images: u64,
    owners: Vec<usize>,
    submission: wgpu::SubmissionIndex,
    mapped: crate::gpu::Mapping,
}

impl<'g> Executor<'g> {
    /// A device on `gpu`, or the CPU reference without one; with `gpu`'s timestamp queries
    /// (a [`Gpu::with_timestamps`]) every kernel is timed on the GPU.
    pub fn new(gpu: Option<&'g Gpu>) -> Executor<'g> {
        let timing = gpu.and_then(|gpu| Timing::new(gpu, 64));
        let (later, spare) = (Vec::new(), Vec::new());
        Executor { gpu, encoder: None, later, recording: 0, spare, timing, work: Work::default() }
    }

    /// The GPU, `None` on the CPU reference.
    pub fn gpu(&self) -> Option<&'g Gpu> {
        self.gpu
    }

    /// The dispatches and submissions since the last call (or since it was made).
    pub fn take_work(&mut self) -> Work {
        std::mem::take(&mut self.work)
    }

    /// Records a dispatch of `program` (a generated kernel, a conversion) for `stage` into the
    /// frame, with the stage's timestamps around its pass; programs need a GPU.
    pub fn dispatch(
        &mut self,
        stage: usize,
        program: &Program,
        constants: &[(&str, f64)],
        resources: &[(u32, Resource<'_>)],
        workgroups: [u32; 3],
    ) -> Result<(), ProgramError> {
        let recorded = self.record(stage, |gpu, encoder, timestamps| {
            program.record(gpu, encoder, constants, resources, workgroups, timestamps)
        });
        recorded.unwrap_or_else(|| Err(ProgramError::Device("a program runs on a GPU, and this run has none".into())))
    }

    /// A GPU buffer of `shape` kept in `slot` across frames (made when it has none of that
    /// shape), for a stage's own results; `None` on the CPU.
    pub fn buffer(&mut self, slot: &mut BufferSlot, shape: Shape) -> Option<Tensor> {
        let gpu = self.gpu?;
        if slot.0.as_ref().is_none_or(|(_, s)| *s != shape) {
            slot.0 = Some((gpu.storage("stage buffer", shape.len()), shape));
        }
        let (buffer, _) = slot.0.as_ref().expect("made above");
        Some(Tensor::Gpu { buffer: buffer.clone(), shape })
    }

    /// Records `stage`'s work into the frame's encoder, with the stage's timestamps for its
    /// pass; `None` on the CPU.
    fn record<R>(
        &mut self,
        stage: usize,
        work: impl FnOnce(&Gpu, &mut wgpu::CommandEncoder, Option<wgpu::ComputePassTimestampWrites<'_>>) -> R,
    ) -> Option<R> {
        let gpu = self.gpu?;
        self.work.dispatches.push(stage);
        let writes = self.timing.as_mut().map(|t| t.next(gpu, stage));
        let encoder = self.encoder.get_or_insert_with(|| gpu.device.create_command_encoder(&Default::default()));
        Some(work(gpu, encoder, writes))
    }

    /// `kernel` on `inputs` for `stage`, its results where the inputs are.
    pub fn kernel(
        &mut self,
        stage: usize,
        slot: &mut KernelSlot,
        kernel: Kernel,
        inputs: &[&Tensor],
    ) -> Result<Vec<Tensor>, ChainError> {
        let Some(gpu) = self.gpu else {
            let images: Vec<Arc<Image>> = inputs.iter().map(|t| host(t)).collect();
            kernel.check(&inputs.iter().map(|t| t.shape()).collect::<Vec<_>>())?;
            let refs: Vec<&Image> = images.iter().map(|i| &**i).collect();
            return Ok(kernel.cpu(&refs).into_iter().map(Tensor::cpu).collect());
        };
        let uploaded: Vec<(wgpu::Buffer, Shape)> = inputs.iter().map(|t| self.on_device(gpu, t)).collect();
        let bound: Vec<(&wgpu::Buffer, Shape)> = uploaded.iter().map(|(b, s)| (b, *s)).collect();
        let fits = slot.0.as_ref().is_some_and(|k| k.kernel().name() == kernel.name() && k.binds(&bound));
        if !fits {
            slot.0 = Some(BoundKernel::new(gpu, kernel, &bound)?);
        }
        let bound = slot.0.as_mut().expect("bound above");
        bound.set_kernel(gpu, kernel)?;
        bound.reset_scratch(gpu);
        self.record(stage, |_, encoder, timestamps| bound.encode(encoder, timestamps));
        Ok(bound
            .outputs()
            .iter()
            .map(|(buffer, shape)| Tensor::Gpu { buffer: buffer.clone(), shape: *shape })
            .collect())
    }

    /// `image` where kernels read it: uploaded into the stage's buffer on a GPU (a copy on the
    /// CPU).
    pub fn upload(&mut self, slot: &mut BufferSlot, image: &Image) -> Tensor {
        let Some(gpu) = self.gpu else { return Tensor::cpu(image.clone()) };
        let shape = Shape { width: image.width, height: image.height, planes: image.planes };
        let fits = slot.0.as_ref().is_some_and(|(_, s)| *s == shape);
        if !fits {
            slot.0 = Some((gpu.storage("upload", shape.len()), shape));
        }
        let (buffer, _) = slot.0.as_ref().expect("made above");
        gpu.queue.write_buffer(buffer, 0, bytemuck::cast_slice(&image.data));
        Tensor::Gpu { buffer: buffer.clone(), shape }
    }

    /// A copy of `tensor` in the stage's buffer, so it outlives this frame (a kernel's output
    /// buffer is written again next frame).
    pub fn keep(&mut self, slot: &mut BufferSlot, tensor: &Tensor) -> Tensor {
        let (Some(gpu), Tensor::Gpu { buffer, shape }) = (self.gpu, tensor) else { return tensor.clone() };
        if slot.0.as_ref().is_none_or(|(_, s)| s != shape) {
            slot.0 = Some((gpu.storage("kept", shape.len()), *shape));
        }
        let (kept, _) = slot.0.as_ref().expect("made above");
        let encoder = self.encoder.get_or_insert_with(|| gpu.device.create_command_encoder(&Default::default()));
        encoder.copy_buffer_to_buffer(buffer, 0, kept, 0, (shape.len() * 4) as u64);
        Tensor::Gpu { buffer: kept.clone(), shape: *shape }
    }

    /// Submits the work recorded so far: a stage on another thread that reads its results then
    /// submits after it.
    pub fn flush(&mut self) -> Result<(), ChainError> {
        match (self.gpu, self.encoder.take()) {
            (Some(gpu), Some(encoder)) => self.submit(gpu, encoder).map(drop),
            _ => Ok(()),
        }
    }

    /// Submits the work recorded so far and the uploads, and waits until the device has done
    /// them (a benchmark's clock starts after).
    pub fn wait(&mut self) -> Result<(), ChainError> {
        let Some(gpu) = self.gpu else { return Ok(()) };
        let encoder = self.encoder.take().unwrap_or_else(|| gpu.device.create_command_encoder(&Default::default()));
        let submission = self.submit(gpu, encoder)?;
        let done = wgpu::PollType::Wait { submission_index: Some(submission), timeout: None };
        gpu.device.poll(done).map(drop).map_err(|e| ChainError::Readback(e.to_string()))
    }

    /// Asks for `tensor`'s samples at the end of the frame ([`Executor::end_frame`]).
    pub fn read_later(&mut self, tensor: &Tensor) -> Later {
        self.later.push(tensor.clone());
        Later { recording: self.recording, index: self.later.len() - 1 }
    }

    /// The frame being recorded, counted from 0: what a stage keeps for a frame's reads is
    /// kept under it ([`Reads::recording`]).
    pub fn recording(&self) -> u64 {
        self.recording
    }

    /// Submits the work recorded so far and reads `tensors` back at once: for a stage that
    /// needs a result before it can go on (ICP's sums each iteration, a cloud to accumulate).
    pub fn read_now(&mut self, tensors: &[&Tensor]) -> Result<Vec<Arc<Image>>, ChainError> {
        let tensors: Vec<Tensor> = tensors.iter().map(|t| (*t).clone()).collect();
        let sent = self.send(tensors, false)?;
        Ok(self.receive(sent)?.0)
    }

    /// Submits the frame's work and reads back what was asked for, in one mapping; with the
    /// GPU time each stage's kernels took, whose timestamps come back in the same mapping.
    pub fn end_frame(&mut self) -> Result<(Reads, StageTimes), ChainError> {
        let submitted = self.submit_frame()?;
        self.collect(submitted)
    }

    /// Submits the frame's work with the copies of what was asked for into a staging buffer of
    /// its own, and does not wait: the next frame is recorded (and submitted: the queue runs it
    /// after this one) while the device works; [`Executor::collect`] waits for this one's reads.
    pub fn submit_frame(&mut self) -> Result<InFlight, ChainError> {
        let later = std::mem::take(&mut self.later);
        let submitted = self.send(later, true);
        self.recording += 1;
        submitted
    }

    /// The reads of a frame [`Executor::submit_frame`] submitted, once the device has done that
    /// frame (not the ones submitted after it), and the GPU time each stage's kernels took.
    pub fn collect(&mut self, frame: InFlight) -> Result<(Reads, StageTimes), ChainError> {
        let recording = frame.recording;
        let (images, times) = self.receive(frame)?;
        Ok((Reads { recording, images }, times))
    }

    /// Submits the recorded work with copies of `tensors` into a staging buffer, which is
    /// then mapped; with `timestamps`, the recording's timestamps too (the passes' ticks
    /// after the images), which ends the recording's timing.
    fn send(&mut self, tensors: Vec<Tensor>, timestamps: bool) -> Result<InFlight, ChainError> {
        let recording = self.recording;
        let Some(gpu) = self.gpu else { return Ok(InFlight { recording, tensors, mapping: None }) };
        let images: u64 = tensors.iter().map(|t| (t.shape().len().max(1) * 4) as u64).sum();
        let ticks = self.timing.as_ref().filter(|_| timestamps).map_or(0, |t| t.bytes());
        let mut encoder = self.encoder.take().unwrap_or_else(|| gpu.device.create_command_encoder(&Default::default()));
        if ticks == 0 && tensors.iter().all(|t| matches!(t, Tensor::Cpu(_))) {
            self.submit(gpu, encoder)?;
            return Ok(InFlight { recording, tensors, mapping: None });
        }
        let staging = self.staging(gpu, images + ticks);
        let mut offset = 0;
        for tensor in &tensors {
            if let Tensor::Gpu { buffer, shape } = tensor {
                encoder.copy_buffer_to_buffer(buffer, 0, &staging, offset, (shape.len() * 4) as u64);
            }
            offset += (tensor.shape().len().max(1) * 4) as u64;
        }
        let owners = match self.timing.as_mut().filter(|_| ticks > 0) {
            Some(timing) => {
                timing.copy_into(&mut encoder, &staging, images);
                timing.end_recording()
            }
            None => Vec::new(),
        };
        let submission = self.submit(gpu, encoder)?;
        let mapped = Gpu::map(&staging);
        let mapping = Mapping { staging, images, owners, submission, mapped };
        Ok(InFlight { recording, tensors, mapping: Some(mapping) })
    }

    /// The images (and the passes' times) of what [`Executor::send`] sent, once the device has
    /// done its submission; the staging buffer is free again.
    fn receive(&mut self, sent: InFlight) -> Result<(Vec<Arc<Image>>, StageTimes), ChainError> {
        let InFlight { tensors, mapping, .. } = sent;
        let (Some(gpu), Some(mapping)) = (self.gpu, mapping) else {
            return Ok((tensors.iter().map(host).collect(), Vec::new()));
        };
        let Mapping { staging, images, owners, submission, mapped } = mapping;
        let (read, ticks) = gpu
            .read_mapped(&staging, mapped, Some(submission), |bytes| {
                let (samples, rest) = bytes.split_at(images as usize);
                let ticks: Vec<u64> = (rest[..owners.len() * 16].chunks_exact(8))
                    .map(|b| u64::from_le_bytes(b.try_into().expect("eight bytes")))
                    .collect();
                (unpack(&tensors, bytemuck::cast_slice(samples)), ticks)
            })
            .map_err(ChainError::Readback)?;
        self.spare.push(staging);
        let times = self.timing.as_ref().map(|timing| timing.times(&owners, &ticks)).unwrap_or_default();
        Ok((read, times))
    }

    /// A spare staging buffer of at least `bytes` (a new one when none is that long).
    fn staging(&mut self, gpu: &Gpu, bytes: u64) -> wgpu::Buffer {
        if let Some(at) = self.spare.iter().position(|s| s.size() >= bytes) {
            return self.spare.swap_remove(at);
        }
        // Too short for this frame's reads, so for the frames like it.
        self.spare.clear();
        gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("pipeline reads"),
            size: bytes,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    }

    /// Finishes and submits the frame's recording: what the device refuses in it (a generated
    /// kernel's binding, say) is an error, not wgpu's panic.
    fn submit(&mut self, gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Result<wgpu::SubmissionIndex, ChainError> {
        self.work.submissions += 1;
        gpu.scoped(|| gpu.queue.submit([encoder.finish()])).map_err(ChainError::Readback)
    }

    /// A tensor's buffer on the GPU (a host image uploaded into a buffer of its own).
    fn on_device(&self, gpu: &Gpu, tensor: &Tensor) -> (wgpu::Buffer, Shape) {
        match tensor {
            Tensor::Gpu { buffer, shape } => (buffer.clone(), *shape),
            Tensor::Cpu(image) => {
                let shape = tensor.shape();
                let buffer = gpu.storage("host image", shape.len());
                gpu.queue.write_buffer(&buffer, 0, bytemuck::cast_slice(&image.data));
                (buffer, shape)
            }
        }
    }
}

/// A tensor known to be in host memory (on the CPU device every tensor is).
fn host(tensor: &Tensor) -> Arc<Image> {
    match tensor {
        Tensor::Cpu(image) => image.clone(),
        Tensor::Gpu { .. } => unreachable!("GPU tensors exist only on a GPU device"),
    }
}

/// `tensors`' images from the `samples` read back for them, one after another (a host image
/// as it is: it took its place, unread).
fn unpack(tensors: &[Tensor], samples: &[f32]) -> Vec<Arc<Image>> {
    let mut at = 0;
    let mut images = Vec::with_capacity(tensors.len());
    for tensor in tensors {
        let shape = tensor.shape();
        images.push(match tensor {
            Tensor::Cpu(image) => image.clone(),
            Tensor::Gpu { .. } => Arc::new(Image {
                width: shape.width,
                height: shape.height,
                planes: shape.planes,
                data: samples[at..at + shape.len()].to_vec(),
            }),
        });
        at += shape.len().max(1);
    }
    images
}

/// The images read at the end of a frame, by the [`Later`] each was asked for with.
#[derive(Clone)]
pub struct Reads {
    recording: u64,
    images: Vec<Arc<Image>>,
}

impl Reads {
    /// The image asked for with `later`, in this frame.
    pub fn get(&self, later: Later) -> &Arc<Image> {
        debug_assert_eq!(later.recording, self.recording, "a read asked for in another frame");
        &self.images[later.index]
    }

    /// The frame they were read in ([`Executor::recording`]).
    pub fn recording(&self) -> u64 {
        self.recording
    }
}

/// A chain of kernels ([`Pipeline`]) prepared on the executor: each step's kernel bound once in
/// a slot, the sources uploaded into buffers of their own, the sinks read at the end of a run.
pub struct ChainRun<'g> {
    executor: Executor<'g>,
    pipeline: Pipeline,
    kernels: Vec<KernelSlot>,
    buffers: Vec<BufferSlot>,
    /// The sources as last uploaded.
    sources: Option<Vec<Tensor>>,
}

impl<'g> ChainRun<'g> {
    /// `pipeline` on `gpu`, or on the CPU reference without one.
    pub fn new(gpu: Option<&'g Gpu>, pipeline: &Pipeline) -> ChainRun<'g> {
        ChainRun {
            executor: Executor::new(gpu),
            pipeline: pipeline.clone(),
            kernels: pipeline.steps.iter().map(|_| KernelSlot::default()).collect(),
            buffers: pipeline.sources.iter().map(|_| BufferSlot::default()).collect(),
            sources: None,
        }
    }

    /// Whether it runs on a GPU.
    pub fn on_gpu(&self) -> bool {
        self.executor.gpu.is_some()
    }

    /// Uploads the sources, runs every step in one submission and reads the sinks back.
    pub fn run(&mut self, sources: &[Image]) -> Result<Vec<Image>, ChainError> {
        self.upload(sources)?;
        self.rerun()
    }

    /// Runs every step again on the sources already uploaded (for iterations that only change
    /// parameters, see [`ChainRun::set_kernel`]) and reads the sinks back.
    pub fn rerun(&mut self) -> Result<Vec<Image>, ChainError> {
        Ok(self.frame()?.0)
    }

    /// Uploads the sources and runs once; each step's time: by the GPU's clock on a
    /// [`Gpu::with_timestamps`] (the steps' passes alone), else the wall time of the run after
    /// the uploads (with its one readback of the sinks) split evenly, as no clock tells the
    /// steps apart.
    pub fn time_steps(&mut self, sources: &[Image]) -> Result<Vec<Duration>, ChainError> {
        self.upload(sources)?;
        self.executor.wait()?;
        let started = std::time::Instant::now();
        let (_, times) = self.frame()?;
        let steps = self.pipeline.steps.len();
        if times.is_empty() {
            return Ok(vec![started.elapsed() / steps.max(1) as u32; steps]);
        }
        let mut by_step = vec![Duration::ZERO; steps];
        for (step, time) in times {
            by_step[step] += time;
        }
        Ok(by_step)
    }

    /// The dispatches and submissions of the runs since the last call.
    pub fn take_work(&mut self) -> Work {
        self.executor.take_work()
    }

    /// Changes the parameters of step `index` (same kernel, same shapes), e.g. the pose of an
    /// ICP iteration.
    pub fn set_kernel(&mut self, index: usize, kernel: Kernel) -> Result<(), ChainError> {
        let step = self.pipeline.steps.get_mut(index).ok_or(ChainError::UnknownStep(index))?;
        if step.kernel.name() != kernel.name() {
            return Err(ChainError::KernelChanged { step: index, was: step.kernel.name(), given: kernel.name() });
        }
        step.kernel = kernel;
        Ok(())
    }

    fn upload(&mut self, sources: &[Image]) -> Result<(), ChainError> {
        self.pipeline.check_sources(sources)?;
        let uploaded = sources.iter().zip(&mut self.buffers).map(|(image, buffer)| self.executor.upload(buffer, image));
        self.sources = Some(uploaded.collect());
        Ok(())
    }

    /// One frame on the uploaded sources: the sinks' images and the steps' GPU times.
    fn frame(&mut self) -> Result<(Vec<Image>, StageTimes), ChainError> {
        let expected = self.pipeline.sources.len();
        let sources = self.sources.as_ref().ok_or(ChainError::Sources { expected, given: 0 })?;
        let mut values: Vec<Option<Tensor>> = vec![None; self.pipeline.slots.len()];
        for (slot, tensor) in self.pipeline.sources.iter().zip(sources) {
            values[slot.0] = Some(tensor.clone());
        }
        for (index, step) in self.pipeline.steps.iter().enumerate() {
            // Every step's inputs were checked to be slots made before it.
            let inputs: Vec<&Tensor> =
                step.inputs.iter().map(|s| values[s.0].as_ref().expect("a computed slot")).collect();
            let outputs = self.executor.kernel(index, &mut self.kernels[index], step.kernel, &inputs)?;
            for (slot, tensor) in step.outputs.iter().zip(outputs) {
                values[slot.0] = Some(tensor);
            }
        }
        let sinks: Vec<Later> = (self.pipeline.sinks.iter())
            .map(|s| self.executor.read_later(values[s.0].as_ref().expect("a computed sink")))
            .collect();
        let (reads, times) = self.executor.end_frame()?;
        Ok((sinks.into_iter().map(|later| (**reads.get(later)).clone()).collect(), times))
    }
}

/// `pipeline` on `sources` by the CPU reference of each kernel.
pub fn run_cpu(pipeline: &Pipeline, sources: &[Image]) -> Result<Vec<Image>, ChainError> {
    ChainRun::new(None, pipeline).run(sources)
}
