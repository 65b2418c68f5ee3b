//! `ToF.AccuracyReport`: the error of depth images against the true distances per frame —
//! the simulator's, or a ground-truth file's for recorded data — as CSV and a plot (SVG and
//! PNG).

use std::{fmt::Write as _, sync::Arc};

use gudsl_runtime::Image;

use super::{depth_images, of_size, Component, Ctx, Inputs, Need, Outputs, Params, SizesByPort};
use crate::pipeline::{
    executor::{Later, Reads},
    files, ErrorKind, OutputDir, PipelineError,
};

/// `ToF.AccuracyReport`.
pub struct AccuracyReport {
    instance: String,
    max_true: f32,
    /// The ground-truth file (`groundTruth`), when given: its truth wins over the frames'.
    truth_file: Option<TruthFile>,
    pending: Vec<(String, Later, Arc<Image>, f32)>,
    rows: Vec<Row>,
}

/// A file of true distances and, once the run loaded it, its images.
struct TruthFile {
    file: files::DepthFile,
    scale: f32,
    images: Vec<Arc<Image>>,
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
    pub fn new(params: &Params) -> Result<AccuracyReport, Vec<PipelineError>> {
        let truth_file = match params.file("groundTruth") {
            Some(path) => Some(TruthFile {
                file: files::DepthFile::open(params.files, &path)
                    .map_err(|e| vec![params.error("groundTruth", ErrorKind::Input, e)])?,
                scale: params.f32("groundTruthScale"),
                images: Vec::new(),
            }),
            None => None,
        };
        Ok(AccuracyReport {
            instance: params.stage.instance.clone(),
            max_true: params.f32("maxTrueDistance"),
            truth_file,
            pending: Vec::new(),
            rows: Vec::new(),
        })
    }

    /// The true distances of `frame`: the file's (one image for every frame, or the frame's),
    /// else what came with the depth image.
    fn truth(&self, frame: usize, producer: &str, own: Option<&Arc<Image>>) -> Result<Arc<Image>, String> {
        let Some(TruthFile { images, file, .. }) = &self.truth_file else {
            return own
                .cloned()
                .ok_or_else(|| format!("the depth images from `{producer}` have no ground truth: give `groundTruth`"));
        };
        match &images[..] {
            [one] => Ok(one.clone()),
            all => all.get(frame).cloned().ok_or_else(|| {
                format!("{} holds {} ground-truth image(s); frame {frame} has none", file.path().display(), all.len())
            }),
        }
    }
}

impl Component for AccuracyReport {
    fn needs(&self) -> Option<Need> {
        self.truth_file
            .is_none()
            .then_some(Need::Truth("only a simulated camera's frames have it; for recorded data give `groundTruth`"))
    }

    fn too_short(&self, frames: usize) -> Option<(&'static str, String)> {
        let truth = self.truth_file.as_ref()?;
        let images = truth.file.extent.frames;
        (images > 1 && images < frames).then(|| {
            let path = truth.file.path().display();
            let why = format!(
                "{path} holds {images} ground-truth images, but the run has {frames} frames: give one image a frame (or one for all), or run fewer frames: the source's `frames` (on the command line `--set <source>.frames={images}`; `--frames` shortens a run of a model that checks)"
            );
            ("groundTruth", why)
        })
    }

    fn sizes_meet(&self, sizes: &SizesByPort) -> Result<(), (Option<&'static str>, String)> {
        let Some(truth) = &self.truth_file else { return Ok(()) };
        let own = (truth.file.extent.width, truth.file.extent.height);
        of_size(sizes, ("DepthIn", "depth images"), own, "groundTruth", "the ground truth", "they cannot meet")
    }

    fn load(&mut self) -> Result<(), String> {
        if let Some(truth) = &mut self.truth_file {
            let count = truth.file.extent.frames;
            let mut reading = truth.file.frames(count, truth.scale);
            truth.images = (0..count).map(|_| reading.next_frame().map(Arc::new)).collect::<Result<_, _>>()?;
        }
        Ok(())
    }

    fn process(&mut self, ctx: &mut Ctx, inputs: &Inputs) -> Result<Outputs, String> {
        for (producer, depth) in depth_images(inputs) {
            let truth = self.truth(ctx.frame, producer, depth.truth.as_ref())?;
            let read = ctx.device.read_later(&depth.distance);
            self.pending.push((producer.to_string(), read, truth, depth.integration_us));
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

    /// Per series, over every pixel of every frame: the mean error and the mean of the frames'
    /// σ, in cm; none for a series without a pixel measured.
    fn figures(&self) -> Vec<(String, f64)> {
        let mut series: Vec<&str> = Vec::new();
        for row in &self.rows {
            if !series.contains(&row.series.as_str()) {
                series.push(&row.series);
            }
        }
        let mut figures = Vec::new();
        for name in series {
            let rows: Vec<&Row> = self.rows.iter().filter(|r| r.series == name).collect();
            let pixels: usize = rows.iter().map(|r| r.pixels).sum();
            if pixels == 0 {
                continue; // no pixel was measured: no error to tell
            }
            let mean = rows.iter().map(|r| r.mean_cm * r.pixels as f64).sum::<f64>() / pixels.max(1) as f64;
            let sigma = rows.iter().map(|r| r.sigma_cm).sum::<f64>() / rows.len().max(1) as f64;
            figures.push((format!("{name} mean_cm"), mean));
            figures.push((format!("{name} sigma_cm"), sigma));
        }
        figures
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
