//! Normals by central differences (sec. 6.5.3): points → normals (3 planes).

use crate::{
    kernels::{Pass, Shape, SizeParams, Unit},
    Image,
};

/// Normals of a point cloud.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Normals;

impl Unit for Normals {
    const NAME: &'static str = "normals";
    const SOURCE: &'static str = include_str!("normals.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(3)];
    type Params = SizeParams;

    fn params(&self, inputs: &[Shape]) -> SizeParams {
        SizeParams::of(inputs[0])
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 3, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![normals(inputs[0])]
    }
}

/// Normals by central differences (sec. 6.5.3), facing the camera:
/// `n = normalise((P(x, y+1) − P(x, y−1)) × (P(x+1, y) − P(x−1, y)))`; zero where a neighbour
/// is invalid (at the origin) or outside the image.
pub fn normals(points: &Image) -> Image {
    let (w, h) = (points.width, points.height);
    let n = w * h;
    let at = |x: usize, y: usize| points.vector(y * w + x);
    let mut out = Image::zeros(w, h, 3);
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let (l, r, u, d, c) = (at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1), at(x, y));
            if [l, r, u, d, c].iter().any(|p| p[2] == 0.0) {
                continue;
            }
            let a = [d[0] - u[0], d[1] - u[1], d[2] - u[2]];
            let b = [r[0] - l[0], r[1] - l[1], r[2] - l[2]];
            let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
            let len = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
            if len > 0.0 {
                for (k, c) in cross.into_iter().enumerate() {
                    out.data[k * n + y * w + x] = c / len;
                }
            }
        }
    }
    out
}
