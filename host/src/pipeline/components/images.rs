//! RGBA images (`ToF.RgbaImage`): the simulated camera seen as a grey-value camera
//! (`ToF.AmplitudeCamera`), a depth image's amplitude as an image (`ToF.AmplitudeImage`), and the
//! viewer of a run without a screen (`ToF.ImageViewer`: PNG files).

use gudsl_runtime::Kernel;

use super::{
    raw::Demodulation, sinks::png, slots, sources::Simulated, Carries, Component, Ctx, Inputs, Outputs, Params,
    PerFrame, Size,
};
use crate::pipeline::{
    data::{Data, Item, Picture},
    executor::{KernelSlot, Later, Reads},
};

/// `ToF.AmplitudeImage`.
pub struct AmplitudeImage {
    gain: f32,
    kernels: Vec<KernelSlot>,
}

impl AmplitudeImage {
    pub fn new(params: &Params) -> AmplitudeImage {
        AmplitudeImage { gain: params.f32("gain"), kernels: Vec::new() }
    }
}

impl Component for AmplitudeImage {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let mut out = Vec::new();
        for (k, item) in inputs.port("DepthIn").iter().enumerate() {
            let Data::Depth(depth) = &item.data else { continue };
            let kernel = Kernel::GreyImage { gain: self.gain };
            let texels = ctx
                .device
                .kernel(ctx.stage, slots(&mut self.kernels, k), kernel, &[&depth.amplitude])
                .map_err(|e| e.to_string())?
                .remove(0);
            out.push(("ImageOut".to_string(), Data::Image(Picture { texels, source: item.producer.clone() })));
        }
        Ok(out)
    }
}

/// `ToF.AmplitudeCamera`: a simulated camera, demodulated, its amplitude as an image.
pub struct AmplitudeCamera {
    instance: String,
    camera: Simulated,
    demodulation: Demodulation,
    grey: AmplitudeImage,
}

impl AmplitudeCamera {
    pub fn new(params: &Params) -> AmplitudeCamera {
        AmplitudeCamera {
            instance: params.stage.instance.clone(),
            camera: {
                let mut camera = Simulated::new(params, false);
                camera.gives_black = false;
                camera
            },
            demodulation: Demodulation::new(params),
            grey: AmplitudeImage::new(params),
        }
    }

    /// What `stage` gave, as the next one's inputs on `port`.
    fn inputs(&self, port: &str, given: Outputs, frame: usize) -> Inputs {
        let mut inputs = Inputs::default();
        for (_, data) in given {
            inputs.push(port, Item { data, producer: self.instance.clone(), frame });
        }
        inputs
    }
}

impl Component for AmplitudeCamera {
    fn frames(&self) -> Option<usize> {
        self.camera.frames()
    }

    fn carries(&self, arriving: Carries) -> Carries {
        self.camera.carries(arriving)
    }

    fn image_size(&self) -> Option<Size> {
        self.camera.image_size()
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        let raw = self.camera.process(ctx, inputs)?;
        let raw = self.inputs("RawIn", raw, ctx.frame);
        let depth = self.demodulation.process(ctx, &raw)?;
        let depth = self.inputs("DepthIn", depth, ctx.frame);
        self.grey.process(ctx, &depth)
    }
}

/// `ToF.ImageViewer`: each image as `<source>_<frame>.png` (RGBA, 8 bits per channel), named
/// `<producer>_<source>_<frame>.png` when several bindings feed it (one source's images may
/// arrive by two ways).
pub struct ImageViewer {
    instance: String,
    several: bool,
    /// Reads asked for this frame: (file name's prefix, read).
    pending: PerFrame<Vec<(String, Later)>>,
}

impl ImageViewer {
    pub fn new(params: &Params) -> ImageViewer {
        ImageViewer {
            instance: params.stage.instance.clone(),
            several: params.providers > 1,
            pending: PerFrame::default(),
        }
    }
}

impl Component for ImageViewer {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for item in inputs.port("ImageIn") {
            if let Data::Image(picture) = &item.data {
                let prefix = match self.several {
                    true => format!("{}_{}", item.producer, picture.source),
                    false => picture.source.clone(),
                };
                let read = ctx.device.read_later(&picture.texels);
                self.pending.now(ctx.device).push((prefix, read));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (prefix, later) in self.pending.take(reads) {
            let image = reads.get(later);
            let pixels = image.width * image.height;
            let texels: Vec<u8> = (0..pixels)
                .flat_map(|i| (0..4).map(move |c| (c, i)))
                .map(|(c, i)| image.data[c * pixels + i].clamp(0.0, 255.0) as u8)
                .collect();
            let buffer = image::RgbaImage::from_raw(image.width as u32, image.height as u32, texels)
                .ok_or("an image of no pixels")?;
            ctx.output.write(&self.instance, &format!("{prefix}_{:04}.png", ctx.frame), &png(buffer)?)?;
        }
        Ok(Vec::new())
    }
}
