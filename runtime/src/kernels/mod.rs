//! The kernels: each one a module with its WGSL compute shader beside it, a `#[repr(C)]`
//! parameter block mirroring the shader's `Params`, the images it reads and writes, its passes,
//! and its CPU reference — grouped by the chapter they implement (`tof`: 2.1, `motion`: 4,
//! `integration`: 5, `car` and `icp`: 6, `filters` and `find_index`: 10). A kernel reads input
//! images and writes output images of f32 planes; the executor binds the parameters (uniform) at
//! 0, the inputs from 1, then the outputs, then an optional scratch buffer of u32 (reductions),
//! and runs the kernel's passes in order.
//!
//! [`Kernel`] is the value a pipeline step holds; it dispatches to its kernel's [`Unit`] in one
//! exhaustive match.

pub mod car;
pub mod filters;
mod find_index;
pub mod icp;
pub mod integration;
pub mod motion;
mod pixels;
pub mod tof;

pub use filters::{bilateral, gaussian, mean, median};
pub use find_index::find_index;

pub use crate::image::Shape;
use crate::{error::ChainError, Image};

/// A kernel pass: its entry point and workgroup counts.
pub struct Pass {
    pub entry: &'static str,
    pub workgroups: [u32; 3],
}

impl Pass {
    /// Entry point `main` over these workgroups.
    fn main(workgroups: [u32; 3]) -> Pass {
        Pass { entry: "main", workgroups }
    }

    /// Entry point `main` in 8×8 tiles over the plane of `shape`.
    fn tiles(shape: Shape) -> Pass {
        Pass::main([shape.width.div_ceil(8) as u32, shape.height.div_ceil(8) as u32, 1])
    }

    /// A reduction's last pass: entry point `finish`, one workgroup.
    fn finish() -> Pass {
        Pass { entry: "finish", workgroups: [1, 1, 1] }
    }
}

/// A reduction's u32 scratch buffer: its length and the value each run starts it with.
pub struct Scratch {
    pub len: usize,
    pub start: u32,
}

/// Workgroups of 256 threads covering `len` items, in rows of at most 65535 workgroups.
fn linear(len: usize) -> [u32; 3] {
    linear_groups(len, 256)
}

/// Workgroups of `threads` threads covering `len` items, in rows of at most 65535 workgroups.
fn linear_groups(len: usize, threads: usize) -> [u32; 3] {
    let groups = len.div_ceil(threads).max(1);
    let x = groups.min(65_535);
    [x as u32, groups.div_ceil(x) as u32, 1]
}

/// The uniform block of a kernel that needs only the image's size: its shader's `Params`
/// begins `width: u32, height: u32` and pads to 32 bytes like every other kernel's.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub(crate) struct SizeParams {
    width: u32,
    height: u32,
    _pad: [u32; 6],
}

impl SizeParams {
    /// The size of `shape`.
    pub(crate) fn of(shape: Shape) -> SizeParams {
        SizeParams { width: shape.width as u32, height: shape.height as u32, _pad: [0; 6] }
    }
}

/// What a kernel module defines.
pub(crate) trait Unit {
    /// A stable name (pipeline cache key and benchmark label).
    const NAME: &'static str;
    /// The WGSL source (with the shared code it uses prepended).
    const SOURCE: &'static str;
    /// Planes of each input image (`None`: any number); every input has the first's size but
    /// the [`Unit::VALUES`].
    const INPUTS: &'static [Option<usize>];
    /// The inputs that are one value (1×1, of their planes) whatever the first's size.
    const VALUES: &'static [usize] = &[];
    /// The uniform block, field for field the shader's `Params`.
    type Params: bytemuck::Pod;

    fn params(&self, inputs: &[Shape]) -> Self::Params;
    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape>;
    fn passes(&self, inputs: &[Shape]) -> Vec<Pass>;
    fn scratch(&self, _inputs: &[Shape]) -> Option<Scratch> {
        None
    }
    /// The CPU reference: the same computation in plain Rust.
    fn cpu(&self, inputs: &[&Image]) -> Vec<Image>;
}

/// A [`Unit`] as an object, its parameter block as bytes.
trait Dispatch {
    fn name(&self) -> &'static str;
    fn source(&self) -> &'static str;
    fn input_planes(&self) -> &'static [Option<usize>];
    fn value_inputs(&self) -> &'static [usize];
    fn params(&self, inputs: &[Shape]) -> Vec<u8>;
    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape>;
    fn passes(&self, inputs: &[Shape]) -> Vec<Pass>;
    fn scratch(&self, inputs: &[Shape]) -> Option<Scratch>;
    fn cpu(&self, inputs: &[&Image]) -> Vec<Image>;
}

impl<U: Unit> Dispatch for U {
    fn name(&self) -> &'static str {
        U::NAME
    }
    fn source(&self) -> &'static str {
        U::SOURCE
    }
    fn input_planes(&self) -> &'static [Option<usize>] {
        U::INPUTS
    }
    fn value_inputs(&self) -> &'static [usize] {
        U::VALUES
    }
    fn params(&self, inputs: &[Shape]) -> Vec<u8> {
        bytemuck::bytes_of(&Unit::params(self, inputs)).to_vec()
    }
    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        Unit::outputs(self, inputs)
    }
    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        Unit::passes(self, inputs)
    }
    fn scratch(&self, inputs: &[Shape]) -> Option<Scratch> {
        Unit::scratch(self, inputs)
    }
    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        Unit::cpu(self, inputs)
    }
}

/// One computation with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kernel {
    /// 4-phase demodulation (sec. 2.1.1): raw frame (8 planes) → phase, amplitude, intensity,
    /// distance (metres, modulation frequency in Hz).
    Demodulate { modulation_hz: f32 },
    /// Black-image subtraction (fixed-pattern noise): raw frame, black frame → raw frame.
    SubtractBlack,
    /// `SubtractBlack` then `Demodulate` in one pass, exactly as the two give it: raw frame,
    /// black frame → phase, amplitude, intensity, distance.
    SubtractBlackDemodulate { modulation_hz: f32 },
    /// Intensity-related distance correction (sec. 2.1.2.2): distance, intensity → distance.
    CorrectIntensity { q: [f32; 3], int_time_calib: f32, int_time: f32 },
    /// Phase normalization (sec. 4.2.2.1): raw frame, calibration (8 planes, see
    /// [`crate::phase_normalization`]) → normalised raw frame.
    NormalizePhases,
    /// `SubtractBlack` then `NormalizePhases` in one pass, exactly as the two give it: raw frame,
    /// black frame, calibration → normalised raw frame.
    SubtractBlackNormalizePhases,
    /// Motion detection (eq. 4.4, 4.5): raw frame → M, mask (`M > theta`).
    DetectMotion { theta: f32 },
    /// Block matching (eq. 4.6–4.10): raw frame, mask → flow (2 planes: dx, dy per phase image)
    /// over a `window × window` search (MWS), optionally only directions within
    /// `restriction.1` radians of `restriction.0` (ρ/2 around the previous mean direction); with
    /// `subpixel`, refined to a quarter pixel beyond the text's whole pixels (never to a vector
    /// whose samples blend across an edge).
    MatchBlocks { window: u32, restriction: Option<(f32, f32)>, subpixel: bool },
    /// Motion detection and block matching in one pass, exactly as `DetectMotion { theta }` then
    /// `MatchBlocks` give them: raw frame → flow, mask.
    DetectMatch { theta: f32, window: u32, restriction: Option<(f32, f32)>, subpixel: bool },
    /// `DetectMatch` restricted to `half_width` radians around the direction its second input
    /// holds (a `MeanDirection` of the frame before, on the GPU): raw frame, direction → flow,
    /// mask.
    DetectMatchAround { theta: f32, window: u32, half_width: f32, subpixel: bool },
    /// The mean direction of a flow's non-zero vectors (ρ's, for the next frame): flow, the
    /// direction before (1×1, 2 planes: radians, known) → the direction; the one before while
    /// nothing moved.
    MeanDirection,
    /// Median smoothing of flow directions over a `window × window` neighbourhood ("NH").
    SmoothFlow { window: u32 },
    /// Raw phase correction along the flow (sec. 4.2.5): raw frame, flow → raw frame (bilinear
    /// samples where the flow is fractional).
    CorrectRaw,
    /// An amplitude as a grey RGBA image of 8-bit values (sec. 11.5's camera): amplitude → 4
    /// planes.
    GreyImage { gain: f32 },
    /// Amplitude masking (eq. 6.1): distance, amplitude → distance (0 outside [min, max]).
    MaskAmplitude { min: f32, max: f32 },
    /// 3×3 outlier removal (sec. 6.5.1.3): distance → distance.
    RemoveOutliers { range: f32, min_similar: u32 },
    /// Foreground segmentation (sec. 6.5.2): intensity, distance, background intensity,
    /// background distance → mask.
    Segment { theta_intensity: f32, theta_distance: f32 },
    /// Binary erosion or dilation of a mask (opening: erode then dilate; closing: the reverse).
    Morphology { radius: u32, dilate: bool },
    /// value, mask → value where the mask is set, else 0.
    ApplyMask,
    /// Polar → Cartesian: distance, unit rays (3 planes) → points (3 planes).
    PointCloud,
    /// Normals by central differences: points → normals (3 planes).
    Normals,
    /// One projective point-to-plane ICP step (sec. 6.5.3): source points, source normals,
    /// model points, model normals → the 29 sums of the 6×6 system (see [`icp::SUMS`]).
    IcpReduce { pose: crate::camera::Pose, intrinsics: crate::camera::Intrinsics, max_distance: f32, min_cos: f32 },
    /// Rigid transform of a point cloud: points → points.
    TransformPoints { pose: crate::camera::Pose },
    /// The next frame's integration time in µs (sec. 5.3): intensity → 1 value.
    IntegrationTime { t_curr: f32, model: integration::IntegrationModel },
    /// Box mean over a `(2r+1)²` window (chapter 10's mean filter), edges replicated.
    Mean { radius: u32 },
    /// Median over a `(2r+1)²` window, r = 1 (3×3) or 2 (5×5), edges replicated.
    Median { radius: u32 },
    /// Gaussian over a `(2⌈3σ⌉+1)²` window, normalised, edges replicated.
    Gaussian { sigma: f32 },
    /// Bilateral filter (chapter 10): spatial and range Gaussians, normalised.
    Bilateral { radius: u32, sigma_space: f32, sigma_range: f32 },
    /// findIndex (chapter 10): the first index whose value is ≥ `threshold`, or the length.
    FindIndex { threshold: f32 },
}

impl Kernel {
    /// Calls `f` with this kernel's unit.
    fn unit<R>(&self, f: impl FnOnce(&dyn Dispatch) -> R) -> R {
        match *self {
            Kernel::Demodulate { modulation_hz } => f(&tof::Demodulate { modulation_hz }),
            Kernel::SubtractBlack => f(&tof::SubtractBlack),
            Kernel::SubtractBlackDemodulate { modulation_hz } => {
                f(&tof::SubtractBlackDemodulate { demodulate: tof::Demodulate { modulation_hz } })
            }
            Kernel::CorrectIntensity { q, int_time_calib, int_time } => {
                f(&tof::CorrectIntensity { q, int_time_calib, int_time })
            }
            Kernel::NormalizePhases => f(&motion::NormalizePhases),
            Kernel::SubtractBlackNormalizePhases => f(&motion::SubtractBlackNormalizePhases),
            Kernel::DetectMotion { theta } => f(&motion::DetectMotion { theta }),
            Kernel::MatchBlocks { window, restriction, subpixel } => {
                f(&motion::MatchBlocks { window, restriction, subpixel })
            }
            Kernel::DetectMatch { theta, window, restriction, subpixel } => {
                f(&motion::DetectMatch { theta, matching: motion::MatchBlocks { window, restriction, subpixel } })
            }
            Kernel::DetectMatchAround { theta, window, half_width, subpixel } => {
                f(&motion::DetectMatchAround { theta, window, half_width, subpixel })
            }
            Kernel::MeanDirection => f(&motion::MeanDirection),
            Kernel::SmoothFlow { window } => f(&motion::SmoothFlow { window }),
            Kernel::CorrectRaw => f(&motion::CorrectRaw),
            Kernel::GreyImage { gain } => f(&tof::GreyImage { gain }),
            Kernel::MaskAmplitude { min, max } => f(&car::MaskAmplitude { min, max }),
            Kernel::RemoveOutliers { range, min_similar } => f(&car::RemoveOutliers { range, min_similar }),
            Kernel::Segment { theta_intensity, theta_distance } => f(&car::Segment { theta_intensity, theta_distance }),
            Kernel::Morphology { radius, dilate } => f(&car::Morphology { radius, dilate }),
            Kernel::ApplyMask => f(&car::ApplyMask),
            Kernel::PointCloud => f(&car::PointCloud),
            Kernel::Normals => f(&car::Normals),
            Kernel::IcpReduce { pose, intrinsics, max_distance, min_cos } => {
                f(&icp::IcpReduce { pose, intrinsics, max_distance, min_cos })
            }
            Kernel::TransformPoints { pose } => f(&icp::TransformPoints { pose }),
            Kernel::IntegrationTime { t_curr, model } => f(&integration::IntegrationTime { t_curr, model }),
            Kernel::Mean { radius } => f(&filters::Mean { radius }),
            Kernel::Median { radius } => f(&filters::Median { radius }),
            Kernel::Gaussian { sigma } => f(&filters::Gaussian { sigma }),
            Kernel::Bilateral { radius, sigma_space, sigma_range } => {
                f(&filters::Bilateral { radius, sigma_space, sigma_range })
            }
            Kernel::FindIndex { threshold } => f(&find_index::FindIndex { threshold }),
        }
    }

    /// One kernel of each kind, with typical parameters (for validation and benchmarks).
    pub fn every_kind() -> Vec<Kernel> {
        use crate::camera::{Intrinsics, IDENTITY};
        vec![
            Kernel::Demodulate { modulation_hz: 20.0e6 },
            Kernel::SubtractBlack,
            Kernel::SubtractBlackDemodulate { modulation_hz: 20.0e6 },
            Kernel::CorrectIntensity { q: [0.0; 3], int_time_calib: 1.0, int_time: 1.0 },
            Kernel::NormalizePhases,
            Kernel::SubtractBlackNormalizePhases,
            Kernel::DetectMotion { theta: 0.0 },
            Kernel::MatchBlocks { window: 5, restriction: None, subpixel: false },
            Kernel::DetectMatch { theta: 655.0, window: 5, restriction: None, subpixel: false },
            Kernel::DetectMatchAround { theta: 655.0, window: 5, half_width: 0.8, subpixel: false },
            Kernel::MeanDirection,
            Kernel::SmoothFlow { window: 3 },
            Kernel::CorrectRaw,
            Kernel::GreyImage { gain: 2.0 },
            Kernel::MaskAmplitude { min: 0.0, max: 1.0 },
            Kernel::RemoveOutliers { range: 0.05, min_similar: 3 },
            Kernel::Segment { theta_intensity: 1.0, theta_distance: 0.1 },
            Kernel::Morphology { radius: 1, dilate: true },
            Kernel::ApplyMask,
            Kernel::PointCloud,
            Kernel::Normals,
            Kernel::IcpReduce { pose: IDENTITY, intrinsics: Intrinsics::CAMCUBE, max_distance: 0.2, min_cos: 0.9 },
            Kernel::TransformPoints { pose: IDENTITY },
            Kernel::IntegrationTime { t_curr: 1000.0, model: integration::IntegrationModel::CAMCUBE },
            Kernel::Mean { radius: 1 },
            Kernel::Median { radius: 1 },
            Kernel::Gaussian { sigma: 1.0 },
            Kernel::Bilateral { radius: 2, sigma_space: 2.0, sigma_range: 0.5 },
            Kernel::FindIndex { threshold: 0.0 },
        ]
    }

    /// A stable name (pipeline cache key and benchmark label).
    pub fn name(&self) -> &'static str {
        self.unit(|u| u.name())
    }

    /// The WGSL source.
    pub fn source(&self) -> &'static str {
        self.unit(|u| u.source())
    }

    /// Number of input images.
    pub fn inputs(&self) -> usize {
        self.unit(|u| u.input_planes().len())
    }

    /// Whether inputs of these shapes fit: as many as the kernel reads, each with the planes it
    /// takes, all of one size but the values (1×1).
    pub fn check(&self, inputs: &[Shape]) -> Result<(), ChainError> {
        let (kernel, planes, values) = self.unit(|u| (u.name(), u.input_planes(), u.value_inputs()));
        if inputs.len() != planes.len() {
            return Err(ChainError::Inputs { kernel, expected: planes.len(), given: inputs.len() });
        }
        for (input, (shape, expected)) in inputs.iter().zip(planes).enumerate() {
            if let Some(expected) = *expected {
                if shape.planes != expected {
                    return Err(ChainError::Planes { kernel, input, expected, given: shape.planes });
                }
            }
            let first = inputs[0];
            let size = if values.contains(&input) { (1, 1) } else { (first.width, first.height) };
            if (shape.width, shape.height) != size || shape.is_empty() {
                return Err(ChainError::Size { kernel, input, expected: size, given: (shape.width, shape.height) });
            }
        }
        Ok(())
    }

    /// Shapes of the outputs for inputs of these shapes (checked with [`Kernel::check`]).
    pub fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        self.unit(|u| u.outputs(inputs))
    }

    /// The u32 scratch buffer a reduction needs, if any.
    pub fn scratch(&self, inputs: &[Shape]) -> Option<Scratch> {
        self.unit(|u| u.scratch(inputs))
    }

    /// The uniform parameter block for inputs of these shapes, as the shader reads it.
    pub fn params(&self, inputs: &[Shape]) -> Vec<u8> {
        self.unit(|u| u.params(inputs))
    }

    /// The passes over inputs of these shapes.
    pub fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        self.unit(|u| u.passes(inputs))
    }

    /// The CPU reference: the same computation in plain Rust.
    pub fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        self.unit(|u| u.cpu(inputs))
    }
}
