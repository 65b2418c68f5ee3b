//! The kernels: each one a WGSL compute shader beside this file and its CPU reference here, with
//! the parameters of the dissertation. A kernel reads input images and writes output images of
//! f32 planes; the executor binds `params` (uniform) at 0, the inputs from 1, then the outputs,
//! then an optional scratch buffer of u32 (reductions), and runs the kernel's passes in order.

pub mod car;
mod filters;
pub mod icp;
pub mod integration;
pub mod motion;
mod reduce;
pub mod tof;

pub use filters::{bilateral, gaussian, mean, median};
pub use reduce::find_index;

/// Size of an image: `planes` planes of `width × height`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shape {
    pub width: usize,
    pub height: usize,
    pub planes: usize,
}

impl Shape {
    pub fn len(&self) -> usize {
        self.width * self.height * self.planes
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
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
    /// Intensity-related distance correction (sec. 2.1.2.2): distance, intensity → distance.
    CorrectIntensity { q: [f32; 3], int_time_calib: f32, int_time: f32 },
    /// Motion detection (eq. 4.4, 4.5): raw frame → M, mask (`M > theta`).
    DetectMotion { theta: f32 },
    /// Block matching (eq. 4.6–4.10): raw frame, mask → flow (2 planes: dx, dy per phase image)
    /// over a `window × window` search (MWS), optionally only directions within
    /// `restriction.1` radians of `restriction.0` (ρ/2 around the previous mean direction).
    MatchBlocks { window: u32, restriction: Option<(f32, f32)> },
    /// Median smoothing of flow directions over a `window × window` neighbourhood ("NH").
    SmoothFlow { window: u32 },
    /// Raw phase correction along the flow (sec. 4.2.5): raw frame, flow → raw frame.
    CorrectRaw,
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

/// A kernel pass: its entry point and workgroup counts.
pub struct Pass {
    pub entry: &'static str,
    pub workgroups: [u32; 3],
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

/// Workgroups of 8×8 threads covering a plane.
fn tiles(shape: Shape) -> [u32; 3] {
    [shape.width.div_ceil(8) as u32, shape.height.div_ceil(8) as u32, 1]
}

impl Kernel {
    /// A stable name (pipeline cache key and benchmark label).
    pub fn name(&self) -> &'static str {
        match self {
            Kernel::Demodulate { .. } => "demodulate",
            Kernel::SubtractBlack => "subtract_black",
            Kernel::CorrectIntensity { .. } => "correct_intensity",
            Kernel::DetectMotion { .. } => "detect_motion",
            Kernel::MatchBlocks { .. } => "match_blocks",
            Kernel::SmoothFlow { .. } => "smooth_flow",
            Kernel::CorrectRaw => "correct_raw",
            Kernel::MaskAmplitude { .. } => "mask_amplitude",
            Kernel::RemoveOutliers { .. } => "remove_outliers",
            Kernel::Segment { .. } => "segment",
            Kernel::Morphology { .. } => "morphology",
            Kernel::ApplyMask => "apply_mask",
            Kernel::PointCloud => "point_cloud",
            Kernel::Normals => "normals",
            Kernel::IcpReduce { .. } => "icp_reduce",
            Kernel::TransformPoints { .. } => "transform_points",
            Kernel::IntegrationTime { .. } => "integration_time",
            Kernel::Mean { .. } => "mean",
            Kernel::Median { .. } => "median",
            Kernel::Gaussian { .. } => "gaussian",
            Kernel::Bilateral { .. } => "bilateral",
            Kernel::FindIndex { .. } => "find_index",
        }
    }

    pub fn source(&self) -> &'static str {
        match self {
            Kernel::Demodulate { .. } => include_str!("demodulate.wgsl"),
            Kernel::SubtractBlack => include_str!("subtract_black.wgsl"),
            Kernel::CorrectIntensity { .. } => include_str!("correct_intensity.wgsl"),
            Kernel::DetectMotion { .. } => include_str!("detect_motion.wgsl"),
            Kernel::MatchBlocks { .. } => include_str!("match_blocks.wgsl"),
            Kernel::SmoothFlow { .. } => include_str!("smooth_flow.wgsl"),
            Kernel::CorrectRaw => include_str!("correct_raw.wgsl"),
            Kernel::MaskAmplitude { .. } => include_str!("mask_amplitude.wgsl"),
            Kernel::RemoveOutliers { .. } => include_str!("remove_outliers.wgsl"),
            Kernel::Segment { .. } => include_str!("segment.wgsl"),
            Kernel::Morphology { .. } => include_str!("morphology.wgsl"),
            Kernel::ApplyMask => include_str!("apply_mask.wgsl"),
            Kernel::PointCloud => include_str!("point_cloud.wgsl"),
            Kernel::Normals => include_str!("normals.wgsl"),
            Kernel::IcpReduce { .. } => concat!(include_str!("workgroup_sum.wgsl"), include_str!("icp_reduce.wgsl")),
            Kernel::IntegrationTime { .. } => {
                concat!(include_str!("workgroup_sum.wgsl"), include_str!("integration_time.wgsl"))
            }
            Kernel::TransformPoints { .. } => include_str!("transform_points.wgsl"),
            Kernel::Mean { .. } => include_str!("mean.wgsl"),
            Kernel::Median { .. } => include_str!("median.wgsl"),
            Kernel::Gaussian { .. } | Kernel::Bilateral { .. } => include_str!("weighted.wgsl"),
            Kernel::FindIndex { .. } => include_str!("find_index.wgsl"),
        }
    }

    /// Number of input images.
    pub fn inputs(&self) -> usize {
        match self {
            Kernel::SubtractBlack
            | Kernel::CorrectIntensity { .. }
            | Kernel::MatchBlocks { .. }
            | Kernel::CorrectRaw
            | Kernel::MaskAmplitude { .. }
            | Kernel::ApplyMask
            | Kernel::PointCloud => 2,
            Kernel::Segment { .. } | Kernel::IcpReduce { .. } => 4,
            _ => 1,
        }
    }

    /// Shapes of the outputs for inputs of these shapes.
    pub fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        let first = inputs[0];
        match self {
            Kernel::FindIndex { .. } | Kernel::IntegrationTime { .. } => vec![Shape { width: 1, height: 1, planes: 1 }],
            Kernel::Demodulate { .. } => vec![Shape { planes: 1, ..first }; 4],
            Kernel::SubtractBlack | Kernel::CorrectRaw | Kernel::SmoothFlow { .. } => vec![first],
            Kernel::DetectMotion { .. } => vec![Shape { planes: 1, ..first }; 2],
            Kernel::MatchBlocks { .. } => vec![Shape { planes: 2, ..first }],
            Kernel::PointCloud | Kernel::Normals | Kernel::TransformPoints { .. } => vec![Shape { planes: 3, ..first }],
            Kernel::IcpReduce { .. } => vec![Shape { width: icp::SUMS, height: 1, planes: 1 }],
            _ => vec![Shape { planes: 1, ..first }],
        }
    }

    /// Length of the u32 scratch buffer and the value it starts each run with (none: 0).
    pub fn scratch(&self, inputs: &[Shape]) -> (usize, u32) {
        match self {
            Kernel::FindIndex { .. } => (1, u32::MAX),
            Kernel::IcpReduce { .. } => {
                let [x, y, _] = linear_groups(inputs[0].width * inputs[0].height, 64);
                ((x * y) as usize * icp::SUMS, 0)
            }
            Kernel::IntegrationTime { .. } => {
                let [x, y, _] = linear(inputs[0].width * inputs[0].height);
                ((x * y) as usize * 2, 0)
            }
            _ => (0, 0),
        }
    }

    /// The uniform parameter block for inputs of these shapes.
    pub fn params(&self, inputs: &[Shape]) -> Vec<u8> {
        let s = inputs[0];
        let (w, h) = (s.width as u32, s.height as u32);
        let words: Vec<u32> = match *self {
            Kernel::Demodulate { modulation_hz } => {
                let range = tof::unambiguous_range(modulation_hz);
                vec![(s.width * s.height) as u32, w, range.to_bits(), 0, 0, 0, 0, 0]
            }
            Kernel::SubtractBlack => vec![s.len() as u32, 0, 0, 0, 0, 0, 0, 0],
            Kernel::DetectMotion { theta } => vec![w, h, theta.to_bits(), 0, 0, 0, 0, 0],
            Kernel::MatchBlocks { window, restriction } => {
                let (restrict, (mean, half)) = (u32::from(restriction.is_some()), restriction.unwrap_or((0.0, 0.0)));
                vec![w, h, (window - 1) / 2, restrict, mean.to_bits(), half.to_bits(), 0, 0]
            }
            Kernel::SmoothFlow { window } => vec![w, h, (window - 1) / 2, 0, 0, 0, 0, 0],
            Kernel::CorrectRaw | Kernel::Normals => vec![w, h, 0, 0, 0, 0, 0, 0],
            Kernel::MaskAmplitude { min, max } => vec![w * h, w, min.to_bits(), max.to_bits(), 0, 0, 0, 0],
            Kernel::RemoveOutliers { range, min_similar } => vec![w, h, range.to_bits(), min_similar, 0, 0, 0, 0],
            Kernel::Segment { theta_intensity, theta_distance } => {
                vec![w * h, w, theta_intensity.to_bits(), theta_distance.to_bits(), 0, 0, 0, 0]
            }
            Kernel::Morphology { radius, dilate } => vec![w, h, radius, u32::from(dilate), 0, 0, 0, 0],
            Kernel::ApplyMask | Kernel::PointCloud => vec![w * h, w, 0, 0, 0, 0, 0, 0],
            Kernel::CorrectIntensity { q, int_time_calib, int_time } => {
                let scale = int_time_calib / int_time;
                vec![s.len() as u32, w, q[0].to_bits(), q[1].to_bits(), q[2].to_bits(), scale.to_bits(), 0, 0]
            }
            Kernel::Mean { radius } | Kernel::Median { radius } => vec![w, h, radius, 0, 0, 0, 0, 0],
            Kernel::Gaussian { sigma } => {
                let radius = filters::gaussian_radius(sigma);
                // A range sigma of 0 turns the range weight off: a plain Gaussian.
                vec![w, h, radius, sigma.to_bits(), 0f32.to_bits(), 0, 0, 0]
            }
            Kernel::Bilateral { radius, sigma_space, sigma_range } => {
                vec![w, h, radius, sigma_space.to_bits(), sigma_range.max(f32::MIN_POSITIVE).to_bits(), 0, 0, 0]
            }
            Kernel::IcpReduce { pose, intrinsics: k, max_distance, min_cos } => {
                let mut floats = pose.to_vec();
                floats.extend([k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2]);
                floats.extend([w as f32, h as f32, max_distance, min_cos]);
                floats.iter().map(|v| v.to_bits()).collect()
            }
            Kernel::IntegrationTime { t_curr, model: m } => {
                let floats = [w as f32, h as f32, t_curr, m.i_opt, m.h[0], m.h[1], m.h[2], m.h[3]];
                let limits = [m.h_range.0, m.h_range.1, m.gain, m.t_range.0, m.t_range.1, 0.0, 0.0, 0.0];
                floats.iter().chain(&limits).map(|v| v.to_bits()).collect()
            }
            Kernel::TransformPoints { pose } => {
                let mut words: Vec<u32> = pose.iter().map(|v| v.to_bits()).collect();
                words.extend([w, h, 0, 0]);
                words
            }
            Kernel::FindIndex { threshold } => vec![(s.len()) as u32, threshold.to_bits(), 0, 0, 0, 0, 0, 0],
        };
        bytemuck::cast_slice(&words).to_vec()
    }

    /// The passes over inputs of these shapes.
    pub fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        match self {
            Kernel::FindIndex { .. } => vec![
                Pass { entry: "main", workgroups: linear(inputs[0].len()) },
                Pass { entry: "finish", workgroups: [1, 1, 1] },
            ],
            Kernel::SubtractBlack => vec![Pass { entry: "main", workgroups: linear(inputs[0].len()) }],
            Kernel::IcpReduce { .. } => vec![
                Pass { entry: "main", workgroups: linear_groups(inputs[0].width * inputs[0].height, 64) },
                Pass { entry: "finish", workgroups: [1, 1, 1] },
            ],
            Kernel::IntegrationTime { .. } => vec![
                Pass { entry: "main", workgroups: linear(inputs[0].width * inputs[0].height) },
                Pass { entry: "finish", workgroups: [1, 1, 1] },
            ],
            _ => vec![Pass { entry: "main", workgroups: tiles(inputs[0]) }],
        }
    }

    /// The CPU reference: the same computation in plain Rust.
    pub fn cpu(&self, inputs: &[&crate::Image]) -> Vec<crate::Image> {
        let input = inputs[0];
        match *self {
            Kernel::Demodulate { modulation_hz } => tof::demodulate(input, modulation_hz).into(),
            Kernel::SubtractBlack => vec![tof::subtract_black(input, inputs[1])],
            Kernel::DetectMotion { theta } => motion::detect(input, theta).into(),
            Kernel::MatchBlocks { window, restriction } => {
                vec![motion::match_blocks(input, inputs[1], window, restriction)]
            }
            Kernel::SmoothFlow { window } => vec![motion::smooth_flow(input, window)],
            Kernel::CorrectRaw => vec![motion::correct_raw(input, inputs[1])],
            Kernel::MaskAmplitude { min, max } => vec![car::mask_amplitude(input, inputs[1], min, max)],
            Kernel::RemoveOutliers { range, min_similar } => vec![car::remove_outliers(input, range, min_similar)],
            Kernel::Segment { theta_intensity, theta_distance } => {
                vec![car::segment(input, inputs[1], inputs[2], inputs[3], theta_intensity, theta_distance)]
            }
            Kernel::Morphology { radius, dilate } => vec![car::morphology(input, radius, dilate)],
            Kernel::ApplyMask => vec![car::apply_mask(input, inputs[1])],
            Kernel::PointCloud => vec![car::point_cloud(input, inputs[1])],
            Kernel::Normals => vec![car::normals(input)],
            Kernel::IcpReduce { pose, intrinsics, max_distance, min_cos } => {
                let sums =
                    icp::reduce([input, inputs[1], inputs[2], inputs[3]], &pose, &intrinsics, max_distance, min_cos);
                vec![crate::Image::from_plane(icp::SUMS, 1, sums.iter().map(|&v| v as f32).collect())]
            }
            Kernel::TransformPoints { pose } => vec![icp::transform_points(input, &pose)],
            Kernel::IntegrationTime { t_curr, model } => {
                vec![crate::Image::from_plane(1, 1, vec![integration::estimate(input, t_curr, &model)])]
            }
            Kernel::CorrectIntensity { q, int_time_calib, int_time } => {
                vec![tof::correct_intensity(input, inputs[1], q, int_time_calib, int_time)]
            }
            Kernel::Mean { radius } => vec![mean(input, radius)],
            Kernel::Median { radius } => vec![median(input, radius)],
            Kernel::Gaussian { sigma } => vec![gaussian(input, sigma)],
            Kernel::Bilateral { radius, sigma_space, sigma_range } => {
                vec![bilateral(input, radius, sigma_space, sigma_range)]
            }
            Kernel::FindIndex { threshold } => {
                vec![crate::Image::from_plane(1, 1, vec![find_index(&input.data, threshold) as f32])]
            }
        }
    }
}
