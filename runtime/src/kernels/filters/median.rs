//! Median over a `(2r+1)²` window, r = 1 (3×3) or 2 (5×5), edges replicated.

use bytemuck::{Pod, Zeroable};

use super::map_pixels;
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `median.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    _pad: u32,
    _pad2: [u32; 4],
}

/// The median of radius `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Median {
    pub(crate) radius: u32,
}

impl Unit for Median {
    const NAME: &'static str = "median";
    const SOURCE: &'static str = include_str!("median.wgsl");
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
        vec![median(inputs[0], self.radius)]
    }
}

/// Median over a `(2r+1)²` window.
pub fn median(input: &Image, radius: u32) -> Image {
    let r = radius as isize;
    map_pixels(input, |x, y| {
        let mut values: Vec<f32> = Vec::with_capacity(((2 * r + 1) * (2 * r + 1)) as usize);
        for dy in -r..=r {
            for dx in -r..=r {
                values.push(input.at_clamped(0, x + dx, y + dy));
            }
        }
        values.sort_by(f32::total_cmp);
        values[values.len() / 2]
    })
}
