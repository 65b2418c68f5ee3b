//! 3×3 outlier removal (sec. 6.5.1.3): distance → distance (flying pixels become 0).

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `remove_outliers.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    range: f32,
    min_similar: u32,
    _pad: [u32; 4],
}

/// Neighbours within `range` metres, at least `min_similar` of them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct RemoveOutliers {
    pub(crate) range: f32,
    pub(crate) min_similar: u32,
}

impl Unit for RemoveOutliers {
    const NAME: &'static str = "remove_outliers";
    const SOURCE: &'static str = include_str!("remove_outliers.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let (width, height) = (s.width as u32, s.height as u32);
        Params { width, height, range: self.range, min_similar: self.min_similar, _pad: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![remove_outliers(inputs[0], self.range, self.min_similar)]
    }
}

/// Sec. 6.5.1.3: a valid pixel stays valid when at least `min_similar` of its valid 8-neighbours
/// lie within `range` metres of it; else it becomes 0 (flying pixels go).
pub fn remove_outliers(distance: &Image, range: f32, min_similar: u32) -> Image {
    let (w, h) = (distance.width as isize, distance.height as isize);
    let mut out = distance.clone();
    for y in 0..h {
        for x in 0..w {
            let d = distance.data[(y * w + x) as usize];
            if d == 0.0 {
                continue;
            }
            let mut similar = 0;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h {
                        continue;
                    }
                    let n = distance.data[(ny * w + nx) as usize];
                    if n != 0.0 && (n - d).abs() < range {
                        similar += 1;
                    }
                }
            }
            if similar < min_similar {
                out.data[(y * w + x) as usize] = 0.0;
            }
        }
    }
    out
}
