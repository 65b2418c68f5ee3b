//! Motion detection (eq. 4.4, 4.5): raw frame → M and the mask `M > θ`.

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{pixels::per_pixel, Pass, Shape, Unit},
    Image,
};

/// The uniform block of `detect_motion.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    theta: f32,
    _pad: u32,
    _pad2: [u32; 4],
}

/// Motion detection with threshold θ.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DetectMotion {
    pub(crate) theta: f32,
}

impl Unit for DetectMotion {
    const NAME: &'static str = "detect_motion";
    const SOURCE: &'static str = concat!(include_str!("motion_measure.wgsl"), include_str!("detect_motion.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(8)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        Params { width: s.width as u32, height: s.height as u32, theta: self.theta, _pad: 0, _pad2: [0; 4] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }; 2]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        detect(inputs[0], self.theta).into()
    }
}

/// Motion detection (eq. 4.4, 4.5): `M = Σ_{i=1..3} |P⁺_i − P⁺_0|` and the mask `M > θ` (1 or 0).
pub fn detect(raw: &Image, theta: f32) -> [Image; 2] {
    let (w, h, n) = (raw.width, raw.height, raw.pixels());
    let d = &raw.data;
    let plus = |k: usize, i: usize| d[2 * k * n + i] + d[(2 * k + 1) * n + i];
    let motion = per_pixel(w, h, |x, y| {
        let i = y * w + x;
        let p0 = plus(0, i);
        (1..4).map(|k| (plus(k, i) - p0).abs()).sum::<f32>()
    });
    let mask = motion.iter().map(|&v| if v > theta { 1.0 } else { 0.0 }).collect();
    [Image { width: w, height: h, planes: 1, data: motion }, Image { width: w, height: h, planes: 1, data: mask }]
}
