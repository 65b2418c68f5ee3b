//! One projective point-to-plane ICP step (sec. 6.5.3): source points, source normals, model
//! points, model normals → the 29 sums of the 6×6 system (see [`SUMS`]).

use bytemuck::{Pod, Zeroable};

use super::{cross, dot, SUMS};
use crate::{
    camera::{apply, Intrinsics, Pose},
    kernels::{linear_groups, Scratch},
};
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `icp_reduce.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    /// The current pose, row by row (3 × 4).
    pose: [f32; 12],
    /// fx, fy, cx, cy.
    focal_centre: [f32; 4],
    /// k1, k2, p1, p2.
    distortion: [f32; 4],
    /// width, height, max distance, min cos.
    limits: [f32; 4],
}

/// Pairs within `max_distance` metres whose normals differ by less than the angle of `min_cos`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct IcpReduce {
    pub(crate) pose: Pose,
    pub(crate) intrinsics: Intrinsics,
    pub(crate) max_distance: f32,
    pub(crate) min_cos: f32,
}

impl Unit for IcpReduce {
    const NAME: &'static str = "icp_reduce";
    const SOURCE: &'static str = concat!(include_str!("../workgroup_sum.wgsl"), include_str!("icp_reduce.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(3), Some(3), Some(3), Some(3)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let (s, k) = (inputs[0], &self.intrinsics);
        Params {
            pose: self.pose,
            focal_centre: [k.fx, k.fy, k.cx, k.cy],
            distortion: [k.k1, k.k2, k.p1, k.p2],
            limits: [s.width as f32, s.height as f32, self.max_distance, self.min_cos],
        }
    }

    fn outputs(&self, _inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { width: SUMS, height: 1, planes: 1 }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main(groups(inputs[0])), Pass::finish()]
    }

    fn scratch(&self, inputs: &[Shape]) -> Option<Scratch> {
        let [x, y, _] = groups(inputs[0]);
        Some(Scratch { len: (x * y) as usize * SUMS, start: 0 })
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        let sums = reduce(
            [inputs[0], inputs[1], inputs[2], inputs[3]],
            &self.pose,
            &self.intrinsics,
            self.max_distance,
            self.min_cos,
        );
        vec![Image::from_plane(SUMS, 1, sums.iter().map(|&v| v as f32).collect())]
    }
}

/// One workgroup of 64 threads per 64 pixels, each reducing its pixels' sums together.
fn groups(input: Shape) -> [u32; 3] {
    linear_groups(input.width * input.height, 64)
}

/// The sums of one ICP step (see [`SUMS`]) over `[source, source normals, model, model normals]`,
/// accumulated in f64.
pub fn reduce(
    clouds: [&Image; 4],
    pose: &Pose,
    intrinsics: &Intrinsics,
    max_distance: f32,
    min_cos: f32,
) -> [f64; SUMS] {
    let mut sums = [0.0f64; SUMS];
    for i in 0..clouds[0].pixels() {
        if let Some((a, b)) = pair(clouds, pose, intrinsics, max_distance, min_cos, i) {
            let mut k = 0;
            for r in 0..6 {
                for c in r..6 {
                    sums[k] += (a[r] * a[c]) as f64;
                    k += 1;
                }
            }
            for r in 0..6 {
                sums[21 + r] += (a[r] * b) as f64;
            }
            sums[27] += 1.0;
            sums[28] += (b * b) as f64;
        }
    }
    sums
}

/// The linearised pair of source pixel `i`, if it has a model partner.
fn pair(
    [source, source_normals, model, model_normals]: [&Image; 4],
    pose: &Pose,
    intrinsics: &Intrinsics,
    max_distance: f32,
    min_cos: f32,
    i: usize,
) -> Option<([f32; 6], f32)> {
    let (s, sn) = (source.vector(i), source_normals.vector(i));
    if s[2] == 0.0 || sn == [0.0; 3] {
        return None;
    }
    let p = apply(pose, s, true);
    let np = apply(pose, sn, false);
    let (u, v) = intrinsics.project(p)?;
    let (u, v) = ((u + 0.5).floor(), (v + 0.5).floor());
    if u < 0.0 || v < 0.0 || u >= model.width as f32 || v >= model.height as f32 {
        return None;
    }
    let j = v as usize * model.width + u as usize;
    let (d, n) = (model.vector(j), model_normals.vector(j));
    if d[2] == 0.0 || n == [0.0; 3] {
        return None;
    }
    let diff = [d[0] - p[0], d[1] - p[1], d[2] - p[2]];
    if dot(diff, diff) > max_distance * max_distance || dot(np, n) < min_cos {
        return None;
    }
    let pn = cross(p, n);
    Some(([pn[0], pn[1], pn[2], n[0], n[1], n[2]], dot(n, diff)))
}
