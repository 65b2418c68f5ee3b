//! Sinks: depth images to `.npy` (float32) and PNG (16-bit millimetres and a colour-mapped
//! preview), point clouds to PLY, and the accuracy against the simulator's truth per frame as CSV and a plot (SVG
//! and PNG). Each asks for its images at the end of the frame and writes them then, into a
//! folder of the output named after its instance; fed by several producers, it prefixes its
//! files with the producer's name.

use std::{fmt::Write as _, io::Cursor, sync::Arc};

use gudsl_formats::{arrays, ply::Points};
use gudsl_runtime::Image;

use super::{depth_images, Component, Ctx, Inputs, Need, Outputs, Params};
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
type Pending = Vec<(String, &'static str, Later)>;

/// `ToF.NpyWriter`.
pub struct NpyWriter {
    instance: String,
    planes: Vec<&'static str>,
    several: bool,
    pending: Pending,
}

impl NpyWriter {
    pub fn new(params: &Params) -> NpyWriter {
        let planes = ["distance", "amplitude", "intensity"].into_iter().filter(|p| params.flag(p)).collect();
        NpyWriter {
            instance: params.stage.instance.clone(),
            planes,
            several: params.providers > 1,
            pending: Vec::new(),
        }
    }
}

impl Component for NpyWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for (producer, depth) in depth_images(inputs) {
            for &what in &self.planes {
                let tensor = match what {
                    "distance" => &depth.distance,
                    "amplitude" => &depth.amplitude,
                    _ => &depth.intensity,
                };
                self.pending.push((producer.to_string(), what, ctx.device.read_later(tensor)));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, what, later) in std::mem::take(&mut self.pending) {
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
            pending: Vec::new(),
        }
    }
}

impl Component for PngWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        if self.distance || self.preview {
            for (producer, depth) in depth_images(inputs) {
                self.pending.push((producer.to_string(), "distance", ctx.device.read_later(&depth.distance)));
            }
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (producer, _, later) in std::mem::take(&mut self.pending) {
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

/// `ToF.AccuracyReport`.
pub struct AccuracyReport {
    instance: String,
    max_true: f32,
    pending: Vec<(String, Later, Arc<Image>, f32)>,
    rows: Vec<Row>,
}

/// One series' accuracy in one frame.
struct Row {
    frame: usize,
    series: String,
    pixels: usize,
    mean_cm: f64,
    sigma_cm: f64,
    integration_us: f32,
}

impl AccuracyReport {
    pub fn new(params: &Params) -> AccuracyReport {
        AccuracyReport {
            instance: params.stage.instance.clone(),
            max_true: params.f32("maxTrueDistance"),
            pending: Vec::new(),
            rows: Vec::new(),
        }
    }
}

impl Component for AccuracyReport {
    fn needs(&self) -> Option<Need> {
        Some(Need::Truth("only a simulated camera's frames have it"))
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for (producer, depth) in depth_images(inputs) {
            let Some(truth) = &depth.truth else {
                return Err(format!(
                    "the depth images from `{producer}` have no ground truth: only a simulated camera's do"
                ));
            };
            let read = ctx.device.read_later(&depth.distance);
            self.pending.push((producer.to_string(), read, truth.clone(), depth.integration_us));
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (series, later, truth, integration_us) in std::mem::take(&mut self.pending) {
            let (pixels, mean_cm, sigma_cm) = error_cm(reads.get(later), &truth, self.max_true);
            self.rows.push(Row { frame: ctx.frame, series, pixels, mean_cm, sigma_cm, integration_us });
        }
        Ok(Vec::new())
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        let mut csv = String::from("frame,series,pixels,mean_cm,sigma_cm,integration_us\n");
        for Row { frame, series, pixels, mean_cm, sigma_cm, integration_us } in &self.rows {
            let _ = writeln!(csv, "{frame},{series},{pixels},{mean_cm:.4},{sigma_cm:.4},{integration_us}");
        }
        output.write(&self.instance, "accuracy.csv", csv.as_bytes())?;
        let svg = plot(&self.rows);
        output.write(&self.instance, "accuracy.svg", svg.as_bytes())?;
        let png = gudsl_render::png::to_png(&svg, gudsl_render::png::EXPORT_SCALE)
            .map_err(|e| format!("the plot as PNG: {e}"))?;
        output.write(&self.instance, "accuracy.png", &png)?;
        Ok(())
    }
}

/// Pixels, mean and σ of |distance − truth| in cm over the pixels with a measurement whose
/// true distance is below `max_true`.
pub fn error_cm(distance: &Image, truth: &Image, max_true: f32) -> (usize, f64, f64) {
    let errors: Vec<f64> = distance
        .data
        .iter()
        .zip(&truth.data)
        .filter(|(d, t)| t.is_finite() && **t < max_true && **d > 0.0)
        .map(|(d, t)| ((d - t).abs() * 100.0) as f64)
        .collect();
    let n = errors.len().max(1) as f64;
    let mean = errors.iter().sum::<f64>() / n;
    let variance = errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n;
    (errors.len(), mean, variance.sqrt())
}

/// The mean error per frame of each series as a line plot with its σ as a band.
fn plot(rows: &[Row]) -> String {
    let (width, height, left, right, top, bottom) = (640.0, 360.0, 64.0, 160.0, 24.0, 48.0);
    let mut series: Vec<&str> = Vec::new();
    for row in rows {
        if !series.contains(&row.series.as_str()) {
            series.push(&row.series);
        }
    }
    let last = rows.iter().map(|r| r.frame).max().unwrap_or(0).max(1) as f64;
    let top_value = rows.iter().map(|r| r.mean_cm + r.sigma_cm).fold(0.0f64, f64::max).max(0.1) * 1.1;
    let x = |frame: usize| left + (width - left - right) * frame as f64 / last;
    let y = |value: f64| top + (height - top - bottom) * (1.0 - value / top_value);
    let colours = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b"];
    let mut svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" viewBox=\"0 0 {width} {height}\" \
         font-family=\"DejaVu Sans\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    );
    let _ = writeln!(
        svg,
        "<path d=\"M{left} {top} V{} H{}\" stroke=\"black\" fill=\"none\"/>",
        height - bottom,
        width - right
    );
    for k in 0..=4 {
        let value = top_value * k as f64 / 4.0;
        let _ =
            writeln!(svg, "<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{value:.2}</text>", left - 6.0, y(value) + 4.0);
    }
    let step = (last as usize).div_ceil(10).max(1);
    for frame in (0..=last as usize).step_by(step) {
        let _ = writeln!(
            svg,
            "<text x=\"{:.1}\" y=\"{}\" text-anchor=\"middle\">{frame}</text>",
            x(frame),
            height - bottom + 16.0
        );
    }
    let _ = writeln!(
        svg,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">frame</text>",
        (left + width - right) / 2.0,
        height - 12.0
    );
    let _ = writeln!(svg, "<text x=\"16\" y=\"{}\" transform=\"rotate(-90 16 {})\" text-anchor=\"middle\">mean |error| (cm), band ±σ</text>", height / 2.0, height / 2.0);
    for (s, name) in series.iter().enumerate() {
        let colour = colours[s % colours.len()];
        let points: Vec<&Row> = rows.iter().filter(|r| r.series == *name).collect();
        let upper: Vec<String> =
            points.iter().map(|r| format!("{:.1},{:.1}", x(r.frame), y(r.mean_cm + r.sigma_cm))).collect();
        let lower: Vec<String> = points
            .iter()
            .rev()
            .map(|r| format!("{:.1},{:.1}", x(r.frame), y((r.mean_cm - r.sigma_cm).max(0.0))))
            .collect();
        let _ = writeln!(
            svg,
            "<polygon points=\"{} {}\" fill=\"{colour}\" fill-opacity=\"0.15\"/>",
            upper.join(" "),
            lower.join(" ")
        );
        let line: Vec<String> = points.iter().map(|r| format!("{:.1},{:.1}", x(r.frame), y(r.mean_cm))).collect();
        let _ = writeln!(
            svg,
            "<polyline points=\"{}\" stroke=\"{colour}\" stroke-width=\"2\" fill=\"none\"/>",
            line.join(" ")
        );
        let ly = top + 16.0 * s as f64 + 8.0;
        let _ = writeln!(
            svg,
            "<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"3\" fill=\"{colour}\"/>",
            width - right + 12.0,
            ly - 4.0
        );
        let _ = writeln!(svg, "<text x=\"{}\" y=\"{ly}\">{}</text>", width - right + 30.0, escape(name));
    }
    svg.push_str("</svg>\n");
    svg
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;")
}

/// `ToF.PlyWriter`: the clouds it receives as binary PLY with normals, every frame's
/// (`cloud_0003.ply`) or the last (`cloud.ply`, when the run ends); fed by several producers,
/// a file for each.
pub struct PlyWriter {
    instance: String,
    every_frame: bool,
    several: bool,
    /// The last cloud of each producer.
    last: Vec<(String, Points)>,
}

impl PlyWriter {
    pub fn new(params: &Params) -> PlyWriter {
        PlyWriter {
            instance: params.stage.instance.clone(),
            every_frame: params.flag("everyFrame"),
            several: params.providers > 1,
            last: Vec::new(),
        }
    }

    fn name(&self, producer: &str, frame: Option<usize>) -> String {
        match frame {
            Some(frame) => file_name(self.several.then_some(producer), "cloud", frame, "ply"),
            None if self.several => format!("{producer}_cloud.ply"),
            None => "cloud.ply".to_string(),
        }
    }
}

impl Component for PlyWriter {
    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for item in inputs.port("CloudIn") {
            let Data::Cloud(cloud) = &item.data else { continue };
            let (points, normals) = super::cloud::host_points(ctx, cloud)?;
            if self.every_frame {
                let mut bytes = Vec::new();
                gudsl_formats::ply::write(&mut bytes, &points, &normals, "gudsl ToF point cloud")
                    .map_err(|e| e.to_string())?;
                ctx.output.write(&self.instance, &self.name(&item.producer, Some(ctx.frame)), &bytes)?;
            }
            self.last.retain(|(producer, _)| *producer != item.producer);
            self.last.push((item.producer.clone(), (points, normals)));
        }
        Ok(Vec::new())
    }

    fn finish_run(&mut self, output: &mut OutputDir) -> Result<(), String> {
        for (producer, (points, normals)) in &self.last {
            let mut bytes = Vec::new();
            gudsl_formats::ply::write(&mut bytes, points, normals, "gudsl ToF point cloud")
                .map_err(|e| e.to_string())?;
            output.write(&self.instance, &self.name(producer, None), &bytes)?;
        }
        Ok(())
    }
}
