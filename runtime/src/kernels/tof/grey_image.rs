//! An amplitude as a grey RGBA image (the colour camera of sec. 11.5's example): amplitude →
//! 4 planes R, G, B, A of 8-bit values.

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `grey_image.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    gain: f32,
    _pad: u32,
}

/// Grey values per unit of amplitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GreyImage {
    pub(crate) gain: f32,
}

impl Unit for GreyImage {
    const NAME: &'static str = "grey_image";
    const SOURCE: &'static str = include_str!("grey_image.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { len: (s.width * s.height) as u32, width: s.width as u32, gain: self.gain, _pad: 0 }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 4, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![grey_image(inputs[0], self.gain)]
    }
}

/// Each pixel's grey value `min(255, ⌊amplitude × gain + ½⌋)` (0 for a negative or NaN
/// amplitude) in R, G and B, 255 in A: four planes.
pub fn grey_image(amplitude: &Image, gain: f32) -> Image {
    let grey: Vec<f32> = amplitude.data.iter().map(|&a| grey_value(a * gain)).collect();
    let mut data = Vec::with_capacity(grey.len() * 4);
    for _ in 0..3 {
        data.extend_from_slice(&grey);
    }
    data.extend(std::iter::repeat_n(255.0, grey.len()));
    Image { width: amplitude.width, height: amplitude.height, planes: 4, data }
}

#[allow(clippy::manual_clamp)] // `clamp` keeps a NaN; `max(NaN, 0)` is 0, as the shader's
fn grey_value(scaled: f32) -> f32 {
    (scaled + 0.5).floor().max(0.0).min(255.0)
}
