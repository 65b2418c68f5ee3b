//! Generated kernels on the runtime's device: a [`gudsl_codegen::Kernel`] compiled once into a
//! [`Program`], then launched with host arguments as OpenCL's `clSetKernelArg` and
//! `clEnqueueNDRangeKernel` take them (values, buffers, images, `shared` sizes in bytes; a global
//! size and an optional local size per work dimension).

use std::{fmt, time::Duration};

use gudsl_codegen::{Binding, Kernel, KernelParam, LOCAL_SIZE_CONSTANTS};
use gudsl_model::hir::Ty;
use gudsl_runtime::{
    BindingKind, BindingSpec, DeviceBuffer, DeviceImage, Executor, Gpu, Program, ProgramError, Resource, TexelFormat,
};

/// A scalar host value.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Number {
    Int(i64),
    UInt(u64),
    Float(f64),
    Bool(bool),
}

impl Number {
    pub fn as_i64(self) -> i64 {
        match self {
            Number::Int(v) => v,
            Number::UInt(v) => v as i64,
            Number::Float(v) => v as i64,
            Number::Bool(v) => v as i64,
        }
    }

    pub fn as_f64(self) -> f64 {
        match self {
            Number::Int(v) => v as f64,
            Number::UInt(v) => v as f64,
            Number::Float(v) => v,
            Number::Bool(v) => v as i64 as f64,
        }
    }
}

/// One argument of a kernel launch.
#[derive(Clone, Copy)]
pub enum Arg<'a> {
    /// A value parameter; for a `shared` parameter, its size in bytes.
    Number(Number),
    /// A vector value parameter, component by component.
    Vector(&'a [Number]),
    Buffer(&'a DeviceBuffer),
    Image(&'a DeviceImage),
}

/// The work of one launch: `global[d]` work-items in each of the first `dimensions`
/// dimensions, in work-groups of `local` (chosen when `None`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WorkRange {
    pub dimensions: u32,
    pub global: [u32; 3],
    pub local: Option<[u32; 3]>,
}

impl WorkRange {
    /// A 1D range of `global` work-items.
    pub fn linear(global: u32, local: Option<u32>) -> WorkRange {
        WorkRange { dimensions: 1, global: [global, 1, 1], local: local.map(|l| [l, 1, 1]) }
    }

    /// A 2D range of `width × height` work-items.
    pub fn planar(width: u32, height: u32, local: Option<[u32; 2]>) -> WorkRange {
        WorkRange { dimensions: 2, global: [width, height, 1], local: local.map(|[x, y]| [x, y, 1]) }
    }
}

/// Why a kernel did not launch.
#[derive(Debug, Clone, PartialEq)]
pub enum LaunchError {
    /// An argument that does not fit its parameter.
    Argument {
        kernel: String,
        param: String,
        message: String,
    },
    /// A work range the kernel cannot run over.
    Range {
        kernel: String,
        message: String,
    },
    Program(ProgramError),
}

impl fmt::Display for LaunchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LaunchError::Argument { kernel, param, message } => {
                write!(f, "argument `{param}` of kernel `{kernel}`: {message}")
            }
            LaunchError::Range { kernel, message } => write!(f, "kernel `{kernel}`: {message}"),
            LaunchError::Program(error) => error.fmt(f),
        }
    }
}

impl std::error::Error for LaunchError {}

impl From<ProgramError> for LaunchError {
    fn from(error: ProgramError) -> LaunchError {
        LaunchError::Program(error)
    }
}

/// A generated kernel compiled for one device.
pub struct Launcher {
    kernel: Kernel,
    program: Program,
}

impl Launcher {
    /// Compiles `kernel` on `gpu`.
    pub fn new(gpu: &Gpu, kernel: &Kernel) -> Result<Launcher, LaunchError> {
        let mut bindings = vec![BindingSpec { binding: 0, kind: BindingKind::Uniform }];
        for param in &kernel.params {
            match &param.binding {
                Binding::Storage { binding, writable } => {
                    bindings.push(BindingSpec { binding: *binding, kind: BindingKind::Storage { writable: *writable } })
                }
                Binding::Image { binding, image, read, written } => {
                    let format = TexelFormat::from_wgsl(image.format).ok_or_else(|| LaunchError::Argument {
                        kernel: kernel.diagram.clone(),
                        param: param.name.clone(),
                        message: format!("no device format `{}`", image.format),
                    })?;
                    let dimensions = image.dimensions;
                    let kind = if *written {
                        BindingKind::StorageTexture { format, dimensions, read: *read }
                    } else {
                        BindingKind::Texture { format, dimensions }
                    };
                    bindings.push(BindingSpec { binding: *binding, kind });
                }
                Binding::Uniform { .. } | Binding::Workgroup { .. } => {}
            }
        }
        let program = Program::new(gpu, &kernel.diagram, &kernel.wgsl, &kernel.entry_point, &bindings)?;
        Ok(Launcher { kernel: kernel.clone(), program })
    }

    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// Runs the kernel over `range` with `args` (one per parameter, in order); returns the time
    /// from submission to completion.
    pub fn launch(&self, gpu: &Gpu, args: &[Arg<'_>], range: &WorkRange) -> Result<Duration, LaunchError> {
        self.bound(gpu, args, range, |constants, resources, workgroups| {
            self.program.dispatch(gpu, constants, resources, workgroups)
        })
    }

    /// Records the launch into `executor`'s frame as `stage`'s work (timed with the stage), for
    /// the executor to submit with the frame; a launch needs the executor's GPU.
    pub fn record(
        &self,
        executor: &mut Executor,
        stage: usize,
        args: &[Arg<'_>],
        range: &WorkRange,
    ) -> Result<(), LaunchError> {
        let Some(gpu) = executor.gpu() else {
            let message = "a generated kernel runs on a GPU, and this run has none".to_string();
            return Err(LaunchError::Program(ProgramError::Device(message)));
        };
        self.bound(gpu, args, range, |constants, resources, workgroups| {
            executor.dispatch(stage, &self.program, constants, resources, workgroups)
        })
    }

    /// `args` checked against the parameters and packed as the program takes them (pipeline
    /// constants, resources at their bindings, work-groups), handed to `dispatch`.
    fn bound<R>(
        &self,
        gpu: &Gpu,
        args: &[Arg<'_>],
        range: &WorkRange,
        dispatch: impl FnOnce(&[(&str, f64)], &[(u32, Resource<'_>)], [u32; 3]) -> Result<R, ProgramError>,
    ) -> Result<R, LaunchError> {
        let kernel = &self.kernel;
        if args.len() != kernel.params.len() {
            return Err(LaunchError::Range {
                kernel: kernel.diagram.clone(),
                message: format!("{} argument(s) given, it takes {}", args.len(), kernel.params.len()),
            });
        }
        let local = self.local_size(gpu, range)?;
        let mut uniform = vec![0u8; kernel.uniform.size as usize];
        let mut resources = Vec::new();
        let mut lengths: Vec<(String, f64)> = Vec::new();
        for (param, arg) in kernel.params.iter().zip(args) {
            let wrong = |message: String| LaunchError::Argument {
                kernel: kernel.diagram.clone(),
                param: param.name.clone(),
                message,
            };
            match (&param.binding, arg) {
                (Binding::Uniform { offset }, Arg::Number(number)) => {
                    write_value(&mut uniform, *offset, param, std::slice::from_ref(number)).map_err(wrong)?
                }
                (Binding::Uniform { offset }, Arg::Vector(numbers)) => {
                    write_value(&mut uniform, *offset, param, numbers).map_err(wrong)?
                }
                (Binding::Storage { binding, .. }, Arg::Buffer(buffer)) => {
                    resources.push((*binding, Resource::Buffer(buffer)))
                }
                (Binding::Image { binding, .. }, Arg::Image(image)) => {
                    resources.push((*binding, Resource::Image(image)))
                }
                (Binding::Workgroup { length_constant, element_size }, Arg::Number(bytes)) => {
                    let bytes = bytes.as_i64();
                    let limit = gpu.device.limits().max_compute_workgroup_storage_size as i64;
                    if bytes <= 0 || bytes % *element_size as i64 != 0 || bytes > limit {
                        return Err(wrong(format!(
                            "work-group memory of {bytes} bytes: it takes a positive multiple of {element_size} bytes (one element), at most {limit}"
                        )));
                    }
                    lengths.push((length_constant.clone(), (bytes / *element_size as i64) as f64));
                }
                (binding, _) => {
                    return Err(wrong(format!("it is bound as {binding:?}; the argument given does not fit")))
                }
            }
        }
        let global_size: Vec<u8> = range.global.iter().flat_map(|n| n.to_le_bytes()).collect();
        let at = kernel.uniform.global_size_offset as usize;
        uniform[at..at + 12].copy_from_slice(&global_size);
        let at = kernel.uniform.work_dim_offset as usize;
        uniform[at..at + 4].copy_from_slice(&range.dimensions.to_le_bytes());
        resources.push((0, Resource::Uniform(&uniform)));

        let mut constants: Vec<(&str, f64)> =
            LOCAL_SIZE_CONSTANTS.into_iter().zip(local).map(|(name, size)| (name, size as f64)).collect();
        constants.extend(lengths.iter().map(|(name, length)| (name.as_str(), *length)));
        let workgroups = [0, 1, 2].map(|d| range.global[d].div_ceil(local[d]));
        Ok(dispatch(&constants, &resources, workgroups)?)
    }

    /// The work-group size: the one given, checked, or one chosen (8×8 in 2D, 64 in 1D, 4×4×4
    /// in 3D; for a kernel that synchronises, the largest sizes up to those that divide the
    /// global size).
    fn local_size(&self, gpu: &Gpu, range: &WorkRange) -> Result<[u32; 3], LaunchError> {
        let error = |message: String| LaunchError::Range { kernel: self.kernel.diagram.clone(), message };
        if range.global.contains(&0) {
            return Err(error(format!("an empty global size {:?}", range.global)));
        }
        let local = match range.local {
            Some(local) => local,
            None => {
                let preferred = match range.dimensions {
                    1 => [64, 1, 1],
                    2 => [8, 8, 1],
                    _ => [4, 4, 4],
                };
                let mut local = [0, 1, 2].map(|d| preferred[d].min(range.global[d]));
                if self.kernel.uses_barriers {
                    for (size, global) in local.iter_mut().zip(range.global) {
                        while !global.is_multiple_of(*size) {
                            *size -= 1;
                        }
                    }
                }
                local
            }
        };
        let limits = gpu.device.limits();
        let maxima = [
            limits.max_compute_workgroup_size_x,
            limits.max_compute_workgroup_size_y,
            limits.max_compute_workgroup_size_z,
        ];
        if local.contains(&0)
            || (0..3).any(|d| local[d] > maxima[d])
            || local.iter().product::<u32>() > limits.max_compute_invocations_per_workgroup
        {
            return Err(error(format!(
                "a work-group of {}×{}×{} work-items: this device runs at most {}×{}×{}, {} in all",
                local[0],
                local[1],
                local[2],
                maxima[0],
                maxima[1],
                maxima[2],
                limits.max_compute_invocations_per_workgroup
            )));
        }
        if self.kernel.uses_barriers && (0..3).any(|d| !range.global[d].is_multiple_of(local[d])) {
            return Err(error(format!(
                "it synchronises its work-groups (barrier), so the global size {:?} must be a multiple of the local size {:?}",
                range.global, local
            )));
        }
        Ok(local)
    }
}

/// Writes `numbers` as the parameter's type into the uniform block at `offset`.
fn write_value(uniform: &mut [u8], offset: u32, param: &KernelParam, numbers: &[Number]) -> Result<(), String> {
    let (base, width) = match param.ty.dereferenced() {
        Ty::Vector(base, width) => (base.as_ref(), *width as usize),
        other => (other, 1),
    };
    if numbers.len() != width && numbers.len() != 1 {
        return Err(format!("{} component(s) given for a `{}`", numbers.len(), param.ty));
    }
    for component in 0..width {
        let number = numbers[component.min(numbers.len() - 1)];
        let bytes = match base {
            // A sampler is its flags (`gudsl_codegen`'s `images.rs`).
            Ty::Int => (number.as_i64() as i32).to_le_bytes(),
            Ty::Gpu(name) if name == "sampler_t" => (number.as_i64() as i32).to_le_bytes(),
            Ty::UInt => (number.as_i64() as u32).to_le_bytes(),
            Ty::Bool => u32::from(number.as_i64() != 0).to_le_bytes(),
            Ty::Float => (number.as_f64() as f32).to_le_bytes(),
            other => return Err(format!("a `{other}` cannot be handed to a kernel")),
        };
        let at = offset as usize + 4 * component;
        uniform[at..at + 4].copy_from_slice(&bytes);
    }
    Ok(())
}
