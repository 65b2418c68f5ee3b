//! `ToF.AccuracyReport`: the error of depth images against the true distances per frame —
//! the simulator's, or a ground-truth file's for recorded data — as CSV and a plot (SVG and
//! PNG).

use std::{fmt::Write as _, sync::Arc};

use gudsl_runtime::Image;
use plotters::prelude::*;

use super::{depth_images, of_size, Component, Ctx, Inputs, Need, Outputs, Params, PerFrame, SizesByPort};
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
    pending: PerFrame<Vec<Measured>>,
    rows: Vec<Row>,
}

/// An item to measure once its frame's reads are back: its series, its distances' read, the
/// true distances, its integration time (µs).
type Measured = (String, Later, Arc<Image>, f32);

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
            pending: PerFrame::default(),
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
            self.pending.now(ctx.device).push((producer.to_string(), read, truth, depth.integration_us));
        }
        Ok(Vec::new())
    }

    fn finish_frame(&mut self, ctx: &mut Ctx, reads: &Reads) -> Result<Outputs, String> {
        for (series, later, truth, integration_us) in self.pending.take(reads) {
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
        let svg = plot(&self.rows)?;
        output.write(&self.instance, "accuracy.svg", svg.as_bytes())?;
        let png = gudsl_render::png::to_png(&svg, gudsl_render::png::EXPORT_SCALE)
            .map_err(|e| format!("the plot as PNG: {e}"))?;
        output.write(&self.instance, "accuracy.png", &png)?;
        Ok(())
    }

    /// Per series, over every pixel of every frame: the mean error and the mean of the frames'
    /// σ, in cm; none for a series without a pixel measured.
    fn figures(&self) -> Vec<(String, f64)> {
        let mut figures = Vec::new();
        for name in series_of(&self.rows) {
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

/// The series of the rows, in the order they first appear.
fn series_of(rows: &[Row]) -> Vec<&str> {
    let mut series: Vec<&str> = Vec::new();
    for row in rows {
        if !series.contains(&row.series.as_str()) {
            series.push(&row.series);
        }
    }
    series
}

/// The mean error per frame of each series as a line plot with its σ as a band (plotters:
/// ticks at round values, the axes named with their units), one colour a series.
fn plot(rows: &[Row]) -> Result<String, String> {
    let mut svg = String::new();
    draw(&mut svg, rows).map_err(|e| format!("the accuracy plot: {e}"))?;
    Ok(svg)
}

fn draw(svg: &mut String, rows: &[Row]) -> Result<(), Box<dyn std::error::Error>> {
    let series = series_of(rows);
    let last = rows.iter().map(|r| r.frame).max().unwrap_or(0).max(1) as f64;
    let top = rows.iter().map(|r| r.mean_cm + r.sigma_cm).fold(0.0f64, f64::max).max(0.1) * 1.1;
    let root = SVGBackend::with_string(svg, (640, 360)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .margin(14)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(0.0..last, 0.0..top)?;
    chart
        .configure_mesh()
        .x_desc("frame")
        .y_desc("mean |error| (cm), band ±σ")
        .x_labels((last as usize + 1).min(11))
        .x_label_formatter(&|x| if x.fract() == 0.0 { format!("{x}") } else { String::new() })
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(WHITE.mix(0.0))
        .draw()?;
    for (s, name) in series.iter().enumerate() {
        let colour = Palette99::pick(s).to_rgba();
        let points: Vec<&Row> = rows.iter().filter(|r| r.series == *name).collect();
        let band: Vec<(f64, f64)> = points
            .iter()
            .map(|r| (r.frame as f64, r.mean_cm + r.sigma_cm))
            .chain(points.iter().rev().map(|r| (r.frame as f64, (r.mean_cm - r.sigma_cm).max(0.0))))
            .collect();
        chart.draw_series(std::iter::once(Polygon::new(band, colour.mix(0.15).filled())))?;
        let line = points.iter().map(|r| (r.frame as f64, r.mean_cm));
        chart
            .draw_series(LineSeries::new(line, colour.stroke_width(2)))?
            .label(name.to_string())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
    }
    chart.configure_series_labels().border_style(BLACK.mix(0.3)).background_style(WHITE.mix(0.8)).draw()?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The texts of the plot that are numbers, in the order drawn.
    fn numbers(svg: &str) -> Vec<f64> {
        svg.split("<text").filter_map(|t| t.split('>').nth(1)?.split('<').next()?.trim().parse().ok()).collect()
    }

    /// Ticks at round values with their units named, not the range cut in fourths (0, 8.38,
    /// 16.76, … as the hand-drawn plot had them).
    #[test]
    fn the_plot_has_round_ticks_and_names_its_units() {
        let row = |frame, series: &str, mean_cm| Row {
            frame,
            series: series.to_string(),
            pixels: 10,
            mean_cm,
            sigma_cm: 4.0,
            integration_us: 1000.0,
        };
        let rows = [row(0, "Uncompensated", 26.46), row(1, "Uncompensated", 24.0), row(0, "Compensated", 3.0)];
        let svg = plot(&rows).unwrap();
        assert!(svg.contains("mean |error| (cm), band ±σ") && svg.contains("\nframe\n"), "{svg}");
        assert!(svg.contains("Uncompensated") && svg.contains("Compensated"));
        let values: Vec<f64> = numbers(&svg).into_iter().filter(|v| v.fract() != 0.0 || *v > 1.0).collect();
        assert!(values.len() >= 4, "{values:?}");
        let steps: Vec<f64> = values.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
        let step = steps[0];
        assert!(steps.iter().all(|s| (s - step).abs() < 1e-9), "evenly spaced: {values:?}");
        let mantissa = step / 10f64.powf(step.log10().floor());
        assert!([1.0, 2.0, 2.5, 5.0].iter().any(|m| (m - mantissa).abs() < 1e-9), "a round step: {step} ({values:?})");
        assert!(values.iter().all(|v| (v / step).fract().abs() < 1e-9), "ticks on the step: {values:?}");
    }
}
