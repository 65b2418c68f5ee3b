//! Sinks: raw frames to `.npy` (the channels a recording has), depth images to `.npy` and OpenEXR (float32) and PNG (16-bit millimetres and a
//! colour-mapped preview), point clouds to PLY and PCD (the accuracy report: `accuracy.rs`). Each asks for its images at the end of the frame and writes them then, into a
//! folder of the output named after its instance; fed by several producers, it prefixes its
//! files with the producer's name.

use std::{io::Cursor, sync::Arc};

use gudsl_formats::{arrays, ply::Points};

use super::{depth_images, depth_planes, Component, Ctx, Inputs, Outputs, Params, PerFrame};
use crate::pipeline::{
    data::Data,
    executor::{Later, Reads},
    OutputDir,
};

/// A file name for frame `frame` of `what`: `distance_0003.npy`, or with several producers
/// `Demod_distance_0003.npy`.
fn file_name(prefix: Option<&str>, what: &str, frame: usize, extension: &str) -> String {
    match prefix {
        Some(producer) => format!("{producer}_{what}_{frame:04}.{extension}"),
        None => format!("{what}_{frame:04}.{extension}"),
    }
}

/// Reads asked for this frame: (producer, what, read).
type Pending = PerFrame<Vec<(String, &'static str, Later)>>;

/// `ToF.NpyWriter` and `ToF.ExrWriter`: depth images a file a frame and plane
/// (`distance_0003.npy`, float32) or a file a frame (`depth_0003.exr`, float32 channels `Z` —
/// the distance, where depth readers look —, `amplitude`, `intensity`).
pub struct DepthWriter {
    instance: String,
    format: DepthFormat,
    planes: Vec<&'static str>,
    several: bool,
    pending: Pending,
}

/// The files a [`DepthWriter`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DepthFormat {
    Npy,
    Exr,
}

impl DepthWriter {
    pub fn new(params: &Params, format: DepthFormat) -> DepthWriter {
        let planes = ["distance", "amplitude", "intensity"].into_iter().filter(|p| params.flag(p)).collect();
        DepthWriter {
            instance: params.stage.instance.clone(),
            format,
            planes,
            several: params.providers > 1,
            pending: PerFrame::default(),
        }
    }

    /// One producer's planes of a frame as one EXR file.
    fn write_exr(
        &self,
        ctx: &mut Ctx,
        producer: &str,
        planes: &[(&str, &Arc<gudsl_runtime::Image>)],
    ) -> Result<(), String> {
        let Some((_, first)) = planes.first() else { return Ok(()) };
        let channels: Vec<(&str, &[f32])> = planes
            .iter()
            .map(|(what, image)| (if *what == "distance" { "Z" } else { what }, &image.data[..]))
            .collect();
        let bytes = gudsl_formats::openexr::encode(first.width, first.height, &channels);
        let name = file_name(self.several.then_some(producer), "depth", ctx.frame, "exr");
        ctx.output.write(&self.instance, &name, &bytes)?;
        Ok(())
    }
}

impl Component for DepthWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for (producer, depth) in depth_images(inputs) {
            for (what, tensor) in depth_planes(depth, &self.planes) {
                let read = ctx.device.read_later(tensor);
                self.pending.now(ctx.device).push((producer.to_string(), what, read));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        let pending = self.pending.take(reads);
        if self.format == DepthFormat::Exr {
            for (k, (producer, ..)) in pending.iter().enumerate().step_by(self.planes.len().max(1)) {
                let planes: Vec<_> = pending[k..k + self.planes.len()]
                    .iter()
                    .map(|(_, what, later)| (*what, reads.get(*later)))
                    .collect();
                self.write_exr(ctx, producer, &planes)?;
            }
            return Ok(Vec::new());
        }
        for (producer, what, later) in pending {
            let image = reads.get(later);
            let bytes = arrays::encode(&[image.height, image.width], &image.data, arrays::Dtype::F32);
            let name = file_name(self.several.then_some(producer.as_str()), what, ctx.frame, "npy");
            ctx.output.write(&self.instance, &name, &bytes)?;
        }
        Ok(Vec::new())
    }
}

/// `ToF.PngWriter`.
pub struct PngWriter {
    instance: String,
    distance: bool,
    preview: bool,
    max_distance: f32,
    several: bool,
    pending: Pending,
}

impl PngWriter {
    pub fn new(params: &Params) -> PngWriter {
        PngWriter {
            instance: params.stage.instance.clone(),
            distance: params.flag("distance"),
            preview: params.flag("preview"),
            max_distance: params.f32("maxDistance"),
            several: params.providers > 1,
            pending: PerFrame::default(),
        }
    }
}

impl Component for PngWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        if self.distance || self.preview {
            for (producer, depth) in depth_images(inputs) {
                let read = ctx.device.read_later(&depth.distance);
                self.pending.now(ctx.device).push((producer.to_string(), "distance", read));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, _, later) in self.pending.take(reads) {
            let image = reads.get(later);
            let prefix = self.several.then_some(producer.as_str());
            if self.distance {
                let millimetres: Vec<u16> =
                    image.plane(0).iter().map(|d| (d * 1000.0).round().clamp(0.0, 65535.0) as u16).collect();
                let buffer = image::ImageBuffer::<image::Luma<u16>, _>::from_raw(
                    image.width as u32,
                    image.height as u32,
                    millimetres,
                )
                .ok_or("an image of no pixels")?;
                ctx.output.write(&self.instance, &file_name(prefix, "distance", ctx.frame, "png"), &png(buffer)?)?;
            }
            if self.preview {
                let colours: Vec<u8> = image.plane(0).iter().flat_map(|&d| colour(d, self.max_distance)).collect();
                let buffer = image::RgbImage::from_raw(image.width as u32, image.height as u32, colours)
                    .ok_or("an image of no pixels")?;
                ctx.output.write(&self.instance, &file_name(prefix, "preview", ctx.frame, "png"), &png(buffer)?)?;
            }
        }
        Ok(Vec::new())
    }
}

/// `ToF.RawWriter`: raw frames as the channels `RawFrameFile` reads, `raw_a_0000.npy` and
/// `raw_b_0000.npy`, float32 of shape (4, H, W).
pub struct RawWriter {
    instance: String,
    several: bool,
    pending: Pending,
}

impl RawWriter {
    pub fn new(params: &Params) -> RawWriter {
        RawWriter {
            instance: params.stage.instance.clone(),
            several: params.providers > 1,
            pending: PerFrame::default(),
        }
    }
}

impl Component for RawWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        read_each(ctx, inputs, ("RawIn", "raw"), &mut self.pending, |data| match data {
            Data::Raw(frame) => Some(&frame.raw),
            _ => None,
        });
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, _, later) in self.pending.take(reads) {
            let raw = reads.get(later);
            for (channel, first) in [("raw_a", 0), ("raw_b", 1)] {
                let planes = super::channel(raw, first);
                let bytes = arrays::encode(&[4, raw.height, raw.width], &planes, arrays::Dtype::F32);
                let name = file_name(self.several.then_some(producer.as_str()), channel, ctx.frame, "npy");
                ctx.output.write(&self.instance, &name, &bytes)?;
            }
        }
        Ok(Vec::new())
    }
}

/// `ToF.MaskWriter`: each mask as 8-bit grey PNG, 255 where set.
pub struct MaskWriter {
    instance: String,
    several: bool,
    pending: Pending,
}

impl MaskWriter {
    pub fn new(params: &Params) -> MaskWriter {
        MaskWriter {
            instance: params.stage.instance.clone(),
            several: params.providers > 1,
            pending: PerFrame::default(),
        }
    }
}

impl Component for MaskWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        read_each(ctx, inputs, ("MaskIn", "mask"), &mut self.pending, |data| match data {
            Data::Mask(mask) => Some(mask),
            _ => None,
        });
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, what, later) in self.pending.take(reads) {
            let image = reads.get(later);
            let grey: Vec<u8> = image.plane(0).iter().map(|&m| if m > 0.0 { 255 } else { 0 }).collect();
            let buffer = image::GrayImage::from_raw(image.width as u32, image.height as u32, grey)
                .ok_or("an image of no pixels")?;
            let name = file_name(self.several.then_some(producer.as_str()), what, ctx.frame, "png");
            ctx.output.write(&self.instance, &name, &png(buffer)?)?;
        }
        Ok(Vec::new())
    }
}

/// `ToF.FlowWriter`: each flow field as `.npy` (2, H, W) and as a colour-wheel PNG.
pub struct FlowWriter {
    instance: String,
    several: bool,
    max_length: f32,
    pending: Pending,
}

impl FlowWriter {
    pub fn new(params: &Params) -> FlowWriter {
        FlowWriter {
            instance: params.stage.instance.clone(),
            several: params.providers > 1,
            max_length: params.f32("maxLength"),
            pending: PerFrame::default(),
        }
    }
}

impl Component for FlowWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        read_each(ctx, inputs, ("FlowIn", "flow"), &mut self.pending, |data| match data {
            Data::Flow(flow) => Some(flow),
            _ => None,
        });
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, what, later) in self.pending.take(reads) {
            let flow = reads.get(later);
            let prefix = self.several.then_some(producer.as_str());
            let npy =
                arrays::encode(&[2, flow.height, flow.width], &flow.data[..2 * flow.pixels()], arrays::Dtype::F32);
            ctx.output.write(&self.instance, &file_name(prefix, what, ctx.frame, "npy"), &npy)?;
            let (dx, dy) = (flow.plane(0), flow.plane(1));
            let rgb: Vec<u8> = dx.iter().zip(dy).flat_map(|(&u, &v)| wheel(u, v, self.max_length)).collect();
            let buffer =
                image::RgbImage::from_raw(flow.width as u32, flow.height as u32, rgb).ok_or("an image of no pixels")?;
            ctx.output.write(&self.instance, &file_name(prefix, what, ctx.frame, "png"), &png(buffer)?)?;
        }
        Ok(Vec::new())
    }
}

/// The colour of flow `(u, v)` on the wheel: the hue its direction (0° red, to the right;
/// image y grows downwards), the brightness its length up to `max_length`, full saturation.
fn wheel(u: f32, v: f32, max_length: f32) -> [u8; 3] {
    let value = ((u * u + v * v).sqrt() / max_length).min(1.0);
    let hue = v.atan2(u).to_degrees().rem_euclid(360.0) / 60.0;
    let sector = hue.floor();
    let f = hue - sector;
    let (p, q, t) = (0.0, value * (1.0 - f), value * f);
    let (r, g, b) = match sector as u32 % 6 {
        0 => (value, t, p),
        1 => (q, value, p),
        2 => (p, value, t),
        3 => (p, q, value),
        4 => (t, p, value),
        _ => (value, p, q),
    };
    [r, g, b].map(|c| (c * 255.0).round() as u8)
}

/// Asks for the read of the image `pick` finds in each item on `port`, kept in `pending` as
/// `what` (the files' name) with its producer.
fn read_each(
    ctx: &mut Ctx,
    inputs: &Inputs,
    (port, what): (&str, &'static str),
    pending: &mut Pending,
    pick: fn(&Data) -> Option<&crate::pipeline::data::Tensor>,
) {
    for item in inputs.port(port) {
        if let Some(image) = pick(&item.data) {
            let read = ctx.device.read_later(image);
            pending.now(ctx.device).push((item.producer.clone(), what, read));
        }
    }
}

/// An image encoded as PNG.
pub(super) fn png<P: image::PixelWithColorType, C: std::ops::Deref<Target = [P::Subpixel]>>(
    buffer: image::ImageBuffer<P, C>,
) -> Result<Vec<u8>, String>
where
    [P::Subpixel]: image::EncodableLayout,
{
    let mut bytes = Cursor::new(Vec::new());
    buffer.write_to(&mut bytes, image::ImageFormat::Png).map_err(|e| format!("PNG encoding: {e}"))?;
    Ok(bytes.into_inner())
}

/// The preview's colour of a distance: near red through yellow, green and cyan to far blue
/// over [0, `max`]; invalid (0, NaN) black, beyond `max` dark blue.
fn colour(distance: f32, max: f32) -> [u8; 3] {
    if distance.is_nan() || distance <= 0.0 {
        return [0, 0, 0];
    }
    let t = (distance / max).min(1.0);
    let hue = 240.0 * t;
    let x = 1.0 - ((hue / 60.0) % 2.0 - 1.0).abs();
    let (r, g, b) = match (hue / 60.0) as u32 {
        0 => (1.0, x, 0.0),
        1 => (x, 1.0, 0.0),
        2 => (0.0, 1.0, x),
        _ => (0.0, x, 1.0),
    };
    let v = if distance > max { 0.5 } else { 1.0 };
    [(r * v * 255.0) as u8, (g * v * 255.0) as u8, (b * v * 255.0) as u8]
}

/// `ToF.PlyWriter` and `ToF.PcdWriter`: the clouds it receives as binary PLY or PCD with
/// normals, every frame's (`cloud_0003.ply`) or the last (`cloud.ply`, when the run ends); fed
/// by several producers, a file for each.
pub struct CloudWriter {
    instance: String,
    format: CloudFormat,
    every_frame: bool,
    several: bool,
    /// The last cloud of each producer.
    last: Vec<(String, Points)>,
    /// This frame's clouds, each with its producer, until the frame's reads are back.
    pending: PerFrame<Vec<(String, super::cloud::CloudRead)>>,
}

/// The files a [`CloudWriter`] writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CloudFormat {
    Ply,
    Pcd,
}

impl CloudWriter {
    pub fn new(params: &Params, format: CloudFormat) -> CloudWriter {
        CloudWriter {
            instance: params.stage.instance.clone(),
            format,
            every_frame: params.flag("everyFrame"),
            several: params.providers > 1,
            last: Vec::new(),
            pending: PerFrame::default(),
        }
    }

    fn name(&self, producer: &str, frame: Option<usize>) -> String {
        let extension = match self.format {
            CloudFormat::Ply => "ply",
            CloudFormat::Pcd => "pcd",
        };
        match frame {
            Some(frame) => file_name(self.several.then_some(producer), "cloud", frame, extension),
            None if self.several => format!("{producer}_cloud.{extension}"),
            None => format!("cloud.{extension}"),
        }
    }

    fn encode(&self, (points, normals): &Points) -> Result<Vec<u8>, String> {
        match self.format {
            CloudFormat::Pcd => Ok(gudsl_formats::pcd::encode(points, normals)),
            CloudFormat::Ply => {
                let mut bytes = Vec::new();
                gudsl_formats::ply::write(&mut bytes, points, normals, "gudsl ToF point cloud")
                    .map_err(|e| e.to_string())?;
                Ok(bytes)
            }
        }
    }
}

impl Component for CloudWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for item in inputs.port("CloudIn") {
            let Data::Cloud(cloud) = &item.data else { continue };
            let read = super::cloud::CloudRead::ask(ctx, cloud);
            self.pending.now(ctx.device).push((item.producer.clone(), read));
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, cloud) in self.pending.take(reads) {
            let points = cloud.take(reads);
            if self.every_frame {
                let bytes = self.encode(&points)?;
                ctx.output.write(&self.instance, &self.name(&producer, Some(ctx.frame)), &bytes)?;
            }
            self.last.retain(|(given, _)| *given != producer);
            self.last.push((producer, points));
        }
        Ok(Vec::new())
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        for (producer, points) in &self.last {
            output.write(&self.instance, &self.name(producer, None), &self.encode(points)?)?;
        }
        Ok(())
    }
}
