//! Raw phase correction along the flow (sec. 4.2.5): raw frame, flow → raw frame.

use rayon::prelude::*;

use super::bilinear;

use crate::{
    kernels::{Pass, Shape, SizeParams, Unit},
    Image,
};

/// Raw phase correction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CorrectRaw;

impl Unit for CorrectRaw {
    const NAME: &'static str = "correct_raw";
    const SOURCE: &'static str = include_str!("correct_raw.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(2)];
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
        vec![correct_raw(inputs[0], inputs[1])]
    }
}

/// Raw phase correction (sec. 4.2.5): `A_i(x, y) ← A_i(x + i·u, y + i·v)` and the same for `B_i`,
/// with `(u, v)` the pixel's flow, coordinates clamped; bilinear between the four pixels around
/// where the flow is fractional (sub-pixel matching), exactly the pixel where it is whole.
pub fn correct_raw(raw: &Image, flow: &Image) -> Image {
    let (w, h) = (raw.width, raw.height);
    let n = w * h;
    let mut out = raw.clone();
    // Plane by plane, each on a core of its own: rows read and written in order.
    out.data[..8 * n].par_chunks_mut(n).enumerate().for_each(|(plane, corrected)| {
        let k = (plane / 2) as f32;
        let source = &raw.data[plane * n..(plane + 1) * n];
        for (y, row) in corrected.chunks_mut(w).enumerate() {
            for (x, value) in row.iter_mut().enumerate() {
                let i = y * w + x;
                let (u, v) = (flow.data[i], flow.data[n + i]);
                // (A whole number compared through an integer: `fract` is a libm call on x86-64.)
                *value = if u == u as i32 as f32 && v == v as i32 as f32 {
                    // Whole pixels: the one pixel bilinear sampling would give, exactly.
                    let sx = (x as isize + (k * u) as isize).clamp(0, w as isize - 1) as usize;
                    let sy = (y as isize + (k * v) as isize).clamp(0, h as isize - 1) as usize;
                    source[sy * w + sx]
                } else {
                    bilinear(x as f32 + k * u, y as f32 + k * v, |px, py| raw.at_clamped(plane, px, py))
                };
            }
        }
    });
    out
}
