//! Phase normalization (sec. 4.2.2.1, eq. 4.1): raw frame, calibration → normalised raw frame;
//! [`SubtractBlackNormalizePhases`] takes the black image off the frame in the same pass
//! (`black_normalize_phases.wgsl`), exactly as [`crate::kernels::tof::SubtractBlack`] then
//! [`NormalizePhases`] give it.

use crate::{
    kernels::{tof::subtract_black, Pass, Shape, SizeParams, Unit},
    Image,
};

/// Phase normalization with a per-pixel calibration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NormalizePhases;

impl Unit for NormalizePhases {
    const NAME: &'static str = "normalize_phases";
    const SOURCE: &'static str = concat!(include_str!("normalize_phases.wgsl"), include_str!("normalize_pixel.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(8)];
    type Params = SizeParams;

    fn params(&self, inputs: &[Shape]) -> SizeParams {
        SizeParams::of(inputs[0])
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![inputs[0]]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![normalize_phases(inputs[0], inputs[1])]
    }
}

/// Black-image subtraction then phase normalization, in one pass: raw frame, black frame,
/// calibration → normalised raw frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SubtractBlackNormalizePhases;

impl Unit for SubtractBlackNormalizePhases {
    const NAME: &'static str = "subtract_black_normalize_phases";
    const SOURCE: &'static str = concat!(
        include_str!("black_normalize_phases.wgsl"),
        include_str!("../tof/less_black.wgsl"),
        include_str!("normalize_pixel.wgsl")
    );
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(8), Some(8)];
    type Params = SizeParams;

    fn params(&self, inputs: &[Shape]) -> SizeParams {
        NormalizePhases.params(inputs)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        NormalizePhases.outputs(inputs)
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        NormalizePhases.passes(inputs)
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![normalize_phases(&subtract_black(inputs[0], inputs[1]), inputs[2])]
    }
}

/// `f(X) = a·√max(X + b, 0) + c·X + d` with the pixel's coefficients for its tap.
fn normalize_value(x: f32, [a, b, c, d]: [f32; 4]) -> f32 {
    a * (x + b).max(0.0).sqrt() + c * x + d
}

/// Phase normalization (eq. 4.1): every channel `A_i`, `B_i` through its pixel's tap function;
/// `calibration` holds the coefficients `a b c d` of tap A, then of tap B (8 planes, see
/// [`crate::phase_normalization`]).
pub fn normalize_phases(raw: &Image, calibration: &Image) -> Image {
    let n = raw.pixels();
    let mut out = raw.clone();
    for plane in 0..8 {
        let tap = plane % 2;
        for i in 0..n {
            let coefficients = std::array::from_fn(|k| calibration.data[(4 * tap + k) * n + i]);
            out.data[plane * n + i] = normalize_value(raw.data[plane * n + i], coefficients);
        }
    }
    out
}
