//! Median smoothing of flow directions ("NH", sec. 4.2.4): flow → flow.

use bytemuck::{Pod, Zeroable};

use super::angle_of;
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `smooth_flow.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    _pad: u32,
    _pad2: [u32; 4],
}

/// Smoothing over a `window × window` neighbourhood.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct SmoothFlow {
    pub(crate) window: u32,
}

impl Unit for SmoothFlow {
    const NAME: &'static str = "smooth_flow";
    const SOURCE: &'static str = include_str!("smooth_flow.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(2)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { width: s.width as u32, height: s.height as u32, radius: (self.window - 1) / 2, _pad: 0, _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![inputs[0]]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![smooth_flow(inputs[0], self.window)]
    }
}

/// Flow smoothing ("NH", sec. 4.2.4): each non-zero vector takes the median direction of the
/// non-zero vectors in its `window × window` neighbourhood, keeps its length, and is rounded
/// to whole pixels.
pub fn smooth_flow(flow: &Image, window: u32) -> Image {
    let (w, h) = (flow.width, flow.height);
    let r = (window as isize - 1) / 2;
    let n = w * h;
    let mut out = flow.clone();
    for y in 0..h as isize {
        for x in 0..w as isize {
            let i = y as usize * w + x as usize;
            let (u, v) = (flow.data[i], flow.data[n + i]);
            if u == 0.0 && v == 0.0 {
                continue;
            }
            let mut angles: Vec<f32> = Vec::new();
            for dy in -r..=r {
                for dx in -r..=r {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    let (a, b) = (flow.data[j], flow.data[n + j]);
                    if a != 0.0 || b != 0.0 {
                        angles.push(angle_of(a, b));
                    }
                }
            }
            angles.sort_by(f32::total_cmp);
            let median = angles[angles.len() / 2];
            let length = (u * u + v * v).sqrt();
            out.data[i] = (length * median.cos()).round();
            out.data[n + i] = (length * median.sin()).round();
        }
    }
    out
}
