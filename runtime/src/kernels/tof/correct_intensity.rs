//! Intensity-related distance correction (sec. 2.1.2.2): distance, intensity → distance.

use bytemuck::{Pod, Zeroable};

use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `correct_intensity.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    len: u32,
    width: u32,
    q0: f32,
    q1: f32,
    q2: f32,
    /// `intT_calib / intT`.
    scale: f32,
    _pad: [u32; 2],
}

/// The correction polynomial `q` measured at `int_time_calib`, applied at `int_time` (µs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CorrectIntensity {
    pub(crate) q: [f32; 3],
    pub(crate) int_time_calib: f32,
    pub(crate) int_time: f32,
}

impl Unit for CorrectIntensity {
    const NAME: &'static str = "correct_intensity";
    const SOURCE: &'static str = include_str!("correct_intensity.wgsl");
    const INPUTS: &'static [Option<usize>] = &[Some(1), Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let [q0, q1, q2] = self.q;
        let scale = self.int_time_calib / self.int_time;
        Params { len: s.len() as u32, width: s.width as u32, q0, q1, q2, scale, _pad: [0; 2] }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![correct_intensity(inputs[0], inputs[1], self.q, self.int_time_calib, self.int_time)]
    }
}

/// Intensity-related distance correction (sec. 2.1.2.2):
/// `D_c = D_m − δ_calib(I_m · intT_calib / intT)`, `δ_calib(x) = q2·x² + q1·x + q0`.
pub fn correct_intensity(
    distance: &Image,
    intensity: &Image,
    q: [f32; 3],
    int_time_calib: f32,
    int_time: f32,
) -> Image {
    let data = distance
        .data
        .iter()
        .zip(&intensity.data)
        .map(|(d, i)| {
            let x = i * int_time_calib / int_time;
            d - (q[2] * x * x + q[1] * x + q[0])
        })
        .collect();
    Image { data, ..distance.clone() }
}
