//! 4-phase demodulation (sec. 2.1.1): a raw frame (8 planes) → phase, amplitude, intensity and
//! distance images; [`SubtractBlackDemodulate`] takes the black image off the frame in the same
//! pass (`black_demodulate.wgsl`), exactly as [`super::SubtractBlack`] then [`Demodulate`] give
//! it, without writing and reading the frame between.

use std::f32::consts::PI;

use bytemuck::{Pod, Zeroable};

use super::{subtract_black, unambiguous_range};
use crate::{
    kernels::{pixels::per_pixel, Pass, Shape, Unit},
    Image,
};

/// The uniform block of `demodulate_pixel.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    pixels: u32,
    width: u32,
    /// The unambiguous range δ, metres.
    range: f32,
    _pad: u32,
    _pad2: [u32; 4],
}

/// Demodulation at a modulation frequency (Hz).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Demodulate {
    pub(crate) modulation_hz: f32,
}

impl Unit for Demodulate {
    const NAME: &'static str = "demodulate";
    const SOURCE: &'static str = concat!(include_str!("demodulate.wgsl"), include_str!("demodulate_pixel.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(8)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        Params::of(inputs[0], self.modulation_hz)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }; 4]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        demodulate(inputs[0], self.modulation_hz).into()
    }
}

impl Params {
    /// The block for frames of `shape` at a modulation frequency (Hz).
    fn of(shape: Shape, modulation_hz: f32) -> Params {
        let (pixels, width) = ((shape.width * shape.height) as u32, shape.width as u32);
        Params { pixels, width, range: unambiguous_range(modulation_hz), _pad: 0, _pad2: [0; 4] }
    }
}

/// Black-image subtraction then demodulation, in one pass: raw frame, black frame → phase,
/// amplitude, intensity, distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SubtractBlackDemodulate {
    pub(crate) demodulate: Demodulate,
}

impl Unit for SubtractBlackDemodulate {
    const NAME: &'static str = "subtract_black_demodulate";
    const SOURCE: &'static str = concat!(
        include_str!("black_demodulate.wgsl"),
        include_str!("less_black.wgsl"),
        include_str!("demodulate_pixel.wgsl")
    );
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(8)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        self.demodulate.params(inputs)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        self.demodulate.outputs(inputs)
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        self.demodulate.passes(inputs)
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        self.demodulate.cpu(&[&subtract_black(inputs[0], inputs[1])])
    }
}

/// Phase, amplitude, intensity and distance of one pixel from its eight raw samples:
/// `φ = atan2(P3 − P1, P0 − P2)` wrapped into [0, 2π), `A = ½·√((P3 − P1)² + (P0 − P2)²)`,
/// `I = Σ(A_i + B_i)/4` (the channel sums: Σ P_i is 0 by construction), `D = δ·φ/2π`.
pub fn demodulate_pixel(raw: [f32; 8], modulation_hz: f32) -> [f32; 4] {
    let p = |i: usize| raw[2 * i] - raw[2 * i + 1];
    let (y, x) = (p(3) - p(1), p(0) - p(2));
    let mut phase = y.atan2(x);
    if phase < 0.0 {
        phase += 2.0 * PI;
    }
    let amplitude = 0.5 * (y * y + x * x).sqrt();
    let intensity = raw.iter().sum::<f32>() / 4.0;
    let distance = unambiguous_range(modulation_hz) * phase / (2.0 * PI);
    [phase, amplitude, intensity, distance]
}

/// Demodulates a raw frame into phase, amplitude, intensity and distance images.
pub fn demodulate(raw: &Image, modulation_hz: f32) -> [Image; 4] {
    let (w, h, n) = (raw.width, raw.height, raw.pixels());
    let values = per_pixel(w, h, |x, y| {
        let i = y * w + x;
        demodulate_pixel(std::array::from_fn(|p| raw.data[p * n + i]), modulation_hz)
    });
    std::array::from_fn(|k| Image { width: w, height: h, planes: 1, data: values.iter().map(|v| v[k]).collect() })
}
