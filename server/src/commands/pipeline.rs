//! `gudsl run FILE --diagram PIPELINE`: a component-instance diagram run as a ToF pipeline on
//! the first wgpu adapter (`--cpu`: the CPU reference), frame after frame with a progress bar on
//! a terminal (a line a frame otherwise), then a table of the stages — time per frame and share
//! of the total — and the files written, all under the output folder (default
//! `gudsl-out/<diagram>/`), with `report.json` beside them. A pipeline the plan finds problems
//! in (E0401–E0403) or whose files or components do not fit (E0404, E0405) is refused with its
//! diagnostics. Exit code: 0 done, 1 a problem of the model or a failed stage, 2 an input or
//! output that cannot be read or written, or no device.

use std::{io::IsTerminal, path::Path, process::ExitCode, sync::atomic::AtomicBool};

use gudsl_host::{
    diagnostics::file_diagnostics,
    pipeline::{
        self, summary, table, write_report, ErrorKind, OutputDir, PipelineError, PipelineObserver, PipelineReport,
        Preparations, PreparedPipeline,
    },
};
use gudsl_model::{
    analysis::{Analysis, FileId},
    hir::{pipeline::PipelinePlan, DiagnosticCode, Severity},
    syntax::TextRange,
    AnalysisHost,
};
use gudsl_runtime::Gpu;

use super::{
    settings::{self, Assignment, Setting, Sweep},
    study,
};
use crate::report::{self, Finding};

/// What `run` was asked to do with a pipeline.
pub struct PipelineArgs<'a> {
    pub diagram: &'a str,
    pub frames: Option<usize>,
    pub cpu: bool,
    pub output: Option<&'a Path>,
    /// `--set`: values every setting runs with.
    pub sets: &'a [Assignment],
    /// `--sweep`: the parameter study's grid.
    pub sweeps: &'a [Sweep],
}

/// Runs the pipeline `args` names — once, or once a setting of a parameter study — taking
/// what the check of the model prepared from `preparations`. Every setting is checked and
/// prepared before the first runs.
pub fn run(
    host: &mut AnalysisHost,
    files: &[FileId],
    preparations: &Preparations,
    mut checked: report::Report,
    args: &PipelineArgs,
) -> ExitCode {
    let settings = match settings::grid(args.sets, args.sweeps) {
        Ok(settings) => settings,
        Err(why) => {
            eprintln!("gudsl run: {why}");
            return ExitCode::from(1);
        }
    };
    let plan = match host.analysis().pipeline_plan(args.diagram) {
        Ok(Some(plan)) => plan,
        Ok(None) => {
            eprintln!("gudsl run: no component-instance diagram `{}`", args.diagram);
            return ExitCode::from(1);
        }
        Err(_) => return cancelled(),
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
    let original = host.analysis().file_text(plan.file).to_string();
    let mut prepared = Vec::new();
    for setting in &settings {
        let made = if setting.assignments.is_empty() {
            prepare_as_checked(&host.analysis(), preparations, &plan, &mut checked, file)
        } else {
            prepare_setting(host, preparations, &plan, &original, setting)
        };
        match made {
            Ok(made) => prepared.push(made),
            Err(code) => return code,
        }
    }
    let gpu = pipeline::gpu(args.cpu, |error| {
        eprintln!("gudsl run: no GPU adapter ({error}); running on the CPU reference (--cpu says so)")
    });
    let output = match OutputDir::for_run(args.output, Path::new("."), &plan.diagram) {
        Ok(output) => output,
        Err(error) => {
            eprintln!("gudsl run: not writing into the output folder: {error}");
            return ExitCode::from(2);
        }
    };
    if args.sweeps.is_empty() {
        let prepared = prepared.pop().expect("one setting");
        return ExitCode::from(run_one(prepared, gpu.as_ref(), output, args.frames).1);
    }
    study::run(&settings, prepared, output, |prepared, nested| run_one(prepared, gpu.as_ref(), nested, args.frames))
}

fn cancelled() -> ExitCode {
    eprintln!("gudsl run: the analysis was cancelled");
    ExitCode::from(2)
}

/// The pipeline `plan` as the check prepared it; its problems refused as the check's findings.
fn prepare_as_checked(
    analysis: &Analysis,
    preparations: &Preparations,
    plan: &PipelinePlan,
    checked: &mut report::Report,
    file: usize,
) -> Result<PreparedPipeline, ExitCode> {
    match preparations.take_for(analysis, plan) {
        Err(_) => Err(cancelled()),
        Ok(Ok(prepared)) => Ok(prepared),
        Ok(Err(errors)) => {
            let code = if errors.iter().any(|e| e.kind == ErrorKind::Input) { 2 } else { 1 };
            checked.findings.clear();
            add_findings(checked, file, &errors);
            eprintln!("gudsl run: `{}` cannot run", plan.diagram);
            Err(super::refuse(checked, code))
        }
    }
}

/// The pipeline with `setting` written into the model: its problems told at the value that
/// caused them (`--set A.b=1: …`), or with the setting.
fn prepare_setting(
    host: &mut AnalysisHost,
    preparations: &Preparations,
    base: &PipelinePlan,
    original: &str,
    setting: &Setting,
) -> Result<PreparedPipeline, ExitCode> {
    let ranges = settings::apply(host, base.file, original, &base.diagram, setting).map_err(|why| {
        eprintln!("error[{}]: {why}", DiagnosticCode::ParameterValue.as_str());
        ExitCode::from(1)
    })?;
    let analysis = host.analysis();
    let told = |severity: Severity, code: DiagnosticCode, range: Option<TextRange>, message: &str| {
        let severity = if severity == Severity::Error { "error" } else { "warning" };
        let given = range.and_then(|r| ranges.iter().position(|v| v.contains_range(r) || r.contains_range(*v)));
        match given {
            Some(k) => {
                eprintln!("{severity}[{}]: {}: {message}", code.as_str(), setting.given(&setting.assignments[k]))
            }
            None => eprintln!("{severity}[{}]: {message} (with {})", code.as_str(), all_given(setting)),
        }
    };
    // Checked as the file is checked: the model's rules, the kernels, the pipeline's files.
    let Ok(diagnostics) = file_diagnostics(&analysis, base.file, preparations) else { return Err(cancelled()) };
    diagnostics.iter().for_each(|d| told(d.severity, d.code, Some(d.range), &d.message));
    if diagnostics.iter().any(|d| d.severity == Severity::Error) {
        let input = diagnostics.iter().any(|d| d.code == DiagnosticCode::PipelineInput);
        return Err(ExitCode::from(if input { 2 } else { 1 }));
    }
    let Ok(Some(plan)) = analysis.pipeline_plan(&base.diagram) else { return Err(cancelled()) };
    match preparations.take_for(&analysis, &plan) {
        Err(_) => Err(cancelled()),
        Ok(Err(errors)) => {
            // What the file's diagnostics do not tell: a component the runtime cannot run.
            let not_told = errors.iter().filter(|e| e.kind == ErrorKind::NotRunnable);
            not_told.for_each(|e| told(Severity::Error, e.code(), e.range, &e.to_string()));
            Err(ExitCode::from(1))
        }
        Ok(Ok(prepared)) => Ok(prepared),
    }
}

fn all_given(setting: &Setting) -> String {
    setting.assignments.iter().map(|a| setting.given(a)).collect::<Vec<_>>().join(" ")
}

/// Runs one prepared pipeline into `output`: its report printed and written, and the exit
/// code — 0 done, 1 a stage failed, 2 an output not written.
fn run_one(
    mut prepared: PreparedPipeline,
    gpu: Option<&Gpu>,
    mut output: OutputDir,
    frames: Option<usize>,
) -> (PipelineReport, u8) {
    let count = frames.map_or(prepared.frames(), |n| n.min(prepared.frames()));
    let device = gpu.map_or_else(|| "the CPU reference".to_string(), |g| g.describe());
    eprintln!("running {} ({count} frames) on {device}", prepared.diagram());
    let mut progress = Progress::new(count);
    let report = prepared.run(gpu, &mut output, frames, &mut progress, &AtomicBool::new(false));
    progress.done();
    print_report(&report);
    if let Err(error) = write_report(&report, &mut output) {
        eprintln!("gudsl run: {error}");
        return (report, 2);
    }
    // A sink that failed failed alone: the others wrote everything; the run still fails.
    for error in report.failed_stages() {
        eprintln!("error: {error}");
    }
    let code = match &report.outcome {
        Ok(()) if report.failed_stages().next().is_some() => 1,
        Ok(()) => 0,
        Err(error) => {
            eprintln!("error: {error}");
            if error.kind == ErrorKind::Output {
                2
            } else {
                1
            }
        }
    };
    (report, code)
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
