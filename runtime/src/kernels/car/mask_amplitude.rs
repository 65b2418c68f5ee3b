//! Amplitude masking (eq. 6.1): distance, amplitude → distance (0 outside [min, max]).

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `mask_amplitude.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    min_amplitude: f32,
    max_amplitude: f32,
    _pad: [u32; 4],
}

/// The amplitudes kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MaskAmplitude {
    pub(crate) min: f32,
    pub(crate) max: f32,
}

impl Unit for MaskAmplitude {
    const NAME: &'static str = "mask_amplitude";
    const SOURCE: &'static str = include_str!("mask_amplitude.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1), Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let (len, width) = ((s.width * s.height) as u32, s.width as u32);
        Params { len, width, min_amplitude: self.min, max_amplitude: self.max, _pad: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![mask_amplitude(inputs[0], inputs[1], self.min, self.max)]
    }
}

/// Eq. 6.1: distance kept where `min ≤ amplitude ≤ max`, else 0 (under- or over-saturated).
pub fn mask_amplitude(distance: &Image, amplitude: &Image, min: f32, max: f32) -> Image {
    let data =
        distance.data.iter().zip(&amplitude.data).map(|(&d, &a)| if a >= min && a <= max { d } else { 0.0 }).collect();
    Image { data, ..distance.clone() }
}
