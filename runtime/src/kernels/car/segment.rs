//! Foreground segmentation (sec. 6.5.2): intensity, distance, background intensity,
//! background distance → mask.

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `segment.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    theta_intensity: f32,
    theta_distance: f32,
    _pad: [u32; 4],
}

/// The thresholds on intensity and distance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    pub(crate) theta_intensity: f32,
    pub(crate) theta_distance: f32,
}

impl Unit for Segment {
    const NAME: &'static str = "segment";
    const SOURCE: &'static str = include_str!("segment.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1), Some(1), Some(1), Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let (len, width) = ((s.width * s.height) as u32, s.width as u32);
        let (theta_intensity, theta_distance) = (self.theta_intensity, self.theta_distance);
        Params { len, width, theta_intensity, theta_distance, _pad: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        let [i, d, bi, bd] = [inputs[0], inputs[1], inputs[2], inputs[3]];
        vec![segment(i, d, bi, bd, self.theta_intensity, self.theta_distance)]
    }
}

/// Foreground (sec. 6.5.2): `|I − B_I| > θ_I AND |D − B_D| > θ_D` on valid distances, as 1 or 0.
pub fn segment(
    intensity: &Image,
    distance: &Image,
    background_intensity: &Image,
    background_distance: &Image,
    theta_intensity: f32,
    theta_distance: f32,
) -> Image {
    let data = (0..distance.data.len())
        .map(|i| {
            let d = distance.data[i];
            let foreground = d != 0.0
                && (intensity.data[i] - background_intensity.data[i]).abs() > theta_intensity
                && (d - background_distance.data[i]).abs() > theta_distance;
            if foreground {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    Image { data, ..distance.clone() }
}
