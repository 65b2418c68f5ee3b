//! One kernel bound to its buffers on a GPU: the uniform parameters, the compiled passes, the
//! bind group over its input and output buffers and a reduction's scratch, made once and
//! encoded into any command encoder as often as wanted. The executor keeps one in each of its
//! kernel slots, bound again only when its inputs change.

use crate::error::ChainError;
use crate::gpu::Gpu;
use crate::{Kernel, Shape};

/// A kernel, its parameters for inputs of fixed shapes, and the buffers it reads and writes.
pub struct BoundKernel {
    kernel: Kernel,
    inputs: Vec<Shape>,
    input_buffers: Vec<wgpu::Buffer>,
    params: wgpu::Buffer,
    passes: Vec<(wgpu::ComputePipeline, [u32; 3])>,
    bind_group: wgpu::BindGroup,
    scratch: Option<(wgpu::Buffer, Vec<u32>)>,
    outputs: Vec<(wgpu::Buffer, Shape)>,
}

impl BoundKernel {
    /// `kernel` over `inputs` (buffers of f32 samples and their shapes), writing into output
    /// buffers of its own.
    pub fn new(gpu: &Gpu, kernel: Kernel, inputs: &[(&wgpu::Buffer, Shape)]) -> Result<BoundKernel, ChainError> {
        let shapes: Vec<Shape> = inputs.iter().map(|(_, shape)| *shape).collect();
        kernel.check(&shapes)?;
        let outputs: Vec<wgpu::Buffer> =
            kernel.outputs(&shapes).iter().map(|shape| gpu.storage(kernel.name(), shape.len())).collect();
        Ok(BoundKernel::into(gpu, kernel, inputs, outputs))
    }

    /// `kernel` over `inputs` writing into `outputs` (checked by the caller: buffers of the
    /// sizes [`Kernel::outputs`] gives).
    pub(crate) fn into(
        gpu: &Gpu,
        kernel: Kernel,
        inputs: &[(&wgpu::Buffer, Shape)],
        outputs: Vec<wgpu::Buffer>,
    ) -> BoundKernel {
        let shapes: Vec<Shape> = inputs.iter().map(|(_, shape)| *shape).collect();
        let block = kernel.params(&shapes);
        let params = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("params"),
            size: block.len() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        gpu.queue.write_buffer(&params, 0, &block);
        let scratch = kernel.scratch(&shapes).map(|s| (gpu.storage("scratch", s.len), vec![s.start; s.len]));
        let layout = gpu.layout(inputs.len(), outputs.len() + usize::from(scratch.is_some()));
        let passes = kernel
            .passes(&shapes)
            .into_iter()
            .map(|pass| (gpu.pipeline(kernel.name(), pass.entry, kernel.source(), &layout), pass.workgroups))
            .collect();
        let mut resources: Vec<&wgpu::Buffer> = vec![&params];
        resources.extend(inputs.iter().map(|(buffer, _)| *buffer));
        resources.extend(&outputs);
        if let Some((buffer, _)) = &scratch {
            resources.push(buffer);
        }
        let entries: Vec<wgpu::BindGroupEntry> = resources
            .iter()
            .enumerate()
            .map(|(i, b)| wgpu::BindGroupEntry { binding: i as u32, resource: b.as_entire_binding() })
            .collect();
        let bind_group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &layout,
            entries: &entries,
        });
        let outputs = outputs.into_iter().zip(kernel.outputs(&shapes)).collect();
        let input_buffers = inputs.iter().map(|(buffer, _)| (*buffer).clone()).collect();
        BoundKernel { kernel, inputs: shapes, input_buffers, params, passes, bind_group, scratch, outputs }
    }

    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Whether it is bound to exactly these input buffers of these shapes.
    pub fn binds(&self, inputs: &[(&wgpu::Buffer, Shape)]) -> bool {
        inputs.len() == self.inputs.len()
            && inputs
                .iter()
                .zip(self.input_buffers.iter().zip(&self.inputs))
                .all(|((b, s), (mine, shape))| *b == mine && s == shape)
    }

    /// The output buffers and their shapes.
    pub fn outputs(&self) -> &[(wgpu::Buffer, Shape)] {
        &self.outputs
    }

    /// New parameters of the same kernel (only they change; shapes and buffers stay).
    pub fn set_kernel(&mut self, gpu: &Gpu, kernel: Kernel) -> Result<(), ChainError> {
        if kernel.name() != self.kernel.name() {
            return Err(ChainError::KernelChanged { step: 0, was: self.kernel.name(), given: kernel.name() });
        }
        if kernel != self.kernel {
            self.kernel = kernel;
            gpu.queue.write_buffer(&self.params, 0, &kernel.params(&self.inputs));
        }
        Ok(())
    }

    /// Sets a reduction's scratch buffer to its starting values (before each run).
    pub fn reset_scratch(&self, gpu: &Gpu) {
        if let Some((buffer, start)) = &self.scratch {
            gpu.queue.write_buffer(buffer, 0, bytemuck::cast_slice(start));
        }
    }

    /// Records the kernel's dispatches in one compute pass (timed by `timestamps` when given).
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>) {
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: None, timestamp_writes: timestamps });
        pass.set_bind_group(0, &self.bind_group, &[]);
        for (compute, groups) in &self.passes {
            pass.set_pipeline(compute);
            pass.dispatch_workgroups(groups[0], groups[1], groups[2]);
        }
    }
}
