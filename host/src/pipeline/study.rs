//! A parameter study's or a batch's results, one row a run: its setting (the values swept, the
//! recording), what the stages measured (an accuracy report's errors), the time per frame and
//! how the run ended — as a table for the terminal, `study.csv` (or `summary.csv`) for scripts
//! and a plot, a panel a figure over the first column of the setting with a line for each
//! value of the others. Rows come from the runs themselves or from the `report.json` they
//! wrote (the summary of many recordings run apart).

use std::collections::BTreeSet;

use plotters::prelude::*;

use super::{Figure, OutputDir, PipelineReport};

/// One run of a study or a batch.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyRow {
    /// Its setting, by name (`recording`, `Motion.threshold`) and value.
    pub setting: Vec<(String, String)>,
    /// The folder its outputs went to, beneath the study's.
    pub folder: String,
    pub figures: Vec<Figure>,
    pub ms_per_frame: f64,
    /// `ok`, `failed: <sinks>` or `error`.
    pub state: String,
    /// Each stage's host and GPU ms per frame.
    pub stages: Vec<(String, f64, f64)>,
}

impl StudyRow {
    /// The row of a run with `setting` into `folder`.
    pub fn of(setting: Vec<(String, String)>, folder: String, report: &PipelineReport) -> StudyRow {
        let per_frame = |d: std::time::Duration| d.as_secs_f64() * 1000.0 / report.frames.max(1) as f64;
        StudyRow {
            setting,
            folder,
            figures: report.figures.clone(),
            ms_per_frame: per_frame(report.total),
            state: state(
                report.outcome.is_err(),
                &report.failed_stages().filter_map(|e| e.stage.as_deref()).collect::<Vec<_>>(),
            ),
            stages: report
                .stages
                .iter()
                .map(|s| (s.instance.clone(), per_frame(s.host), per_frame(s.device)))
                .collect(),
        }
    }

    /// The row of the `report.json` in `folder`; `None` for one that is no run's report.
    pub fn from_report(folder: &str, json: &serde_json::Value) -> Option<StudyRow> {
        let text = |v: &serde_json::Value| v.as_str().map(str::to_string);
        let setting =
            json["setting"].as_array()?.iter().map(|p| Some((text(&p[0])?, text(&p[1])?))).collect::<Option<_>>()?;
        let figures = json["figures"]
            .as_array()?
            .iter()
            .map(|f| Some(Figure { stage: text(&f["stage"])?, name: text(&f["name"])?, value: f["value"].as_f64()? }));
        let stages = json["stages"].as_array()?;
        let failed: Vec<String> =
            stages.iter().filter(|s| s["state"] == "failed").filter_map(|s| text(&s["instance"])).collect();
        let failed: Vec<&str> = failed.iter().map(String::as_str).collect();
        let state = state(!json["error"].is_null(), &failed);
        let stages = stages.iter().map(|s| {
            Some((text(&s["instance"])?, s["host_ms_per_frame"].as_f64()?, s["device_ms_per_frame"].as_f64()?))
        });
        Some(StudyRow {
            setting,
            folder: folder.to_string(),
            figures: figures.collect::<Option<_>>()?,
            ms_per_frame: json["ms_per_frame"].as_f64()?,
            state,
            stages: stages.collect::<Option<_>>()?,
        })
    }
}

/// The rows of every run's `report.json` beneath `output`, `depth` folders down, in the order
/// of their folders; the folders whose report is unreadable or no run's are named apart.
pub fn rows_beneath(output: &OutputDir, depth: usize) -> Result<(Vec<StudyRow>, Vec<String>), String> {
    let (mut rows, mut unread) = (Vec::new(), Vec::new());
    for (folder, bytes) in output.reports(depth)? {
        let json: Option<serde_json::Value> = serde_json::from_slice(&bytes).ok();
        match json.as_ref().and_then(|json| StudyRow::from_report(&folder, json)) {
            Some(row) => rows.push(row),
            None => unread.push(folder),
        }
    }
    Ok((rows, unread))
}

/// How a run ended: `ok`, `failed: <sinks>` or `error`.
/// Decided once for a run and for the `report.json` it wrote: whether it stopped with an
/// error, else the sinks that failed.
fn state(stopped: bool, failed: &[&str]) -> String {
    match (stopped, failed.is_empty()) {
        (true, _) => "error".to_string(),
        (false, true) => "ok".to_string(),
        (false, false) => format!("failed: {}", failed.join(" ")),
    }
}

/// A column of figures: the stage and the figure's name.
type Column = (String, String);

/// Every figure any run measured, in the order first met.
fn columns(runs: &[StudyRow]) -> Vec<Column> {
    let mut columns: Vec<Column> = Vec::new();
    for figure in runs.iter().flat_map(|r| &r.figures) {
        let column = (figure.stage.clone(), figure.name.clone());
        if !columns.contains(&column) {
            columns.push(column);
        }
    }
    columns
}

fn value(run: &StudyRow, (stage, name): &Column) -> Option<f64> {
    run.figures.iter().find(|f| &f.stage == stage && &f.name == name).map(|f| f.value)
}

/// The setting's names, from the first run's.
fn swept(runs: &[StudyRow]) -> Vec<String> {
    runs.first().map(|r| r.setting.iter().map(|(name, _)| name.clone()).collect()).unwrap_or_default()
}

/// The study as rows of text: a header, then one row a setting.
fn rows(runs: &[StudyRow]) -> (Vec<String>, Vec<Vec<String>>) {
    let columns = columns(runs);
    let mut header = swept(runs);
    header.extend(columns.iter().map(|(stage, name)| format!("{stage} {name}")));
    header.extend(["ms/frame".to_string(), "state".to_string()]);
    let body = runs
        .iter()
        .map(|run| {
            let mut row: Vec<String> = run.setting.iter().map(|(_, v)| v.clone()).collect();
            row.extend(columns.iter().map(|c| value(run, c).map_or_else(|| "-".to_string(), |v| format!("{v:.4}"))));
            row.extend([format!("{:.3}", run.ms_per_frame), run.state.clone()]);
            row
        })
        .collect();
    (header, body)
}

/// The table printed after a study: columns as wide as their widest cell.
pub fn study_table(runs: &[StudyRow]) -> String {
    let (header, body) = rows(runs);
    let widths: Vec<usize> = (0..header.len())
        .map(|k| body.iter().map(|row| row[k].chars().count()).chain([header[k].chars().count()]).max().unwrap_or(0))
        .collect();
    let line = |cells: &[String]| {
        let padded: Vec<String> = cells.iter().zip(&widths).map(|(cell, width)| format!("{cell:>width$}")).collect();
        padded.join("  ").trim_end().to_string() + "\n"
    };
    std::iter::once(&header).chain(&body).map(|row| line(row)).collect()
}

/// The CSV of the runs: the table's columns, the output folder of each run and each stage's
/// host and GPU time per frame, numbers unrounded.
pub fn study_csv(runs: &[StudyRow]) -> Result<String, String> {
    let columns = columns(runs);
    let stages: Vec<&str> = runs.first().map(|r| r.stages.iter().map(|s| s.0.as_str()).collect()).unwrap_or_default();
    let mut header = swept(runs);
    header.extend(columns.iter().map(|(stage, name)| format!("{stage} {name}")));
    header.extend(["ms_per_frame".to_string(), "state".to_string(), "folder".to_string()]);
    for stage in &stages {
        header.extend([format!("{stage} host_ms_per_frame"), format!("{stage} gpu_ms_per_frame")]);
    }
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record(&header).map_err(|e| e.to_string())?;
    for run in runs {
        let mut row: Vec<String> = run.setting.iter().map(|(_, v)| v.clone()).collect();
        row.extend(columns.iter().map(|c| value(run, c).map_or_else(String::new, |v| v.to_string())));
        row.extend([run.ms_per_frame.to_string(), run.state.clone(), run.folder.clone()]);
        for stage in &stages {
            let time = run.stages.iter().find(|s| s.0 == *stage);
            row.extend([
                time.map_or_else(String::new, |t| t.1.to_string()),
                time.map_or_else(String::new, |t| t.2.to_string()),
            ]);
        }
        csv.write_record(&row).map_err(|e| e.to_string())?;
    }
    String::from_utf8(csv.into_inner().map_err(|e| e.to_string())?).map_err(|e| e.to_string())
}

/// Writes `<name>.csv`, `<name>.svg` and `<name>.png` (`study`, `summary`) at the top of the
/// output folder.
pub fn write_study(runs: &[StudyRow], name: &str, output: &mut OutputDir) -> Result<(), String> {
    output.write_top(&format!("{name}.csv"), study_csv(runs)?.as_bytes())?;
    let svg = study_plot(runs)?;
    output.write_top(&format!("{name}.svg"), svg.as_bytes())?;
    let png = gudsl_render::png::to_png(&svg, gudsl_render::png::EXPORT_SCALE)
        .map_err(|e| format!("the plot as PNG: {e}"))?;
    output.write_top(&format!("{name}.png"), &png)?;
    Ok(())
}

const PANEL: (u32, u32) = (480, 300);

/// One panel a figure (and one for the time per frame) over the first swept parameter: its
/// values on the axis in the order swept (numbers to scale), a line for each setting of the
/// other swept parameters.
pub fn study_plot(runs: &[StudyRow]) -> Result<String, String> {
    let mut panels: Vec<(String, Vec<Option<f64>>)> = columns(runs)
        .iter()
        .map(|c| (format!("{} {}", c.0, c.1), runs.iter().map(|r| value(r, c)).collect()))
        .collect();
    panels.push(("ms per frame".to_string(), runs.iter().map(|r| Some(r.ms_per_frame)).collect()));
    let across = panels.len().min(2) as u32;
    let down = panels.len().div_ceil(2) as u32;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (PANEL.0 * across, PANEL.1 * down)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let areas = root.split_evenly((down as usize, across as usize));
        for ((title, values), area) in panels.iter().zip(&areas) {
            panel(area, runs, title, values).map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// The x of each run (its first swept value: the number, or the value's place among those
/// swept) and the names of the places where the values are not all numbers.
fn positions(runs: &[StudyRow]) -> (Vec<f64>, Option<Vec<String>>) {
    let firsts: Vec<&str> = runs.iter().map(|r| r.setting.first().map_or("", |(_, v)| v.as_str())).collect();
    if let Some(numbers) = firsts.iter().map(|v| v.parse::<f64>().ok()).collect::<Option<Vec<f64>>>() {
        return (numbers, None);
    }
    let mut distinct: Vec<String> = Vec::new();
    for value in &firsts {
        if !distinct.iter().any(|d| d == value) {
            distinct.push(value.to_string());
        }
    }
    let x = firsts.iter().map(|v| distinct.iter().position(|d| d == v).unwrap_or(0) as f64).collect();
    (x, Some(distinct))
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

fn panel(
    area: &Area,
    runs: &[StudyRow],
    title: &str,
    values: &[Option<f64>],
) -> Result<(), Box<dyn std::error::Error>> {
    let (x, names) = positions(runs);
    let (x_min, x_max) = bounds(x.iter().copied());
    let (y_min, y_max) = bounds(values.iter().flatten().copied());
    // Errors and times start from 0: the axis shows how far from none they are.
    let y_min = if values.iter().flatten().all(|v| *v >= 0.0) { 0.0 } else { y_min };
    let x_name = swept(runs).first().cloned().unwrap_or_default();
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 15))
        .margin(12)
        .x_label_area_size(34)
        .y_label_area_size(52)
        .build_cartesian_2d(x_min..x_max, y_min..y_max)?;
    let label = |v: &f64| match &names {
        Some(names) if v.fract() == 0.0 => names.get(*v as usize).cloned().unwrap_or_default(),
        Some(_) => String::new(),
        None => format!("{v}"),
    };
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x_name).x_label_formatter(&label).light_line_style(WHITE);
    if let Some(names) = &names {
        mesh.x_labels(names.len());
    }
    mesh.draw()?;
    let lines: BTreeSet<Vec<&str>> = runs.iter().map(|r| rest_of(r)).collect();
    for (k, line) in lines.iter().enumerate() {
        let color = Palette99::pick(k).to_rgba();
        let points: Vec<(f64, f64)> = runs
            .iter()
            .zip(&x)
            .zip(values)
            .filter(|((run, _), _)| &rest_of(run) == line)
            .filter_map(|((_, x), y)| Some((*x, (*y)?)))
            .collect();
        let legend = legend_of(runs, line);
        let series = chart.draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))?;
        if !legend.is_empty() {
            series
                .label(legend)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
        }
        chart.draw_series(points.iter().map(|p| Circle::new(*p, 3, color.filled())))?;
    }
    if lines.len() > 1 {
        chart.configure_series_labels().border_style(BLACK.mix(0.3)).background_style(WHITE.mix(0.8)).draw()?;
    }
    Ok(())
}

/// The values of a run's setting but the first: which line it is on.
fn rest_of(run: &StudyRow) -> Vec<&str> {
    run.setting.iter().skip(1).map(|(_, v)| v.as_str()).collect()
}

fn legend_of(runs: &[StudyRow], line: &[&str]) -> String {
    let names = swept(runs);
    names.iter().skip(1).zip(line).map(|(name, value)| format!("{name}={value}")).collect::<Vec<_>>().join(" ")
}

/// A range around the values, never empty.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (min, max) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if !min.is_finite() {
        return (0.0, 1.0);
    }
    let pad = ((max - min) * 0.08).max(max.abs() * 0.05).max(1e-6);
    (min - pad, max + pad)
}
