//! The next frame's integration time in µs (sec. 5.3, eq. 5.4–5.8): intensity → 1 value.

use bytemuck::{Pod, Zeroable};

use super::{weight, IntegrationModel};
use crate::kernels::{linear, Scratch};
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `integration_time.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    /// width, height, t_curr, I_opt.
    size: [f32; 4],
    /// h, highest degree first.
    h: [f32; 4],
    /// h low, h high, gain, t_min.
    limits: [f32; 4],
    /// t_max.
    extra: [f32; 4],
}

/// The estimate from an intensity image taken at `t_curr` µs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct IntegrationTime {
    pub(crate) t_curr: f32,
    pub(crate) model: IntegrationModel,
}

impl Unit for IntegrationTime {
    const NAME: &'static str = "integration_time";
    const SOURCE: &'static str = concat!(include_str!("../workgroup_sum.wgsl"), include_str!("integration_time.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let (s, m) = (inputs[0], &self.model);
        Params {
            size: [s.width as f32, s.height as f32, self.t_curr, m.i_opt],
            h: m.h,
            limits: [m.h_range.0, m.h_range.1, m.gain, m.t_range.0],
            extra: [m.t_range.1, 0.0, 0.0, 0.0],
        }
    }

    fn outputs(&self, _inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { width: 1, height: 1, planes: 1 }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::main(linear(inputs[0].width * inputs[0].height)), Pass::finish()]
    }

    fn scratch(&self, inputs: &[Shape]) -> Option<Scratch> {
        let [x, y, _] = linear(inputs[0].width * inputs[0].height);
        Some(Scratch { len: (x * y) as usize * 2, start: 0 })
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![Image::from_plane(1, 1, vec![estimate(inputs[0], self.t_curr, &self.model)])]
    }
}

/// Eq. 5.4–5.8: the integration time for the next frame from the intensity image taken at
/// `t_curr` µs (pixels without signal carry no weight; each pixel's time is clamped to the
/// camera's range before the weighted mean).
pub fn estimate(intensity: &Image, t_curr: f32, model: &IntegrationModel) -> f32 {
    let (mut weighted, mut weights) = (0.0f64, 0.0f64);
    for (i, &measured) in intensity.plane(0).iter().enumerate() {
        if measured <= 0.0 {
            continue;
        }
        let t_opt = (model.i_opt / model.correct(measured) * t_curr).clamp(model.t_range.0, model.t_range.1);
        let w = weight(i % intensity.width, i / intensity.width, intensity.width, intensity.height) * model.gain;
        weighted += (w * t_opt) as f64;
        weights += w as f64;
    }
    if weights > 0.0 {
        (weighted / weights) as f32
    } else {
        t_curr
    }
}
