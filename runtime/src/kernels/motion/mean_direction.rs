//! The mean direction of a flow on the GPU (`mean_direction.wgsl`): flow, the direction before
//! → the direction, a 1×1 value of two planes (radians in [0, 2π), 1 when known). The next
//! frame's restricted search ([`super::DetectMatchAround`]) reads it where it is, so ρ needs no
//! read back and frames overlap.

use super::angle_of;
use crate::{
    kernels::{linear_groups, Pass, Scratch, Shape, SizeParams, Unit},
    Image,
};

/// The threads of a workgroup (`mean_direction.wgsl`'s `THREADS`).
const THREADS: usize = 256;
/// The pixels each thread of pass `main` adds (`PER_THREAD`).
const PER_THREAD: usize = 16;

/// The circular mean of a flow's non-zero vectors, else (nothing moved, or the vectors cancel)
/// the direction before.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MeanDirection;

impl Unit for MeanDirection {
    const NAME: &'static str = "mean_direction";
    const SOURCE: &'static str = include_str!("mean_direction.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(2), Some(2)];
    const VALUES: &'static [usize] = &[1];
    type Params = SizeParams;

    fn params(&self, inputs: &[Shape]) -> SizeParams {
        SizeParams::of(inputs[0])
    }

    fn outputs(&self, _inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { width: 1, height: 1, planes: 2 }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main(linear_groups(groups(inputs[0].width * inputs[0].height), 1)), Pass::finish()]
    }

    /// Two sums (x, y) a workgroup of pass `main`.
    fn scratch(&self, inputs: &[Shape]) -> Option<Scratch> {
        Some(Scratch { len: 2 * groups(inputs[0].width * inputs[0].height), start: 0 })
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        let data = match summed_unit_vectors(inputs[0]) {
            // Vectors that cancel have no direction either.
            [x, y] if x != 0.0 || y != 0.0 => vec![angle_of(x, y), 1.0],
            _ => inputs[1].data[..2].to_vec(),
        };
        vec![Image { width: 1, height: 1, planes: 2, data }]
    }
}

/// The workgroups of pass `main` over a flow of `pixels` (`group_count` in the shader).
fn groups(pixels: usize) -> usize {
    pixels.div_ceil(THREADS * PER_THREAD)
}

/// The sum of the unit vectors of `flow`'s non-zero vectors, added as the shader adds them:
/// thread t of workgroup g its pixels t, t + 256, … of g's 256 × 16, the threads' sums in a
/// tree; then thread t the workgroups' sums t, t + 256, …, then a tree.
fn summed_unit_vectors(flow: &Image) -> [f32; 2] {
    let n = flow.pixels();
    let unit = |i: usize| {
        let (u, v) = (flow.data[i], flow.data[n + i]);
        if u == 0.0 && v == 0.0 {
            return [0.0; 2];
        }
        let r = (u * u + v * v).sqrt();
        [u / r, v / r]
    };
    let thread = |g: usize, t: usize| {
        let pixels = (0..PER_THREAD).map(|k| (g * PER_THREAD + k) * THREADS + t).filter(|&i| i < n);
        pixels.map(unit).fold([0.0; 2], |sum, u| [sum[0] + u[0], sum[1] + u[1]])
    };
    let partial: Vec<[f32; 2]> = (0..groups(n)).map(|g| tree(std::array::from_fn(|t| thread(g, t)))).collect();
    tree(std::array::from_fn(|t| {
        partial.iter().skip(t).step_by(THREADS).fold([0.0; 2], |sum, p| [sum[0] + p[0], sum[1] + p[1]])
    }))
}

/// A workgroup's sum of its threads' values, as `workgroup_total` adds them.
fn tree(mut values: [[f32; 2]; THREADS]) -> [f32; 2] {
    let mut stride = THREADS / 2;
    while stride > 0 {
        for t in 0..stride {
            let other = values[t + stride];
            values[t] = [values[t][0] + other[0], values[t][1] + other[1]];
        }
        stride /= 2;
    }
    values[0]
}
