//! The headless wgpu context: any adapter (a real GPU, or Mesa's lavapipe/llvmpipe on machines
//! without one), one device and queue, compute pipelines built once per kernel and reused, and
//! the buffer helpers the executor uses.

use std::{collections::HashMap, fmt, sync::Mutex};

use wgpu::util::DeviceExt;

/// Why no GPU context could be made; the runtime then runs the CPU reference instead.
#[derive(Debug, Clone, PartialEq)]
pub struct GpuUnavailable(pub String);

impl fmt::Display for GpuUnavailable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "no GPU adapter: {} (install a GPU driver, or Mesa's lavapipe: the Debian package mesa-vulkan-drivers)",
            self.0
        )
    }
}

impl std::error::Error for GpuUnavailable {}

/// Keeps a headless machine's terminal clean: without `XDG_RUNTIME_DIR` there is no Wayland
/// session, yet Mesa's implicit Vulkan layer `VK_LAYER_MESA_device_select` tries to connect to
/// one while it orders the adapters, and libwayland prints "error: XDG_RUNTIME_DIR is invalid
/// or not set in the environment." to the user's terminal. There, `NODEVICE_SELECT=1` turns the
/// layer off (it has no display to choose by); a value the user set is kept. Call it first in
/// `main`, before any thread starts (it sets an environment variable).
pub fn quiet_headless_adapters() {
    let runtime_dir = std::env::var_os("XDG_RUNTIME_DIR").map(std::path::PathBuf::from);
    let headless = runtime_dir.is_none_or(|dir| !dir.is_dir());
    if headless && std::env::var_os("NODEVICE_SELECT").is_none() {
        std::env::set_var("NODEVICE_SELECT", "1");
    }
}

/// A device and queue with a cache of compute pipelines by kernel and entry point; shared by
/// threads (a pipeline's stages that run apart).
pub struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter: wgpu::AdapterInfo,
    pipelines: Mutex<HashMap<(&'static str, &'static str), wgpu::ComputePipeline>>,
    /// Whether the device has timestamp queries enabled (see [`Gpu::with_timestamps`]).
    timestamps: bool,
}

impl Gpu {
    /// The first adapter wgpu offers (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME` and the other wgpu
    /// environment variables are honoured).
    pub fn new() -> Result<Gpu, GpuUnavailable> {
        Gpu::open(false)
    }

    /// As [`Gpu::new`], with the adapter's timestamp queries where it has them: then the
    /// executor times every kernel, and [`crate::Program::dispatch`] its pass, by the GPU's own
    /// clock (the compute pass alone, without submission and synchronisation), at the cost of
    /// reading the clock back: for benchmarks. [`Gpu::times_on_device`] says whether it does.
    pub fn with_timestamps() -> Result<Gpu, GpuUnavailable> {
        Gpu::open(true)
    }

    /// Whether passes are timed by the GPU's clock (see [`Gpu::with_timestamps`]).
    pub fn times_on_device(&self) -> bool {
        self.timestamps
    }

    fn open(timestamps: bool) -> Result<Gpu, GpuUnavailable> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::from_env().unwrap_or(wgpu::PowerPreference::HighPerformance),
            ..Default::default()
        };
        let adapter =
            pollster::block_on(instance.request_adapter(&options)).map_err(|e| GpuUnavailable(e.to_string()))?;
        let timestamps = timestamps && adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("gudsl-runtime"),
            required_features: if timestamps { wgpu::Features::TIMESTAMP_QUERY } else { wgpu::Features::empty() },
            // Image buffers are large: take what the adapter offers.
            required_limits: adapter.limits(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        };
        let (device, queue) =
            pollster::block_on(adapter.request_device(&descriptor)).map_err(|e| GpuUnavailable(e.to_string()))?;
        Ok(Gpu { device, queue, adapter: adapter.get_info(), pipelines: Mutex::default(), timestamps })
    }

    /// The device tests run on: `None` only where `GUDSL_NO_GPU=1` says the machine has no
    /// adapter on purpose (otherwise a missing adapter is a failure, not a skipped test); when
    /// `WGPU_BACKEND` asks for a backend, asserts that it is the one wgpu picked (`scripts/test`
    /// runs the GPU tests once more on OpenGL).
    pub fn for_tests() -> Option<Gpu> {
        match Gpu::new() {
            Ok(gpu) => {
                eprintln!("adapter: {}", gpu.describe());
                if let Ok(wanted) = std::env::var("WGPU_BACKEND") {
                    let described = gpu.describe().to_lowercase();
                    assert!(
                        described.contains(&format!("({}", wanted.to_lowercase())),
                        "asked for {wanted}, got {described}"
                    );
                }
                Some(gpu)
            }
            Err(error) if std::env::var_os("GUDSL_NO_GPU").is_some() => {
                eprintln!("skipped: {error}");
                None
            }
            Err(error) => panic!("{error}; set GUDSL_NO_GPU=1 on a machine without one"),
        }
    }

    /// "name (backend, device type)".
    pub fn describe(&self) -> String {
        format!("{} ({:?}, {:?})", self.adapter.name, self.adapter.backend, self.adapter.device_type)
    }

    /// The bind group layout of a kernel with `inputs` read-only and `outputs` read-write storage
    /// buffers (the last `scratch` of them u32 scratch), after the uniform parameters at 0.
    pub fn layout(&self, inputs: usize, outputs: usize) -> wgpu::BindGroupLayout {
        let storage = |binding: u32, read_only: bool| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Storage { read_only },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        };
        let mut entries = vec![wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }];
        entries.extend((0..inputs).map(|i| storage(1 + i as u32, true)));
        entries.extend((0..outputs).map(|i| storage(1 + (inputs + i) as u32, false)));
        self.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor { label: None, entries: &entries })
    }

    /// The compute pipeline of entry point `entry` of the kernel `name`, built from `source`
    /// with `layout` the first time it is asked for.
    pub fn pipeline(
        &self,
        name: &'static str,
        entry: &'static str,
        source: &str,
        layout: &wgpu::BindGroupLayout,
    ) -> wgpu::ComputePipeline {
        let key = (name, entry);
        if let Some(pipeline) = self.cached(&key) {
            return pipeline;
        }
        let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(name),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline_layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(layout)],
            immediate_size: 0,
        });
        let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: Some(&pipeline_layout),
            module: &module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            cache: None,
        });
        self.pipelines.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).insert(key, pipeline.clone());
        pipeline
    }

    fn cached(&self, key: &(&'static str, &'static str)) -> Option<wgpu::ComputePipeline> {
        self.pipelines.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).get(key).cloned()
    }

    /// A storage buffer of `len` f32 samples, readable and writable by kernels, copyable both ways.
    pub fn storage(&self, label: &str, len: usize) -> wgpu::Buffer {
        self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: (len.max(1) * 4) as u64,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        })
    }

    /// A uniform buffer holding `value`.
    pub fn uniform<T: bytemuck::Pod>(&self, label: &str, value: &T) -> wgpu::Buffer {
        self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: bytemuck::bytes_of(value),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        })
    }

    /// Reads `len` f32 samples of `buffer` back to the CPU (waits for the queue).
    pub fn read(&self, buffer: &wgpu::Buffer, len: usize) -> Vec<f32> {
        let bytes = self.download(buffer, (len.max(1) * 4) as u64).expect("a mapped readback buffer");
        bytemuck::cast_slice::<u8, f32>(&bytes)[..len].to_vec()
    }

    /// The first `size` bytes of `buffer` (a multiple of 4), copied back to the CPU (waits).
    pub fn download(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, String> {
        let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = self.device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        self.queue.submit([encoder.finish()]);
        self.map_read(&staging)
    }

    /// The contents of a `MAP_READ` buffer once the queue has written it (waits).
    /// `make`'s value, or the validation or out-of-memory error the device raised while it ran
    /// (wgpu's errors caught in error scopes instead of its default handler's panic).
    pub fn scoped<T>(&self, make: impl FnOnce() -> T) -> Result<T, String> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let memory = self.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let value = make();
        let out_of_memory = pollster::block_on(memory.pop());
        let invalid = pollster::block_on(scope.pop());
        match out_of_memory.or(invalid) {
            None => Ok(value),
            Some(error) => Err(error.to_string()),
        }
    }

    pub fn map_read(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, String> {
        self.with_mapped(staging, <[u8]>::to_vec)
    }

    /// `read` of the bytes of `staging` (mapped for reading after the queue's work is done),
    /// without copying them first.
    pub fn with_mapped<T>(&self, staging: &wgpu::Buffer, read: impl FnOnce(&[u8]) -> T) -> Result<T, String> {
        let mapping = Gpu::map(staging);
        self.read_mapped(staging, mapping, None, read)
    }

    /// Asks for `staging` to be mapped for reading once the work submitted so far that writes
    /// it is done; [`Gpu::read_mapped`] waits for it.
    pub fn map(staging: &wgpu::Buffer) -> Mapping {
        let (sender, receiver) = std::sync::mpsc::channel();
        staging.map_async(wgpu::MapMode::Read, .., move |result| {
            let _ = sender.send(result);
        });
        Mapping(receiver)
    }

    /// `read` of the bytes of `staging` once its `mapping` is done: after `submission` (the
    /// one that fills it; `None`: everything submitted so far), not the submissions after it.
    pub fn read_mapped<T>(
        &self,
        staging: &wgpu::Buffer,
        mapping: Mapping,
        submission: Option<wgpu::SubmissionIndex>,
        read: impl FnOnce(&[u8]) -> T,
    ) -> Result<T, String> {
        let done = wgpu::PollType::Wait { submission_index: submission, timeout: None };
        self.device.poll(done).map_err(|e| e.to_string())?;
        let mapped = match mapping.0.try_recv() {
            Ok(result) => result,
            // Done, but its callback not yet called: the next poll calls it.
            Err(_) => {
                self.device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| e.to_string())?;
                mapping.0.recv().map_err(|_| "the readback was dropped".to_string())?
            }
        };
        mapped.map_err(|e| e.to_string())?;
        let value = read(&staging.get_mapped_range(..).map_err(|e| e.to_string())?);
        staging.unmap();
        Ok(value)
    }
}

/// A buffer being mapped for reading ([`Gpu::map`]): told when it is.
pub struct Mapping(std::sync::mpsc::Receiver<Result<(), wgpu::BufferAsyncError>>);
