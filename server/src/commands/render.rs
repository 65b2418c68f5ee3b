//! `gudsl render PATH… [--diagram NAME] [--format svg|png|layout-json] [--with-report
//! report.json] [--aspect W:H | --page PAPER] [--remember] [-o DIR]`: draws the diagrams of the given files
//! (resolved together as one workspace) into one file per diagram, named after the diagram's
//! fully qualified name, fitted to a landscape screen (or the aspect ratio or paper given), with
//! the nodes pinned in each file's layout sidecar (`<file>.gudsl.layout`) where they were put
//! and the order of its rows kept (`--remember` writes them there);
//! the pipeline a run's `report.json` is of with its times and flows on it
//! (`gudsl_host::pipeline::annotate`). Output is byte-identical for identical input.
//! Exit code: 0 drawn, 1 nothing to draw or a file has syntax errors (what parsed is still
//! drawn), 2 a path or the report could not be read or an output (or, with `--remember`, a
//! sidecar) not written.

use gudsl_host::{output::OutputDir, pipeline::annotate};
use std::{path::PathBuf, process::ExitCode};

use clap::{Args, ValueEnum};

use gudsl_render::{layout::Page, pins::LayoutFile, scene::Hints};

use crate::{layout_file, workspace};

#[derive(Args)]
pub struct RenderArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Only the diagram with this name (simple or fully qualified).
    #[arg(long)]
    diagram: Option<String>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Svg)]
    format: Format,
    /// A pipeline run's `report.json`: its diagram is drawn with each instance's time per frame
    /// and share, the slowest marked, and what each binding carried.
    #[arg(long = "with-report", value_name = "REPORT")]
    with_report: Option<PathBuf>,
    /// The width-to-height ratio the drawing aims at where it does not fit a screen, as `W:H`
    /// (default 16:10, a landscape screen).
    #[arg(long, value_name = "W:H", value_parser = aspect_page, conflicts_with = "page")]
    aspect: Option<Page>,
    /// The paper the drawing is meant for: `A4`, `A3` or `Letter`, upright, or on its side as
    /// `A4-landscape`; a drawing that does not fit is reshaped towards the paper's shape.
    #[arg(long, value_name = "PAPER", value_parser = paper_page)]
    page: Option<Page>,
    /// Output folder (created if missing).
    #[arg(short = 'o', long = "output", default_value = ".")]
    output: PathBuf,
    /// Also write each drawn diagram's rows (the order of its boxes, rank by rank) into its
    /// file's layout sidecar, as the language server does when the file is saved: the next
    /// fresh layout of the diagram, here or in an editor, keeps that order where it can.
    #[arg(long)]
    remember: bool,
}

fn aspect_page(text: &str) -> Result<Page, String> {
    let (width, height) = text.split_once(':').ok_or("an aspect ratio is written W:H, as 16:10")?;
    let number = |n: &str| n.trim().parse::<f64>().map_err(|_| format!("`{n}` is no number"));
    Page::with_aspect(number(width)?, number(height)?).ok_or_else(|| format!("{text} is no aspect ratio"))
}

fn paper_page(text: &str) -> Result<Page, String> {
    Page::paper(text).ok_or_else(|| format!("no paper `{text}`: A4, A3 or Letter, upright or as A4-landscape"))
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    Svg,
    Png,
    /// The computed geometry, as `research/layout_metrics.py` scores it.
    LayoutJson,
}

pub fn run(args: &RenderArgs) -> ExitCode {
    let loaded = workspace::load(&args.paths);
    for error in &loaded.errors {
        eprintln!("gudsl render: {error}");
    }
    // Written as `gudsl run` writes: never through a link in the folder (`docs/security.md`).
    let mut output = match OutputDir::named(&args.output) {
        Ok(output) => output,
        Err(error) => {
            eprintln!("gudsl render: not writing into the output folder: {error}");
            return ExitCode::from(2);
        }
    };
    let report = match args.with_report.as_deref().map(read_report).transpose() {
        Ok(report) => report,
        Err(error) => {
            eprintln!("gudsl render: {error}");
            return ExitCode::from(2);
        }
    };
    let mut reported = false;
    let (host, files) = workspace::analysis_host(&loaded.documents);
    let analysis = host.analysis();
    // Diagrams of a file with syntax errors are drawn from what parsed, and said so.
    let mut broken = false;
    for (document, &file) in loaded.documents.iter().zip(&files) {
        let Ok(parse) = analysis.parse(file) else { return cancelled() };
        if !parse.errors().is_empty() {
            eprintln!(
                "gudsl render: {}: {} syntax error(s); its diagrams are drawn from what parsed (`gudsl check` lists them)",
                document.path.display(),
                parse.errors().len()
            );
            broken = true;
        }
    }
    let mut written = 0;
    let mut unremembered = false;
    for (document, &file) in loaded.documents.iter().zip(&files) {
        let Ok(graphs) = analysis.graphs(file) else { return cancelled() };
        let sidecar = layout_file::path_for(&document.path);
        let layout = read_sidecar(&sidecar);
        let mut drawn_rows = Vec::new();
        for graph in graphs {
            if args.diagram.as_deref().is_some_and(|wanted| !gudsl_host::named::names_diagram(wanted, &graph.id)) {
                continue;
            }
            let page = args.page.or(args.aspect).unwrap_or_default();
            let hints = Hints { pins: layout.pins(&graph.id), previous: None, page, rows: layout.rows(&graph.id) };
            let annotated = report.as_ref().filter(|r| r["diagram"] == graph.id.as_str()).map(|r| {
                let mut annotated = graph.clone();
                annotate(&mut annotated, r).map(|()| annotated)
            });
            let scene = match annotated.transpose() {
                Ok(Some(annotated)) => {
                    reported = true;
                    gudsl_render::scene::build(&annotated, hints)
                }
                Ok(None) => gudsl_render::scene::build(graph, hints),
                Err(error) => {
                    eprintln!("gudsl render: {}: {error}", graph.id);
                    return ExitCode::from(2);
                }
            };
            let (extension, bytes) = match args.format {
                Format::Svg => ("svg", gudsl_render::svg::write(&scene).into_bytes()),
                Format::LayoutJson => ("json", gudsl_render::json::write(&scene).into_bytes()),
                Format::Png => {
                    match gudsl_render::png::to_png(&gudsl_render::svg::write(&scene), gudsl_render::png::EXPORT_SCALE)
                    {
                        Ok(png) => ("png", png),
                        Err(error) => {
                            eprintln!("gudsl render: {}: {error}", graph.id);
                            return ExitCode::from(1);
                        }
                    }
                }
            };
            if let Err(error) = output.write_top(&format!("{}.{extension}", graph.id), &bytes) {
                eprintln!("gudsl render: {error}");
                return ExitCode::from(2);
            }
            written += 1;
            drawn_rows.push((graph.id.clone(), scene.rows));
        }
        if args.remember {
            // (A sidecar that is no layout is refused again there, and left as it is.)
            if let Err(error) = layout_file::remember(&sidecar, drawn_rows) {
                eprintln!("gudsl render: not remembering the rows: {error}");
                unremembered = true;
            }
        }
    }
    if written == 0 {
        match &args.diagram {
            Some(name) => eprintln!("gudsl render: no diagram named `{name}`"),
            None => eprintln!("gudsl render: no diagrams found"),
        }
    } else {
        eprintln!("wrote {written} diagram(s) to {}", args.output.display());
    }
    if let (Some(report), false) = (&report, reported) {
        let diagram = report["diagram"].as_str().unwrap_or("?");
        eprintln!("gudsl render: the report is of `{diagram}`, which none of the diagrams drawn is");
        return ExitCode::from(2);
    }
    if !loaded.errors.is_empty() || unremembered {
        ExitCode::from(2)
    } else if written == 0 || broken {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// The layout sidecar at `path` (pins, rows): a file that is no layout is said and left alone
/// (its positions are not used).
fn read_sidecar(path: &std::path::Path) -> LayoutFile {
    layout_file::read(path).unwrap_or_else(|error| {
        eprintln!("gudsl render: {error}; its positions are not used");
        LayoutFile::default()
    })
}

/// The largest `report.json` read (a run's report is kilobytes).
const REPORT_LIMIT: u64 = 64 << 20;

/// A run's `report.json`, the file the user named.
fn read_report(path: &std::path::Path) -> Result<serde_json::Value, String> {
    let shown = path.display();
    let size = std::fs::metadata(path).map_err(|e| format!("cannot read the report {shown}: {e}"))?.len();
    if size > REPORT_LIMIT {
        return Err(format!("{shown} is {size} bytes: no run's report.json is that large"));
    }
    let text = std::fs::read_to_string(path).map_err(|e| format!("cannot read the report {shown}: {e}"))?;
    let report: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{shown} is not a report.json: {e}"))?;
    match report["diagram"].is_string() && report["stages"].is_array() {
        true => Ok(report),
        false => Err(format!("{shown} is not a pipeline run's report.json (no `diagram` and `stages`)")),
    }
}

fn cancelled() -> ExitCode {
    eprintln!("gudsl render: the analysis was cancelled");
    ExitCode::from(2)
}
