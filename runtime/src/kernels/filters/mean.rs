//! Box mean over a `(2r+1)²` window (chapter 10's mean filter), edges replicated.

use bytemuck::{Pod, Zeroable};

use super::map_pixels;
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `mean.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    _pad: u32,
    _pad2: [u32; 4],
}

/// The mean of radius `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Mean {
    pub(crate) radius: u32,
}

impl Unit for Mean {
    const NAME: &'static str = "mean";
    const SOURCE: &'static str = include_str!("mean.wgsl");
    const INPUTS: &'static [Option<usize>] = &[None];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { width: s.width as u32, height: s.height as u32, radius: self.radius, _pad: 0, _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![mean(inputs[0], self.radius)]
    }
}

/// Box mean over a `(2r+1)²` window.
pub fn mean(input: &Image, radius: u32) -> Image {
    let r = radius as isize;
    map_pixels(input, |x, y| {
        let mut sum = 0.0f32;
        for dy in -r..=r {
            for dx in -r..=r {
                sum += input.at_clamped(0, x + dx, y + dy);
            }
        }
        sum / ((2 * r + 1) * (2 * r + 1)) as f32
    })
}
