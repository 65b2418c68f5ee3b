//! The mean direction of a flow on the GPU (`mean_direction.wgsl`): flow, the direction before
//! → the direction, a 1×1 value of two planes (radians in [0, 2π), 1 when known). The next
//! frame's restricted search ([`super::DetectMatchAround`]) reads it where it is, so ρ needs no
//! read back and frames overlap.

use super::angle_of;
use crate::{
    kernels::{Pass, Shape, SizeParams, Unit},
    Image,
};

/// The threads of its one workgroup (`mean_direction.wgsl`'s `THREADS`).
const THREADS: usize = 256;

/// The circular mean of a flow's non-zero vectors, else the direction before.
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

    fn passes(&self, _inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main([1, 1, 1])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        let data = match summed_unit_vectors(inputs[0]) {
            [c, s, count] if count > 0.0 => vec![angle_of(c, s), 1.0],
            _ => inputs[1].data[..2].to_vec(),
        };
        vec![Image { width: 1, height: 1, planes: 2, data }]
    }
}

/// The sum of the unit vectors of `flow`'s non-zero vectors and their count, added as the
/// shader adds them: thread t over pixels t, t + 256, …, then the threads' sums in a tree.
fn summed_unit_vectors(flow: &Image) -> [f32; 3] {
    let n = flow.pixels();
    let mut sums = [[0.0f32; 3]; THREADS];
    for (t, sum) in sums.iter_mut().enumerate() {
        for i in (t..n).step_by(THREADS) {
            let (u, v) = (flow.data[i], flow.data[n + i]);
            if u != 0.0 || v != 0.0 {
                let r = (u * u + v * v).sqrt();
                *sum = [sum[0] + u / r, sum[1] + v / r, sum[2] + 1.0];
            }
        }
    }
    let mut half = THREADS / 2;
    while half > 0 {
        for t in 0..half {
            let other = sums[t + half];
            sums[t] = [sums[t][0] + other[0], sums[t][1] + other[1], sums[t][2] + other[2]];
        }
        half /= 2;
    }
    sums[0]
}
