//! Median smoothing of flow directions ("NH", sec. 4.2.4): flow → flow.

use std::f32::consts::PI;

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{
        pixels::{per_pixel, scatter},
        Pass, Shape, Unit,
    },
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
/// to whole pixels (ties to even, as WGSL's `round`). The median is circular: the neighbours'
/// directions are taken relative to the pixel's own, wrapped to (−π, π], and the median
/// neighbour's direction is the result — so directions either side of 0°/360° are neighbours,
/// not opposites.
pub fn smooth_flow(flow: &Image, window: u32) -> Image {
    let (w, h) = (flow.width, flow.height);
    let r = (window as isize - 1) / 2;
    let n = w * h;
    let smoothed = per_pixel(w, h, |x, y| {
        let i = y * w + x;
        let (u, v) = (flow.data[i], flow.data[n + i]);
        if u == 0.0 && v == 0.0 {
            return [u, v];
        }
        let (x, y) = (x as isize, y as isize);
        // (direction relative to the pixel's own, the neighbour's vector)
        let mut neighbours: Vec<(f32, f32, f32)> = Vec::with_capacity(((2 * r + 1) * (2 * r + 1)) as usize);
        for dy in -r..=r {
            for dx in -r..=r {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                let (a, b) = (flow.data[j], flow.data[n + j]);
                if a != 0.0 || b != 0.0 {
                    neighbours.push((relative_angle(u, v, a, b), a, b));
                }
            }
        }
        neighbours.sort_by(|p, q| p.0.total_cmp(&q.0));
        let (_, a, b) = neighbours[neighbours.len() / 2];
        let scale = (u * u + v * v).sqrt() / (a * a + b * b).sqrt();
        [(a * scale).round_ties_even(), (b * scale).round_ties_even()]
    });
    let mut out = Image::zeros(w, h, 2);
    scatter(&mut out.data, n, &smoothed);
    out
}

/// The direction of `(a, b)` relative to `(u, v)` in (−π, π], from their cross and dot products:
/// exact in sign for the flow's whole and quarter pixels, so the GPU sorts as the CPU does.
fn relative_angle(u: f32, v: f32, a: f32, b: f32) -> f32 {
    let d = (u * b - v * a).atan2(u * a + v * b);
    if d <= -PI {
        PI
    } else {
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3×3 flow: the centre's vector points up (90°) among four vectors at 14° and four at
    /// 346°. The directions around 0° are the majority; a linear median of [0, 2π) angles
    /// would sort them apart, with 90° in the middle.
    #[test]
    fn the_median_direction_wraps_around_zero() {
        let mut flow = Image::zeros(3, 3, 2);
        for i in 0..9 {
            let (u, v) = match i {
                4 => (0.0, 4.0),
                i if i % 2 == 0 => (4.0, 1.0),
                _ => (4.0, -1.0),
            };
            flow.data[i] = u;
            flow.data[9 + i] = v;
        }
        let smoothed = smooth_flow(&flow, 3);
        assert_eq!((smoothed.data[4], smoothed.data[13]), (4.0, 1.0), "length 4 along 14°");
    }
}
