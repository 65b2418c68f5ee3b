//! Programs the runtime did not write: a WGSL compute module handed over at run time (the code
//! generator's kernels of chapter 10) with the layout of its bindings, the device buffers and
//! images it reads and writes, and timed dispatches with pipeline constants (work-group size,
//! work-group memory). Every wgpu validation error is a [`ProgramError`], never a panic.

use std::{
    cell::RefCell,
    collections::HashMap,
    fmt,
    time::{Duration, Instant},
};

use wgpu::util::DeviceExt;

use crate::{timing::Timing, Gpu};

/// The texel formats of the GPGPU extension's image types (`image2D_uc` → `Rgba8Uint`, …).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TexelFormat {
    Rgba8Uint,
    Rgba8Sint,
    Rgba16Uint,
    Rgba16Sint,
    Rgba32Uint,
    Rgba32Sint,
    Rgba32Float,
}

impl TexelFormat {
    /// The format WGSL calls `name` (`rgba8uint`).
    pub fn from_wgsl(name: &str) -> Option<TexelFormat> {
        Some(match name {
            "rgba8uint" => TexelFormat::Rgba8Uint,
            "rgba8sint" => TexelFormat::Rgba8Sint,
            "rgba16uint" => TexelFormat::Rgba16Uint,
            "rgba16sint" => TexelFormat::Rgba16Sint,
            "rgba32uint" => TexelFormat::Rgba32Uint,
            "rgba32sint" => TexelFormat::Rgba32Sint,
            "rgba32float" => TexelFormat::Rgba32Float,
            _ => return None,
        })
    }

    /// Bytes of one texel (four channels).
    pub fn bytes_per_texel(self) -> u32 {
        match self {
            TexelFormat::Rgba8Uint | TexelFormat::Rgba8Sint => 4,
            TexelFormat::Rgba16Uint | TexelFormat::Rgba16Sint => 8,
            TexelFormat::Rgba32Uint | TexelFormat::Rgba32Sint | TexelFormat::Rgba32Float => 16,
        }
    }

    fn wgpu(self) -> wgpu::TextureFormat {
        match self {
            TexelFormat::Rgba8Uint => wgpu::TextureFormat::Rgba8Uint,
            TexelFormat::Rgba8Sint => wgpu::TextureFormat::Rgba8Sint,
            TexelFormat::Rgba16Uint => wgpu::TextureFormat::Rgba16Uint,
            TexelFormat::Rgba16Sint => wgpu::TextureFormat::Rgba16Sint,
            TexelFormat::Rgba32Uint => wgpu::TextureFormat::Rgba32Uint,
            TexelFormat::Rgba32Sint => wgpu::TextureFormat::Rgba32Sint,
            TexelFormat::Rgba32Float => wgpu::TextureFormat::Rgba32Float,
        }
    }

    fn sample_type(self) -> wgpu::TextureSampleType {
        match self {
            TexelFormat::Rgba8Uint | TexelFormat::Rgba16Uint | TexelFormat::Rgba32Uint => wgpu::TextureSampleType::Uint,
            TexelFormat::Rgba8Sint | TexelFormat::Rgba16Sint | TexelFormat::Rgba32Sint => wgpu::TextureSampleType::Sint,
            TexelFormat::Rgba32Float => wgpu::TextureSampleType::Float { filterable: false },
        }
    }
}

/// What a binding of a program holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BindingKind {
    /// A uniform block, given as bytes at each dispatch.
    Uniform,
    /// A storage buffer (`array<T>`).
    Storage { writable: bool },
    /// A texture the program loads texels from.
    Texture { format: TexelFormat, dimensions: u8 },
    /// A storage texture the program writes (and reads, when `read`).
    StorageTexture { format: TexelFormat, dimensions: u8, read: bool },
}

/// One binding of group 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BindingSpec {
    pub binding: u32,
    pub kind: BindingKind,
}

/// A resource handed to one binding at a dispatch.
#[derive(Clone, Copy)]
pub enum Resource<'a> {
    Uniform(&'a [u8]),
    Buffer(&'a DeviceBuffer),
    Image(&'a DeviceImage),
}

/// What went wrong compiling or running a program, or moving its data.
#[derive(Debug, Clone, PartialEq)]
pub enum ProgramError {
    /// The device refused the module or its pipeline.
    Compile { program: String, message: String },
    /// A resource that does not fit its binding (or a binding left without one).
    Bind { program: String, binding: u32, message: String },
    /// The device refused the dispatch, or more work-groups than it can run were asked for.
    Dispatch { program: String, message: String },
    /// Data of the wrong size for a buffer or an image.
    Data { what: String, expected: u64, given: u64 },
    /// The device refused a buffer or image (too large), or did not hand data back.
    Device(String),
}

impl fmt::Display for ProgramError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ProgramError::Compile { program, message } => {
                write!(f, "the GPU did not accept kernel `{program}`: {message}")
            }
            ProgramError::Bind { program, binding, message } => {
                write!(f, "binding {binding} of kernel `{program}`: {message}")
            }
            ProgramError::Dispatch { program, message } => write!(f, "kernel `{program}` did not run: {message}"),
            ProgramError::Data { what, expected, given } => {
                write!(f, "{what} holds {expected} bytes, {given} given")
            }
            ProgramError::Device(message) => write!(f, "the GPU refused: {message}"),
        }
    }
}

impl std::error::Error for ProgramError {}

/// A compiled module and its entry point, with one pipeline per set of pipeline constants.
#[derive(Debug)]
pub struct Program {
    label: String,
    entry: String,
    bindings: Vec<BindingSpec>,
    module: wgpu::ShaderModule,
    group_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    pipelines: RefCell<HashMap<Vec<(String, u64)>, wgpu::ComputePipeline>>,
}

impl Program {
    /// Compiles `wgsl`, whose entry point `entry` uses exactly `bindings` of group 0.
    pub fn new(
        gpu: &Gpu,
        label: &str,
        wgsl: &str,
        entry: &str,
        bindings: &[BindingSpec],
    ) -> Result<Program, ProgramError> {
        let compile_error = |message| ProgramError::Compile { program: label.to_string(), message };
        let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings.iter().map(layout_entry).collect();
        let (module, group_layout, layout) = gpu
            .scoped(|| {
                let module = gpu.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(label),
                    source: wgpu::ShaderSource::Wgsl(wgsl.into()),
                });
                let group_layout = gpu.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(label),
                    entries: &entries,
                });
                let layout = gpu.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(label),
                    bind_group_layouts: &[Some(&group_layout)],
                    immediate_size: 0,
                });
                (module, group_layout, layout)
            })
            .map_err(compile_error)?;
        Ok(Program {
            label: label.to_string(),
            entry: entry.to_string(),
            bindings: bindings.to_vec(),
            module,
            group_layout,
            layout,
            pipelines: RefCell::new(HashMap::new()),
        })
    }

    /// The pipeline for these pipeline constants, built the first time they are asked for.
    fn pipeline(&self, gpu: &Gpu, constants: &[(&str, f64)]) -> Result<wgpu::ComputePipeline, ProgramError> {
        let mut key: Vec<(String, u64)> =
            constants.iter().map(|(name, value)| (name.to_string(), value.to_bits())).collect();
        key.sort();
        if let Some(pipeline) = self.pipelines.borrow().get(&key) {
            return Ok(pipeline.clone());
        }
        let pipeline = gpu
            .scoped(|| {
                gpu.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(&self.label),
                    layout: Some(&self.layout),
                    module: &self.module,
                    entry_point: Some(&self.entry),
                    compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
                    cache: None,
                })
            })
            .map_err(|message| ProgramError::Compile { program: self.label.clone(), message })?;
        self.pipelines.borrow_mut().insert(key, pipeline.clone());
        Ok(pipeline)
    }

    /// Runs the entry point over `workgroups` with `resources` at their bindings and the pipeline
    /// constants `constants`; waits for the device and returns how long it took from submission
    /// (or, on a [`Gpu::with_timestamps`], the compute pass by the GPU's clock).
    pub fn dispatch(
        &self,
        gpu: &Gpu,
        constants: &[(&str, f64)],
        resources: &[(u32, Resource<'_>)],
        workgroups: [u32; 3],
    ) -> Result<Duration, ProgramError> {
        let dispatch_error = |message| ProgramError::Dispatch { program: self.label.clone(), message };
        let mut timing = Timing::new(gpu, 1);
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let writes = timing.as_mut().map(|t| t.next(gpu, 0));
        self.record(gpu, &mut encoder, constants, resources, workgroups, writes)?;
        if let Some(timing) = &timing {
            timing.resolve(&mut encoder);
        }
        let commands = gpu.scoped(|| encoder.finish()).map_err(dispatch_error)?;
        let start = Instant::now();
        gpu.scoped(|| gpu.queue.submit([commands])).map_err(dispatch_error)?;
        gpu.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| dispatch_error(e.to_string()))?;
        let elapsed = start.elapsed();
        let timed = match &mut timing {
            Some(timing) => timing.take(gpu).map_err(dispatch_error)?.first().map(|(_, time)| *time),
            None => None,
        };
        Ok(timed.unwrap_or(elapsed))
    }

    /// Records the dispatch [`Program::dispatch`] runs into `encoder`, with `timestamps` around
    /// its pass, for the caller to submit with other work (nothing waits).
    pub fn record(
        &self,
        gpu: &Gpu,
        encoder: &mut wgpu::CommandEncoder,
        constants: &[(&str, f64)],
        resources: &[(u32, Resource<'_>)],
        workgroups: [u32; 3],
        timestamps: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), ProgramError> {
        let limit = gpu.device.limits().max_compute_workgroups_per_dimension;
        if workgroups.iter().any(|&n| n > limit) {
            return Err(ProgramError::Dispatch {
                program: self.label.clone(),
                message: format!(
                    "{}×{}×{} work-groups asked for; the device runs at most {limit} per dimension",
                    workgroups[0], workgroups[1], workgroups[2]
                ),
            });
        }
        self.check_aliasing(resources)?;
        let pipeline = self.pipeline(gpu, constants)?;
        let uniforms = self.uniform_buffers(gpu, resources)?;
        let mut entries = Vec::with_capacity(self.bindings.len());
        for spec in &self.bindings {
            let resource = resources.iter().find(|(binding, _)| *binding == spec.binding).map(|(_, r)| *r);
            let bind_error =
                |message: String| ProgramError::Bind { program: self.label.clone(), binding: spec.binding, message };
            let resource = match (spec.kind, resource) {
                (_, None) => return Err(bind_error("no resource given".into())),
                (BindingKind::Uniform, Some(Resource::Uniform(_))) => {
                    let buffer = &uniforms.iter().find(|(binding, _)| *binding == spec.binding).expect("made above").1;
                    buffer.as_entire_binding()
                }
                (BindingKind::Storage { .. }, Some(Resource::Buffer(buffer))) => buffer.buffer.as_entire_binding(),
                (
                    BindingKind::Texture { format, dimensions }
                    | BindingKind::StorageTexture { format, dimensions, .. },
                    Some(Resource::Image(image)),
                ) => {
                    if image.format != format || image.dimensions != dimensions {
                        return Err(bind_error(format!(
                            "a {}D {:?} image is needed, a {}D {:?} image was given",
                            dimensions, format, image.dimensions, image.format
                        )));
                    }
                    wgpu::BindingResource::TextureView(&image.view)
                }
                (kind, Some(_)) => return Err(bind_error(format!("the resource given is not a {kind:?}"))),
            };
            entries.push(wgpu::BindGroupEntry { binding: spec.binding, resource });
        }
        let dispatch_error = |message| ProgramError::Dispatch { program: self.label.clone(), message };
        gpu.scoped(|| {
            let group = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(&self.label),
                layout: &self.group_layout,
                entries: &entries,
            });
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some(&self.label),
                timestamp_writes: timestamps,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(workgroups[0], workgroups[1], workgroups[2]);
        })
        .map_err(dispatch_error)
    }

    /// WebGPU forbids one buffer or image at two bindings of a dispatch when either binding
    /// writes it (OpenCL allows it): said with both bindings, before wgpu refuses.
    fn check_aliasing(&self, resources: &[(u32, Resource<'_>)]) -> Result<(), ProgramError> {
        let writes = |binding: u32| {
            self.bindings.iter().any(|spec| {
                spec.binding == binding
                    && matches!(spec.kind, BindingKind::Storage { writable: true } | BindingKind::StorageTexture { .. })
            })
        };
        for (i, (a, first)) in resources.iter().enumerate() {
            for (b, second) in &resources[i + 1..] {
                let same = match (first, second) {
                    (Resource::Buffer(x), Resource::Buffer(y)) => std::ptr::eq(*x, *y),
                    (Resource::Image(x), Resource::Image(y)) => std::ptr::eq(*x, *y),
                    _ => false,
                };
                if same && (writes(*a) || writes(*b)) {
                    return Err(ProgramError::Bind {
                        program: self.label.clone(),
                        binding: *b,
                        message: format!(
                            "it is given the same memory as binding {a}, and one of them is written; a kernel cannot read and write one buffer or image through two parameters (WebGPU forbids it): pass a copy"
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// A uniform buffer for each uniform binding given bytes.
    fn uniform_buffers(
        &self,
        gpu: &Gpu,
        resources: &[(u32, Resource<'_>)],
    ) -> Result<Vec<(u32, wgpu::Buffer)>, ProgramError> {
        let uniform_bindings = self.bindings.iter().filter(|spec| spec.kind == BindingKind::Uniform);
        uniform_bindings
            .filter_map(|spec| {
                resources.iter().find(|(binding, _)| *binding == spec.binding).and_then(|(binding, resource)| {
                    match resource {
                        Resource::Uniform(bytes) => Some((*binding, *bytes)),
                        _ => None,
                    }
                })
            })
            .map(|(binding, bytes)| {
                let buffer = gpu
                    .scoped(|| {
                        gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                            label: Some("uniforms"),
                            contents: bytes,
                            usage: wgpu::BufferUsages::UNIFORM,
                        })
                    })
                    .map_err(|message| ProgramError::Bind { program: self.label.clone(), binding, message })?;
                Ok((binding, buffer))
            })
            .collect()
    }
}

fn layout_entry(spec: &BindingSpec) -> wgpu::BindGroupLayoutEntry {
    let dimension = |dimensions: u8| match dimensions {
        3 => wgpu::TextureViewDimension::D3,
        _ => wgpu::TextureViewDimension::D2,
    };
    let ty = match spec.kind {
        BindingKind::Uniform => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        BindingKind::Storage { writable } => wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only: !writable },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        BindingKind::Texture { format, dimensions } => wgpu::BindingType::Texture {
            sample_type: format.sample_type(),
            view_dimension: dimension(dimensions),
            multisampled: false,
        },
        BindingKind::StorageTexture { format, dimensions, read } => wgpu::BindingType::StorageTexture {
            access: if read { wgpu::StorageTextureAccess::ReadWrite } else { wgpu::StorageTextureAccess::WriteOnly },
            format: format.wgpu(),
            view_dimension: dimension(dimensions),
        },
    };
    wgpu::BindGroupLayoutEntry { binding: spec.binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// Bytes in device memory that programs read and write (`array<T>` bindings).
#[derive(Debug)]
pub struct DeviceBuffer {
    buffer: wgpu::Buffer,
    len: u64,
}

impl DeviceBuffer {
    /// The whole of a buffer made elsewhere (storage use), shared with its owner.
    pub fn wrap(buffer: &wgpu::Buffer) -> DeviceBuffer {
        DeviceBuffer { buffer: buffer.clone(), len: buffer.size() }
    }

    /// A zeroed buffer of `len` bytes.
    pub fn new(gpu: &Gpu, label: &str, len: u64) -> Result<DeviceBuffer, ProgramError> {
        let size = len.max(4).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
        let buffer = gpu
            .scoped(|| {
                gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            })
            .map_err(|message| ProgramError::Device(format!("a buffer `{label}` of {len} bytes: {message}")))?;
        Ok(DeviceBuffer { buffer, len })
    }

    /// Its length in bytes.
    pub fn len(&self) -> u64 {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Replaces its contents with `bytes` (exactly its length).
    pub fn write(&self, gpu: &Gpu, bytes: &[u8]) -> Result<(), ProgramError> {
        if bytes.len() as u64 != self.len {
            return Err(ProgramError::Data {
                what: "the buffer".into(),
                expected: self.len,
                given: bytes.len() as u64,
            });
        }
        let mut padded = bytes.to_vec();
        padded.resize(self.buffer.size() as usize, 0);
        gpu.queue.write_buffer(&self.buffer, 0, &padded);
        Ok(())
    }

    /// Its contents (waits for the device).
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<u8>, ProgramError> {
        let mut bytes = gpu.download(&self.buffer, self.buffer.size()).map_err(ProgramError::Device)?;
        bytes.truncate(self.len as usize);
        Ok(bytes)
    }
}

/// A 2D or 3D image in device memory: a texture programs load from or store to.
#[derive(Debug)]
pub struct DeviceImage {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    format: TexelFormat,
    dimensions: u8,
    size: [u32; 3],
}

impl DeviceImage {
    /// A zeroed image of `size` texels (`size[2]` is 1 for a 2D image) in `format`.
    pub fn new(
        gpu: &Gpu,
        label: &str,
        format: TexelFormat,
        dimensions: u8,
        size: [u32; 3],
    ) -> Result<DeviceImage, ProgramError> {
        let refused = |message: String| {
            ProgramError::Device(format!("an image `{label}` of {}×{}×{}: {message}", size[0], size[1], size[2]))
        };
        if size.contains(&0) || (dimensions == 2 && size[2] != 1) {
            return Err(refused("an image has at least one texel per dimension (and a depth of 1 in 2D)".into()));
        }
        let texture = gpu
            .scoped(|| {
                gpu.device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: size[2] },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: if dimensions == 3 { wgpu::TextureDimension::D3 } else { wgpu::TextureDimension::D2 },
                    format: format.wgpu(),
                    usage: wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::COPY_DST
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                })
            })
            .map_err(refused)?;
        let view = texture.create_view(&Default::default());
        Ok(DeviceImage { texture, view, format, dimensions, size })
    }

    /// Width, height and depth in texels.
    pub fn size(&self) -> [u32; 3] {
        self.size
    }

    fn bytes(&self) -> u64 {
        self.size.iter().map(|&n| n as u64).product::<u64>() * self.format.bytes_per_texel() as u64
    }

    fn extent(&self) -> wgpu::Extent3d {
        wgpu::Extent3d { width: self.size[0], height: self.size[1], depth_or_array_layers: self.size[2] }
    }

    /// Replaces its texels with `bytes`: rows of texels, tightly packed, row after row, slice
    /// after slice.
    pub fn write(&self, gpu: &Gpu, bytes: &[u8]) -> Result<(), ProgramError> {
        if bytes.len() as u64 != self.bytes() {
            return Err(ProgramError::Data {
                what: "the image".into(),
                expected: self.bytes(),
                given: bytes.len() as u64,
            });
        }
        let row = self.size[0] * self.format.bytes_per_texel();
        gpu.queue.write_texture(
            self.texture.as_image_copy(),
            bytes,
            wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(row), rows_per_image: Some(self.size[1]) },
            self.extent(),
        );
        Ok(())
    }

    /// Its texels, packed as [`DeviceImage::write`] takes them (waits for the device).
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<u8>, ProgramError> {
        let row = (self.size[0] * self.format.bytes_per_texel()) as usize;
        let padded_row = row.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT as usize);
        let rows = (self.size[1] * self.size[2]) as usize;
        let staging = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("image readback"),
            size: (padded_row * rows) as u64,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            self.texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row as u32),
                    rows_per_image: Some(self.size[1]),
                },
            },
            self.extent(),
        );
        gpu.queue.submit([encoder.finish()]);
        let padded = gpu.map_read(&staging).map_err(ProgramError::Device)?;
        Ok(padded.chunks(padded_row).flat_map(|line| &line[..row]).copied().collect())
    }
}
