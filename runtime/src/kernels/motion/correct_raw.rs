//! Raw phase correction along the flow (sec. 4.2.5): raw frame, flow → raw frame.

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
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let (u, v) = (flow.data[i], flow.data[n + i]);
            for k in 0..4 {
                let (sx, sy) = (x as f32 + k as f32 * u, y as f32 + k as f32 * v);
                for plane in [2 * k, 2 * k + 1] {
                    out.data[plane * n + i] = bilinear(sx, sy, |px, py| raw.at_clamped(plane, px, py));
                }
            }
        }
    }
    out
}
