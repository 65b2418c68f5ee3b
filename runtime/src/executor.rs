//! Runs a pipeline: on the GPU with every slot a buffer made once and reused across frames, all
//! steps in one submission and one readback of the sinks; or on the CPU with the reference of
//! each kernel.

use std::borrow::Cow;
use std::time::{Duration, Instant};

use crate::bound::BoundKernel;
use crate::error::PipelineError;
use crate::gpu::Gpu;
use crate::pipeline::{Pipeline, Slot};
use crate::{Image, Kernel};

/// The CPU reference executor.
pub fn run_cpu(pipeline: &Pipeline, sources: &[Image]) -> Result<Vec<Image>, PipelineError> {
    pipeline.check_sources(sources)?;
    let mut values: Vec<Option<Cow<Image>>> = vec![None; pipeline.slots.len()];
    for (slot, image) in pipeline.sources.iter().zip(sources) {
        values[slot.0] = Some(Cow::Borrowed(image));
    }
    for step in &pipeline.steps {
        let inputs: Vec<&Image> =
            step.inputs.iter().map(|s| values[s.0].as_deref().expect("a computed slot")).collect();
        let outputs = step.kernel.cpu(&inputs);
        for (slot, image) in step.outputs.iter().zip(outputs) {
            values[slot.0] = Some(Cow::Owned(image));
        }
    }
    // Every step's inputs and every sink were checked to be slots made before them.
    Ok(pipeline.sinks.iter().map(|s| values[s.0].as_deref().expect("a computed sink").clone()).collect())
}

/// A pipeline prepared on a GPU: buffers, parameters and bind groups made once.
pub struct GpuPipeline<'g> {
    gpu: &'g Gpu,
    pipeline: Pipeline,
    buffers: Vec<wgpu::Buffer>,
    steps: Vec<BoundKernel>,
    staging: wgpu::Buffer,
}

impl<'g> GpuPipeline<'g> {
    pub fn new(gpu: &'g Gpu, pipeline: &Pipeline) -> GpuPipeline<'g> {
        let buffers: Vec<wgpu::Buffer> =
            pipeline.slots.iter().map(|(name, shape)| gpu.storage(name, shape.len())).collect();
        let steps = pipeline
            .steps
            .iter()
            .map(|step| {
                let inputs: Vec<(&wgpu::Buffer, _)> =
                    step.inputs.iter().map(|&s| (&buffers[s.0], pipeline.shape(s))).collect();
                let outputs = step.outputs.iter().map(|s| buffers[s.0].clone()).collect();
                BoundKernel::into(gpu, step.kernel, &inputs, outputs)
            })
            .collect();
        let sink_len: usize = pipeline.sinks.iter().map(|&s| pipeline.shape(s).len()).sum();
        let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sinks"),
            size: (sink_len.max(1) * 4) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        GpuPipeline { gpu, pipeline: pipeline.clone(), buffers, steps, staging }
    }

    /// Uploads the sources, runs every step and reads the sinks back.
    pub fn run(&self, sources: &[Image]) -> Result<Vec<Image>, PipelineError> {
        self.upload(sources)?;
        self.rerun()
    }

    /// Runs every step again on the sources already on the GPU and reads the sinks back (for
    /// iterations that only change parameters, see [`GpuPipeline::set_kernel`]).
    pub fn rerun(&self) -> Result<Vec<Image>, PipelineError> {
        self.reset_scratch();
        let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
        for step in &self.steps {
            step.encode(&mut encoder, None);
        }
        let mut offset = 0u64;
        for &sink in &self.pipeline.sinks {
            let bytes = (self.pipeline.shape(sink).len() * 4) as u64;
            encoder.copy_buffer_to_buffer(&self.buffers[sink.0], 0, &self.staging, offset, bytes);
            offset += bytes;
        }
        self.gpu.queue.submit([encoder.finish()]);
        let (sender, receiver) = std::sync::mpsc::channel();
        self.staging.map_async(wgpu::MapMode::Read, .., move |mapped| {
            let _ = sender.send(mapped);
        });
        let _ = self.gpu.device.poll(wgpu::PollType::wait_indefinitely());
        match receiver.try_recv() {
            Ok(Ok(())) => {}
            Ok(Err(error)) => return Err(PipelineError::Readback(error.to_string())),
            Err(_) => return Err(PipelineError::Readback("the device finished without mapping the results".into())),
        }
        let mut images = Vec::with_capacity(self.pipeline.sinks.len());
        {
            let view = self.staging.get_mapped_range(..).map_err(|e| PipelineError::Readback(e.to_string()))?;
            let all: &[f32] = bytemuck::cast_slice(&view);
            let mut start = 0;
            for &sink in &self.pipeline.sinks {
                let shape = self.pipeline.shape(sink);
                let data = all[start..start + shape.len()].to_vec();
                start += shape.len();
                images.push(Image { width: shape.width, height: shape.height, planes: shape.planes, data });
            }
        }
        self.staging.unmap();
        Ok(images)
    }

    /// Changes the parameters of step `index` (same kernel, same shapes), e.g. the pose of an
    /// ICP iteration.
    pub fn set_kernel(&mut self, index: usize, kernel: Kernel) -> Result<(), PipelineError> {
        let step = self.pipeline.steps.get_mut(index).ok_or(PipelineError::UnknownStep(index))?;
        if step.kernel.name() != kernel.name() {
            return Err(PipelineError::KernelChanged { step: index, was: step.kernel.name(), given: kernel.name() });
        }
        step.kernel = kernel;
        self.steps[index].set_kernel(self.gpu, kernel)
    }

    /// Uploads the sources, then times each step on its own (submit and wait, or the compute
    /// pass by the GPU's clock on a [`Gpu::with_timestamps`]), without readback.
    pub fn time_steps(&self, sources: &[Image]) -> Result<Vec<Duration>, PipelineError> {
        self.upload(sources)?;
        self.reset_scratch();
        let _ = self.gpu.device.poll(wgpu::PollType::wait_indefinitely());
        Ok(self
            .steps
            .iter()
            .map(|step| {
                let start = Instant::now();
                let mut encoder = self.gpu.device.create_command_encoder(&Default::default());
                step.encode(&mut encoder, self.gpu.pass_timestamps());
                self.gpu.resolve_timestamps(&mut encoder);
                self.gpu.queue.submit([encoder.finish()]);
                let _ = self.gpu.device.poll(wgpu::PollType::wait_indefinitely());
                let elapsed = start.elapsed();
                // A timestamp that cannot be read back leaves the wall time.
                self.gpu.device_time().ok().flatten().unwrap_or(elapsed)
            })
            .collect())
    }

    fn upload(&self, sources: &[Image]) -> Result<(), PipelineError> {
        self.pipeline.check_sources(sources)?;
        for (&slot, image) in self.pipeline.sources.iter().zip(sources) {
            self.gpu.queue.write_buffer(&self.buffers[slot.0], 0, bytemuck::cast_slice(&image.data));
        }
        Ok(())
    }

    fn reset_scratch(&self) {
        for step in &self.steps {
            step.reset_scratch(self.gpu);
        }
    }

    /// The slot buffers (for tests that look inside).
    pub fn buffer(&self, slot: Slot) -> &wgpu::Buffer {
        &self.buffers[slot.0]
    }
}

/// A pipeline ready to run on the GPU when there is one, else on the CPU reference: what a
/// caller without a guaranteed adapter uses (`Gpu::new()`'s error says why there is none).
pub enum Prepared<'g> {
    Gpu(GpuPipeline<'g>),
    Cpu(Pipeline),
}

impl<'g> Prepared<'g> {
    pub fn new(gpu: Option<&'g Gpu>, pipeline: &Pipeline) -> Prepared<'g> {
        match gpu {
            Some(gpu) => Prepared::Gpu(GpuPipeline::new(gpu, pipeline)),
            None => Prepared::Cpu(pipeline.clone()),
        }
    }

    pub fn run(&self, sources: &[Image]) -> Result<Vec<Image>, PipelineError> {
        match self {
            Prepared::Gpu(prepared) => prepared.run(sources),
            Prepared::Cpu(pipeline) => run_cpu(pipeline, sources),
        }
    }

    pub fn on_gpu(&self) -> bool {
        matches!(self, Prepared::Gpu(_))
    }
}
