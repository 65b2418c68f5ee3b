//! Where a pipeline's kernels run: on a GPU, every stage's dispatches recorded into one command
//! encoder per frame over buffers made once (a kernel bound to its inputs is reused frame after
//! frame), submitted at the end of the frame, when every read the sinks and stages asked for
//! comes back through one staging buffer in one mapping;
//! or on the CPU, each kernel's reference, for machines without an adapter. Stages cannot tell
//! the two apart.

use std::{sync::Arc, time::Duration};

use gudsl_runtime::{BoundKernel, Gpu, Image, Kernel, PipelineError, Shape};

use super::data::{Data, DepthImage, Picture, PointCloud, RawFrame, Tensor};

/// The GPU (or the CPU) and the frame's recording.
pub struct Device<'g> {
    gpu: Option<&'g Gpu>,
    encoder: Option<wgpu::CommandEncoder>,
    /// Reads asked for the end of the frame.
    later: Vec<Tensor>,
    staging: Option<wgpu::Buffer>,
    timing: Option<Timing>,
}

/// The GPU's clock around every kernel's pass: two timestamps a dispatch, resolved and read
/// back with the frame's reads.
struct Timing {
    queries: wgpu::QuerySet,
    capacity: u32,
    used: u32,
    resolved: wgpu::Buffer,
    period_ns: f32,
    /// The stage each pair of timestamps belongs to.
    owners: Vec<usize>,
}

/// A kernel slot a stage keeps across frames: the kernel bound to the buffers it last ran on.
#[derive(Default)]
pub struct KernelSlot(Option<BoundKernel>);

/// A buffer a stage keeps across frames for data it uploads or keeps.
#[derive(Default)]
pub struct BufferSlot(Option<(wgpu::Buffer, Shape)>);

/// A read asked for at the end of the frame: its index among the frame's reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Later(usize);

impl<'g> Device<'g> {
    /// A device on `gpu`, or the CPU reference without one; with `gpu`'s timestamp queries
    /// (a [`Gpu::with_timestamps`]) every kernel is timed on the GPU.
    pub fn new(gpu: Option<&'g Gpu>) -> Device<'g> {
        let timing = gpu.filter(|gpu| gpu.times_on_device()).map(|gpu| Timing::new(gpu, 64));
        Device { gpu, encoder: None, later: Vec::new(), staging: None, timing }
    }

    /// The GPU, `None` on the CPU reference.
    pub fn gpu(&self) -> Option<&'g Gpu> {
        self.gpu
    }

    /// Records `stage`'s work outside the runtime's kernels (a generated kernel, a conversion)
    /// into the frame's encoder, with the stage's timestamps for its pass; `None` on the CPU.
    pub fn record<R>(
        &mut self,
        stage: usize,
        work: impl FnOnce(&Gpu, &mut wgpu::CommandEncoder, Option<wgpu::ComputePassTimestampWrites<'_>>) -> R,
    ) -> Option<R> {
        let gpu = self.gpu?;
        let writes = self.timing.as_mut().and_then(|t| t.next(stage));
        let encoder = self.encoder.get_or_insert_with(|| gpu.device.create_command_encoder(&Default::default()));
        Some(work(gpu, encoder, timestamp_writes(&writes)))
    }

    /// `kernel` on `inputs` for `stage`, its results where the inputs are.
    pub fn kernel(
        &mut self,
        stage: usize,
        slot: &mut KernelSlot,
        kernel: Kernel,
        inputs: &[&Tensor],
    ) -> Result<Vec<Tensor>, PipelineError> {
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

    /// `data` with its GPU images copied into buffers of their own, so it outlives the frame
    /// (a queued item: its producer writes its buffers again next frame).
    pub fn detached(&mut self, data: &Data) -> Data {
        let mut copy = |t: &Tensor| self.keep(&mut BufferSlot::default(), t);
        match data {
            Data::Raw(frame) => Data::Raw(RawFrame {
                raw: copy(&frame.raw),
                black: frame.black.as_ref().map(&mut copy),
                ..frame.clone()
            }),
            Data::Depth(depth) => Data::Depth(DepthImage {
                distance: copy(&depth.distance),
                amplitude: copy(&depth.amplitude),
                intensity: copy(&depth.intensity),
                ..depth.clone()
            }),
            Data::Mask(mask) => Data::Mask(copy(mask)),
            Data::Image(picture) => {
                Data::Image(Picture { texels: copy(&picture.texels), source: picture.source.clone() })
            }
            Data::Cloud(PointCloud::Organized { points, normals }) => {
                Data::Cloud(PointCloud::Organized { points: copy(points), normals: copy(normals) })
            }
            other => other.clone(),
        }
    }

    /// Submits the work recorded so far: a stage on another thread that reads its results then
    /// submits after it.
    pub fn flush(&mut self) -> Result<(), PipelineError> {
        match (self.gpu, self.encoder.take()) {
            (Some(gpu), Some(encoder)) => submit(gpu, encoder),
            _ => Ok(()),
        }
    }

    /// Asks for `tensor`'s samples at the end of the frame ([`Device::end_frame`]).
    pub fn read_later(&mut self, tensor: &Tensor) -> Later {
        self.later.push(tensor.clone());
        Later(self.later.len() - 1)
    }

    /// Submits the work recorded so far and reads `tensors` back at once: for a stage that
    /// needs a result before it can go on (ICP's sums each iteration, a cloud to accumulate).
    pub fn read_now(&mut self, tensors: &[&Tensor]) -> Result<Vec<Arc<Image>>, PipelineError> {
        let tensors: Vec<Tensor> = tensors.iter().map(|t| (*t).clone()).collect();
        self.read(&tensors)
    }

    /// Submits the frame's work and reads back what was asked for, in one mapping; with the
    /// GPU time each stage's kernels took.
    pub fn end_frame(&mut self) -> Result<(Reads, Vec<(usize, Duration)>), PipelineError> {
        let later = std::mem::take(&mut self.later);
        let images = self.read(&later)?;
        let times = match (&mut self.timing, self.gpu) {
            (Some(timing), Some(gpu)) => timing.take(gpu)?,
            _ => Vec::new(),
        };
        Ok((Reads(images), times))
    }

    /// Submits the recorded work and reads `tensors` back through one staging buffer.
    fn read(&mut self, tensors: &[Tensor]) -> Result<Vec<Arc<Image>>, PipelineError> {
        let Some(gpu) = self.gpu else { return Ok(tensors.iter().map(host).collect()) };
        let bytes: u64 = tensors.iter().map(|t| (t.shape().len().max(1) * 4) as u64).sum();
        let mut encoder = self.encoder.take().unwrap_or_else(|| gpu.device.create_command_encoder(&Default::default()));
        if let Some(timing) = &self.timing {
            timing.resolve(&mut encoder);
        }
        if bytes == 0 || tensors.iter().all(|t| matches!(t, Tensor::Cpu(_))) {
            submit(gpu, encoder)?;
            return Ok(tensors.iter().map(host).collect());
        }
        if self.staging.as_ref().is_none_or(|s| s.size() < bytes) {
            self.staging = Some(gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pipeline reads"),
                size: bytes,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }));
        }
        let staging = self.staging.as_ref().expect("made above");
        let mut offset = 0;
        for tensor in tensors {
            if let Tensor::Gpu { buffer, shape } = tensor {
                encoder.copy_buffer_to_buffer(buffer, 0, staging, offset, (shape.len() * 4) as u64);
            }
            offset += (tensor.shape().len().max(1) * 4) as u64;
        }
        submit(gpu, encoder)?;
        let images = gpu.with_mapped(staging, |bytes| {
            let samples: &[f32] = bytemuck::cast_slice(bytes);
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
        });
        images.map_err(PipelineError::Readback)
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

/// Finishes and submits the frame's recording: what the device refuses in it (a generated
/// kernel's binding, say) is an error, not wgpu's panic.
fn submit(gpu: &Gpu, encoder: wgpu::CommandEncoder) -> Result<(), PipelineError> {
    gpu.scoped(|| gpu.queue.submit([encoder.finish()])).map(drop).map_err(PipelineError::Readback)
}

/// A pass's timestamps at the pair of queries `writes` names (none when the set is full).
fn timestamp_writes(writes: &Option<(wgpu::QuerySet, u32)>) -> Option<wgpu::ComputePassTimestampWrites<'_>> {
    writes.as_ref().map(|(queries, at)| wgpu::ComputePassTimestampWrites {
        query_set: queries,
        beginning_of_pass_write_index: Some(*at),
        end_of_pass_write_index: Some(at + 1),
    })
}

/// A tensor known to be in host memory (on the CPU device every tensor is).
fn host(tensor: &Tensor) -> Arc<Image> {
    match tensor {
        Tensor::Cpu(image) => image.clone(),
        Tensor::Gpu { .. } => unreachable!("GPU tensors exist only on a GPU device"),
    }
}

/// The images read at the end of a frame, by the [`Later`] each was asked for with.
#[derive(Clone)]
pub struct Reads(Vec<Arc<Image>>);

impl Reads {
    pub fn get(&self, later: Later) -> &Arc<Image> {
        &self.0[later.0]
    }
}

impl Timing {
    fn new(gpu: &Gpu, capacity: u32) -> Timing {
        let queries = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("stage timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: capacity,
        });
        let resolved = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("stage timestamps"),
            size: capacity as u64 * 8,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Timing { queries, capacity, used: 0, resolved, period_ns: gpu.queue.get_timestamp_period(), owners: Vec::new() }
    }

    /// The query set and the index of the next pair of timestamps, for `stage`; `None` when
    /// the set is full this frame (it grows for the next).
    fn next(&mut self, stage: usize) -> Option<(wgpu::QuerySet, u32)> {
        if self.used + 2 > self.capacity {
            return None;
        }
        let at = self.used;
        self.used += 2;
        self.owners.push(stage);
        Some((self.queries.clone(), at))
    }

    fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        if self.used > 0 {
            encoder.resolve_query_set(&self.queries, 0..self.used, &self.resolved, 0);
        }
    }

    /// The time each timed pass took, by stage, and a fresh set for the next frame.
    fn take(&mut self, gpu: &Gpu) -> Result<Vec<(usize, Duration)>, PipelineError> {
        if self.used == 0 {
            return Ok(Vec::new());
        }
        let bytes = gpu.download(&self.resolved, self.used as u64 * 8).map_err(PipelineError::Readback)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let times = self
            .owners
            .iter()
            .enumerate()
            .map(|(k, &stage)| {
                let ns = ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * self.period_ns as f64;
                (stage, Duration::from_nanos(ns as u64))
            })
            .collect();
        let full = self.owners.len() as u32 * 2 >= self.capacity;
        self.used = 0;
        self.owners.clear();
        if full {
            *self = Timing::new(gpu, self.capacity * 2);
        }
        Ok(times)
    }
}
