//! Polar → Cartesian (sec. 6.5.3): distance, unit rays (3 planes) → points (3 planes).

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `point_cloud.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    _pad: [u32; 2],
    _pad2: [u32; 4],
}

/// Points from distances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PointCloud;

impl Unit for PointCloud {
    const NAME: &'static str = "point_cloud";
    const SOURCE: &'static str = include_str!("point_cloud.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1), Some(3)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { len: (s.width * s.height) as u32, width: s.width as u32, _pad: [0; 2], _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 3, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![point_cloud(inputs[0], inputs[1])]
    }
}

/// Polar → Cartesian (sec. 6.5.3): `P = D · ray` with the per-pixel unit rays of the intrinsics
/// (3 planes: x, y, z); invalid distances give the origin.
pub fn point_cloud(distance: &Image, rays: &Image) -> Image {
    let n = distance.pixels();
    let mut out = Image::zeros(distance.width, distance.height, 3);
    for i in 0..n {
        for k in 0..3 {
            out.data[k * n + i] = distance.data[i] * rays.data[k * n + i];
        }
    }
    out
}
