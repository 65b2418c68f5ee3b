//! Binary erosion or dilation of a mask (opening: erode then dilate; closing: the reverse).

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `morphology.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    /// 1: dilate, 0: erode.
    dilate: u32,
    _pad: [u32; 4],
}

/// Over a `(2r+1)²` square.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Morphology {
    pub(crate) radius: u32,
    pub(crate) dilate: bool,
}

impl Unit for Morphology {
    const NAME: &'static str = "morphology";
    const SOURCE: &'static str = include_str!("morphology.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let (width, height) = (s.width as u32, s.height as u32);
        Params { width, height, radius: self.radius, dilate: u32::from(self.dilate), _pad: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![morphology(inputs[0], self.radius, self.dilate)]
    }
}

/// Binary erosion (`dilate` false) or dilation over a `(2r+1)²` square, edges replicated.
pub fn morphology(mask: &Image, radius: u32, dilate: bool) -> Image {
    let r = radius as isize;
    let mut out = mask.clone();
    for y in 0..mask.height as isize {
        for x in 0..mask.width as isize {
            let mut any = false;
            let mut all = true;
            for dy in -r..=r {
                for dx in -r..=r {
                    let on = mask.at_clamped(0, x + dx, y + dy) != 0.0;
                    any |= on;
                    all &= on;
                }
            }
            out.data[y as usize * mask.width + x as usize] =
                if (dilate && any) || (!dilate && all) { 1.0 } else { 0.0 };
        }
    }
    out
}
