//! value, mask → value where the mask is set, else 0.

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `apply_mask.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    _pad: [u32; 2],
    _pad2: [u32; 4],
}

/// Masking.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ApplyMask;

impl Unit for ApplyMask {
    const NAME: &'static str = "apply_mask";
    const SOURCE: &'static str = include_str!("apply_mask.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1), Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { len: (s.width * s.height) as u32, width: s.width as u32, _pad: [0; 2], _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![apply_mask(inputs[0], inputs[1])]
    }
}

/// `value · mask` per pixel (a mask of 1 and 0 keeps or clears).
pub fn apply_mask(value: &Image, mask: &Image) -> Image {
    let data = value.data.iter().zip(&mask.data).map(|(v, m)| if *m != 0.0 { *v } else { 0.0 }).collect();
    Image { data, ..value.clone() }
}
