//! gudsl-runtime: the ToF algorithms of the dissertation as WGSL compute kernels on wgpu, each
//! with a CPU reference; one executor runs them, and the pipelines built of them, on the GPU
//! (data kept there, one readback a frame, each stage timed by the GPU's clock) or, without an
//! adapter, on the CPU reference. Programs written elsewhere (the code
//! generator's kernels) run through [`program`].

pub mod bound;
pub mod camera;
pub mod error;
pub mod executor;
pub mod exposure;
pub mod gpu;
pub mod image;
pub mod kernels;
pub mod linalg;
pub mod listings;
pub mod phase_normalization;
pub mod pipeline;
pub mod program;
pub mod registration;
pub mod sim;
mod timing;

pub use bound::BoundKernel;
pub use error::ChainError;
pub use executor::{run_cpu, ChainRun, Executor, Tensor, Work};
pub use gpu::{Gpu, GpuUnavailable};
pub use image::{Image, Shape};
pub use kernels::Kernel;
pub use pipeline::{Pipeline, Slot};
pub use program::{BindingKind, BindingSpec, DeviceBuffer, DeviceImage, Program, ProgramError, Resource, TexelFormat};
