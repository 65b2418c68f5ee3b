//! Chapter 5's automatic integration time as a stage (`ToF.IntegrationTimeControl`): from each
//! depth image's intensity, the time the next frame should be taken at — per pixel (sec. 5.3:
//! the runtime's `IntegrationTime` kernel, where the image is) or by May et al.'s proportional
//! controller on the mean intensity — given after the frame's reads, so it reaches a
//! `ControlledCamera` through its buffered `TimeIn` port the next frame (the loop of sec. 5.4).

use gudsl_runtime::{exposure::ProportionalController, kernels::integration::IntegrationModel, Kernel};

use super::{depth_images, slots, Component, Ctx, Inputs, Outputs, Params};
use crate::pipeline::{
    data::Data,
    executor::{KernelSlot, Later, Reads},
    ErrorKind, PipelineError,
};

/// How the next time is chosen.
enum Method {
    /// Sec. 5.3 with the sensor's model (the simulated camera's or Table 5.1's CamCube), in
    /// the component's time range.
    PerPixel(IntegrationModel),
    Proportional(ProportionalController),
}

pub struct IntegrationTimeControl {
    method: Method,
    /// This frame's reads: the per-pixel estimate or the intensity, with the time the image was
    /// taken at.
    pending: Vec<(Later, f32)>,
    kernels: Vec<KernelSlot>,
}

impl IntegrationTimeControl {
    pub fn new(params: &Params) -> Result<IntegrationTimeControl, Vec<PipelineError>> {
        let t_range = (params.f32("minIntegrationTime"), params.f32("maxIntegrationTime"));
        if t_range.0 > t_range.1 {
            let message =
                format!("the shortest integration time {} µs is above the longest, {} µs", t_range.0, t_range.1);
            return Err(vec![params.error("minIntegrationTime", ErrorKind::Mismatch, message)]);
        }
        let method = match params.member("method") {
            "MeanIntensity" => Method::Proportional(ProportionalController {
                target: params.f32("targetIntensity"),
                k: params.f32("gain"),
                t_range,
            }),
            _ => {
                let sensor = match params.member("sensor") {
                    "CamCube" => IntegrationModel::CAMCUBE,
                    _ => IntegrationModel::SIMULATED,
                };
                Method::PerPixel(IntegrationModel { t_range, ..sensor })
            }
        };
        Ok(IntegrationTimeControl { method, pending: Vec::new(), kernels: Vec::new() })
    }
}

impl Component for IntegrationTimeControl {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for (k, (_, depth)) in depth_images(inputs).enumerate() {
            let t_curr = depth.integration_us;
            let read = match self.method {
                Method::PerPixel(model) => {
                    let kernel = Kernel::IntegrationTime { t_curr, model };
                    let slot = slots(&mut self.kernels, k);
                    let estimate =
                        ctx.device.kernel(ctx.stage, slot, kernel, &[&depth.intensity]).map_err(|e| e.to_string())?;
                    ctx.device.read_later(&estimate[0])
                }
                Method::Proportional(_) => ctx.device.read_later(&depth.intensity),
            };
            self.pending.push((read, t_curr));
        }
        Ok(Vec::new())
    }

    /// The next integration time is the camera's next frame's.
    fn feeds_back(&self) -> bool {
        true
    }

    fn finish_frame(&mut self, _ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        let times = std::mem::take(&mut self.pending).into_iter().map(|(read, t_curr)| {
            let image = reads.get(read);
            let next = match &self.method {
                Method::PerPixel(_) => image.data[0],
                Method::Proportional(controller) => controller.next(image, t_curr),
            };
            ("TimeOut".to_string(), Data::IntegrationTime(next))
        });
        Ok(times.collect())
    }
}
