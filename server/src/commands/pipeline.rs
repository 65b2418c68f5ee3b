//! `gudsl run FILE --diagram PIPELINE`: a component-instance diagram run as a ToF pipeline on
//! the first wgpu adapter (`--cpu`: the CPU reference), frame after frame with a progress bar on
//! a terminal (a line a frame otherwise), then a table of the stages — time per frame and share
//! of the total — and the files written, all under the output folder (default
//! `gudsl-out/<diagram>/`), with `report.json` beside them. A pipeline the plan finds problems
//! in (E0401–E0403) or whose files or components do not fit (E0404, E0405) is refused with its
//! diagnostics. Exit code: 0 done, 1 a problem of the model or a failed stage, 2 an input or
//! output that cannot be read or written, or no device.

use std::{
    io::IsTerminal,
    path::{Path, PathBuf},
    process::ExitCode,
    sync::atomic::AtomicBool,
    time::Duration,
};

use gudsl_host::pipeline::{
    self, ErrorKind, OutputDir, PipelineError, PipelineObserver, PipelineReport, Prepared, StageTime,
};
use gudsl_model::{
    analysis::{Analysis, FileId},
    hir::{pipeline::PipelinePlan, DefKind, Diagnostic, Severity},
    Cancellable,
};

use crate::report::{self, Finding};

/// What `run` was asked to do with a pipeline.
pub struct PipelineArgs<'a> {
    pub diagram: &'a str,
    pub frames: Option<usize>,
    pub cpu: bool,
    pub output: Option<&'a Path>,
}

pub fn run(analysis: &Analysis, files: &[FileId], mut checked: report::Report, args: &PipelineArgs) -> ExitCode {
    let plan = match analysis.pipeline_plan(args.diagram) {
        Ok(Some(plan)) => plan,
        Ok(None) => {
            eprintln!("gudsl run: no component-instance diagram `{}`", args.diagram);
            return ExitCode::from(1);
        }
        Err(_) => {
            eprintln!("gudsl run: the analysis was cancelled");
            return ExitCode::from(2);
        }
    };
    let Some(file) = files.iter().position(|f| *f == plan.file) else {
        eprintln!("gudsl run: `{}` is not in the files given", plan.diagram);
        return ExitCode::from(1);
    };
    if !plan.diagnostics.is_empty() {
        checked
            .findings
            .retain(|f| f.file == file && plan.diagnostics.iter().any(|d| d.range == f.range && d.code == f.code));
        eprintln!("gudsl run: `{}` cannot run", plan.diagram);
        return super::refuse(&checked, 1);
    }
    let Ok(prepared) = prepare(analysis, &plan) else {
        eprintln!("gudsl run: the analysis was cancelled");
        return ExitCode::from(2);
    };
    let mut prepared = match prepared {
        Ok(prepared) => prepared,
        Err(errors) => {
            let code = if errors.iter().any(|e| e.kind == ErrorKind::Input) { 2 } else { 1 };
            checked.findings.clear();
            add_findings(&mut checked, file, &errors);
            eprintln!("gudsl run: `{}` cannot run", plan.diagram);
            return super::refuse(&checked, code);
        }
    };
    let simple = plan.diagram.rsplit('.').next().unwrap_or(&plan.diagram).to_string();
    let root = args.output.map_or_else(|| PathBuf::from("gudsl-out").join(&simple), Path::to_path_buf);
    let mut output = match OutputDir::create(&root) {
        Ok(output) => output,
        Err(error) => {
            eprintln!("gudsl run: cannot create the output folder {}: {error}", root.display());
            return ExitCode::from(2);
        }
    };
    let gpu = device(args.cpu, |error| {
        eprintln!("gudsl run: no GPU adapter ({error}); running on the CPU reference (--cpu says so)")
    });
    let frames = args.frames.map_or(prepared.frames(), |n| n.min(prepared.frames()));
    let device = gpu.as_ref().map_or_else(|| "the CPU reference".to_string(), |g| g.describe());
    eprintln!("running {} ({frames} frames) on {device}", plan.diagram);
    let mut progress = Progress::new(frames);
    let report = prepared.run(gpu.as_ref(), &mut output, args.frames, &mut progress, &AtomicBool::new(false));
    progress.done();
    print_report(&report);
    if let Err(error) = write_report(&report, &mut output) {
        eprintln!("gudsl run: {error}");
        return ExitCode::from(2);
    }
    match &report.outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(if error.kind == ErrorKind::Output { 2 } else { 1 })
        }
    }
}

/// The GPU a pipeline runs on: the first adapter, its kernels timed where it has timestamp
/// queries; `None`, the CPU reference, with `cpu` or when there is no adapter (`no_adapter`
/// told why).
pub fn device(cpu: bool, no_adapter: impl FnOnce(String)) -> Option<gudsl_runtime::Gpu> {
    if cpu {
        return None;
    }
    gudsl_runtime::Gpu::with_timestamps().map_err(|error| no_adapter(error.to_string())).ok()
}

/// The plan's components made, with the kernels its workspace components' `process` runs and
/// its files resolved against the model's folder.
pub fn prepare(analysis: &Analysis, plan: &PipelinePlan) -> Cancellable<Result<Prepared, Vec<PipelineError>>> {
    let behaviors = analysis.with_semantics(|sema| pipeline::behaviors(sema, plan))?;
    Ok(pipeline::prepare(plan, &behaviors, &model_dir(analysis, plan.file)))
}

/// The folder a model file's relative paths resolve against.
pub fn model_dir(analysis: &Analysis, file: FileId) -> PathBuf {
    Path::new(analysis.file_path(file)).parent().unwrap_or(Path::new(".")).to_path_buf()
}

/// What keeps the pipelines declared in `file` from running (E0404, E0405; their files read
/// as far as their headers), for those whose plan has no problems of its own.
pub fn file_diagnostics(analysis: &Analysis, file: FileId) -> Cancellable<Vec<Diagnostic>> {
    let diagrams: Vec<String> = analysis.with_semantics(|sema| {
        sema.file_diagrams(file)
            .filter(|def| matches!(def.kind, DefKind::ComponentInstanceDiagram))
            .map(|def| def.fqn.clone())
            .collect()
    })?;
    let mut out = Vec::new();
    for fqn in diagrams {
        match analysis.pipeline_plan(&fqn)? {
            Some(plan) if plan.file == file && plan.diagnostics.is_empty() => {
                let behaviors = analysis.with_semantics(|sema| pipeline::behaviors(sema, &plan))?;
                out.extend(pipeline::check(&plan, &behaviors, &model_dir(analysis, file)))
            }
            _ => {}
        }
    }
    Ok(out)
}

/// The pipeline's problems as findings of the report `gudsl check` writes.
fn add_findings(report: &mut report::Report, file: usize, errors: &[PipelineError]) {
    for error in errors {
        let Some(range) = error.range else {
            eprintln!("error: {error}");
            continue;
        };
        report.findings.push(Finding {
            file,
            severity: Severity::Error,
            code: error.code(),
            message: error.message.clone(),
            range,
            related: Vec::new(),
        });
    }
    report.findings.sort_by_key(|f| (f.file, f.range.start()));
}

/// A progress bar on a terminal, a line a frame otherwise.
struct Progress {
    bar: Option<indicatif::ProgressBar>,
}

impl Progress {
    fn new(frames: usize) -> Progress {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(frames as u64);
            bar.set_style(
                indicatif::ProgressStyle::with_template("  frame {pos}/{len} {wide_bar} {elapsed} (eta {eta})")
                    .expect("a valid template"),
            );
            bar
        });
        Progress { bar }
    }

    fn done(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl PipelineObserver for Progress {
    fn frame(&mut self, index: usize, frames: usize) {
        match &self.bar {
            Some(bar) => bar.set_position(index as u64 + 1),
            None => eprintln!("  frame {}/{frames}", index + 1),
        }
    }
}

fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1000.0
}

/// One line: how the run ended, in how long, on which device.
pub fn summary(report: &PipelineReport) -> String {
    let per_frame = ms(report.total) / report.frames.max(1) as f64;
    let ended = match &report.outcome {
        Ok(()) => format!("ran {} ({} frames)", report.diagram, report.frames),
        Err(error) if error.kind == ErrorKind::Cancelled => format!("{}: {}", report.diagram, error.message),
        Err(_) => format!("{} stopped with an error", report.diagram),
    };
    format!("{ended} in {:.1} ms ({per_frame:.2} ms per frame) on {}", ms(report.total), report.device)
}

/// The stages' table: per stage its time per frame on the host and on the GPU, and its share
/// of the total; a stage on a thread of its own (`async`) is marked so.
pub fn table(report: &PipelineReport) -> String {
    let per_frame = |d: Duration| ms(d) / report.frames.max(1) as f64;
    let total: Duration = report.stages.iter().map(|s| s.host + s.device).sum();
    let class = |s: &StageTime| if s.apart { format!("{} (async)", s.class) } else { s.class.clone() };
    let width = report.stages.iter().map(|s| s.instance.len()).max().unwrap_or(5).max(5);
    let class_width = report.stages.iter().map(|s| class(s).chars().count()).max().unwrap_or(9).max(9);
    let mut table = format!(
        "{:width$}  {:class_width$}  {:>12}  {:>12}  {:>6}\n",
        "stage", "component", "host ms/fr", "GPU ms/fr", "share"
    );
    for stage in &report.stages {
        let share = (stage.host + stage.device).as_secs_f64() / total.as_secs_f64().max(1e-12) * 100.0;
        table += &format!(
            "{:width$}  {:class_width$}  {:>12.3}  {:>12.3}  {:>5.1}%\n",
            stage.instance,
            class(stage),
            per_frame(stage.host),
            per_frame(stage.device),
            share
        );
    }
    table
}

/// How the run ended, the stages' table and the files written.
fn print_report(report: &PipelineReport) {
    println!("{}", summary(report));
    print!("{}", table(report));
    println!("wrote {} files under the output folder", report.outputs.len());
    for path in report.outputs.iter().filter(|p| !is_frame_file(p)) {
        println!("  {}", path.display());
    }
}

/// A file of one frame (`distance_0003.npy`): listed in `report.json`, not on the terminal.
fn is_frame_file(path: &Path) -> bool {
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or_default();
    stem.rsplit('_').next().is_some_and(|n| n.len() == 4 && n.chars().all(|c| c.is_ascii_digit()))
}

/// Writes `report.json` into the output folder; the report as written.
pub fn write_report(report: &PipelineReport, output: &mut OutputDir) -> Result<serde_json::Value, String> {
    let json = report_json(report);
    let text = serde_json::to_string_pretty(&json).expect("a report serialises") + "\n";
    output.write_top("report.json", text.as_bytes()).map_err(|error| error.to_string())?;
    Ok(json)
}

/// `report.json`: what the run did, for scripts; `plots` are the SVG plots among the outputs.
fn report_json(report: &PipelineReport) -> serde_json::Value {
    let paths = |keep: fn(&Path) -> bool| {
        report.outputs.iter().filter(|p| keep(p)).map(|p| p.display().to_string()).collect::<Vec<_>>()
    };
    serde_json::json!({
        "diagram": report.diagram,
        "device": report.device,
        "frames": report.frames,
        "total_ms": ms(report.total),
        "error": report.outcome.as_ref().err().map(|e| e.to_string()),
        "stages": report.stages.iter().map(|s| serde_json::json!({
            "instance": s.instance, "component": s.class, "items": s.items,
            "host_ms": ms(s.host), "device_ms": ms(s.device), "async": s.apart,
        })).collect::<Vec<_>>(),
        "outputs": paths(|_| true),
        "plots": paths(|p| p.extension().is_some_and(|e| e == "svg")),
    })
}
