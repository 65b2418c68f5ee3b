//! Rigid transform of a point cloud: points → points.

use bytemuck::{Pod, Zeroable};

use crate::camera::{apply, Pose};
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `transform_points.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    /// The pose, row by row (3 × 4).
    pose: [f32; 12],
    /// width, height.
    size: [u32; 4],
}

/// Moving points by a pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TransformPoints {
    pub(crate) pose: Pose,
}

impl Unit for TransformPoints {
    const NAME: &'static str = "transform_points";
    const SOURCE: &'static str = include_str!("transform_points.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(3)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { pose: self.pose, size: [s.width as u32, s.height as u32, 0, 0] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 3, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![transform_points(inputs[0], &self.pose)]
    }
}

/// Moves every valid point (not at the origin) by `pose`.
pub fn transform_points(points: &Image, pose: &Pose) -> Image {
    let n = points.pixels();
    let mut out = Image::zeros(points.width, points.height, 3);
    for i in 0..n {
        let p = points.vector(i);
        if p[2] == 0.0 {
            continue;
        }
        for (k, value) in apply(pose, p, true).into_iter().enumerate() {
            out.data[k * n + i] = value;
        }
    }
    out
}
