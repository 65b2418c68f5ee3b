//! Filters on depth images that run one kernel on the distance (with the amplitude or the
//! intensity where the method needs it) and pass the rest of the image on: intensity
//! correction (Sec. 2.1.2.2), amplitude mask (eq. 6.1), median, Gaussian and bilateral
//! smoothing, outlier removal (Sec. 6.5.1.3).

use gudsl_runtime::Kernel;

use super::{slots, Component, Ctx, Inputs, Outputs, Params};
use crate::pipeline::{
    data::{Data, DepthImage, Tensor},
    executor::KernelSlot,
};

/// Which image of the depth image the kernel reads besides the distance.
#[derive(Clone, Copy)]
enum Second {
    None,
    Amplitude,
    Intensity,
}

/// One of the kernels on the distance, by the stage's class.
pub struct DepthKernel {
    /// The kernel for an image taken at an integration time (µs).
    kernel: Box<dyn Fn(f32) -> Kernel + Send>,
    second: Second,
    slots: Vec<KernelSlot>,
}

impl DepthKernel {
    pub fn new(params: &Params) -> DepthKernel {
        let (kernel, second): (Box<dyn Fn(f32) -> Kernel + Send>, Second) = match params.stage.class.as_str() {
            "ToF.IntensityCorrection" => {
                let q = [params.f32("q0"), params.f32("q1"), params.f32("q2")];
                let int_time_calib = params.f32("calibrationIntegrationTime");
                (Box::new(move |int_time| Kernel::CorrectIntensity { q, int_time_calib, int_time }), Second::Intensity)
            }
            "ToF.AmplitudeMask" => {
                let (min, max) = (params.f32("minAmplitude"), params.f32("maxAmplitude"));
                (Box::new(move |_| Kernel::MaskAmplitude { min, max }), Second::Amplitude)
            }
            "ToF.MedianFilter" => {
                let radius = (params.count("size") as u32).saturating_sub(1) / 2;
                (Box::new(move |_| Kernel::Median { radius }), Second::None)
            }
            "ToF.GaussianFilter" => {
                let sigma = params.f32("sigma");
                (Box::new(move |_| Kernel::Gaussian { sigma }), Second::None)
            }
            "ToF.BilateralFilter" => {
                let (radius, sigma_space, sigma_range) =
                    (params.count("radius") as u32, params.f32("sigmaSpace"), params.f32("sigmaRange"));
                (Box::new(move |_| Kernel::Bilateral { radius, sigma_space, sigma_range }), Second::None)
            }
            // ToF.OutlierRemoval
            _ => {
                let (range, min_similar) = (params.f32("range"), params.count("minNeighbours") as u32);
                (Box::new(move |_| Kernel::RemoveOutliers { range, min_similar }), Second::None)
            }
        };
        DepthKernel { kernel, second, slots: Vec::new() }
    }
}

impl Component for DepthKernel {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        let images = inputs.port("DepthIn").iter().filter_map(|item| match &item.data {
            Data::Depth(depth) => Some(depth),
            _ => None,
        });
        for (k, depth) in images.enumerate() {
            let mut reads: Vec<&Tensor> = vec![&depth.distance];
            match self.second {
                Second::None => {}
                Second::Amplitude => reads.push(&depth.amplitude),
                Second::Intensity => reads.push(&depth.intensity),
            }
            let kernel = (self.kernel)(depth.integration_us);
            let distance = ctx
                .device
                .kernel(ctx.stage, slots(&mut self.slots, k), kernel, &reads)
                .map_err(|e| e.to_string())?
                .remove(0);
            out.push(("DepthOut".to_string(), Data::Depth(DepthImage { distance, ..depth.clone() })));
        }
        Ok(out)
    }
}
