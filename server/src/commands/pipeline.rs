//! `gudsl run FILE --diagram PIPELINE`: a component-instance diagram run as a ToF pipeline on
//! the first wgpu adapter (`--cpu`: the CPU reference), frame after frame with a progress bar on
//! a terminal (a line a frame otherwise), then a table of the stages — time per frame and share
//! of the total — and the files written, all under the output folder (default
//! `gudsl-out/<diagram>/`), with `report.json` beside them. A pipeline the plan finds problems
//! in (E0401–E0403) or whose files or components do not fit (E0404, E0405) is refused with its
//! diagnostics. Exit code: 0 done, 1 a problem of the model or a failed stage, 2 an input or
//! output that cannot be read or written, or no device.

use std::{io::IsTerminal, path::Path, process::ExitCode, sync::atomic::AtomicBool};

use gudsl_host::pipeline::{
    self, summary, table, write_report, ErrorKind, OutputDir, PipelineError, PipelineObserver, PipelineReport,
    Preparations,
};
use gudsl_model::{
    analysis::{Analysis, FileId},
    hir::Severity,
};

use crate::report::{self, Finding};

/// What `run` was asked to do with a pipeline.
pub struct PipelineArgs<'a> {
    pub diagram: &'a str,
    pub frames: Option<usize>,
    pub cpu: bool,
    pub output: Option<&'a Path>,
}

/// Runs the pipeline `args` names, taking what the check of the model prepared from
/// `preparations`.
pub fn run(
    analysis: &Analysis,
    files: &[FileId],
    preparations: &Preparations,
    mut checked: report::Report,
    args: &PipelineArgs,
) -> ExitCode {
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
    let Ok(prepared) = preparations.take_for(analysis, &plan) else {
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
    let mut output = match OutputDir::for_run(args.output, Path::new("."), &plan.diagram) {
        Ok(output) => output,
        Err(error) => {
            eprintln!("gudsl run: not writing into the output folder: {error}");
            return ExitCode::from(2);
        }
    };
    let gpu = pipeline::gpu(args.cpu, |error| {
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
    // A sink that failed failed alone: the others wrote everything; the run still fails.
    for error in report.failed_stages() {
        eprintln!("error: {error}");
    }
    match &report.outcome {
        Ok(()) if report.failed_stages().next().is_some() => ExitCode::from(1),
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(if error.kind == ErrorKind::Output { 2 } else { 1 })
        }
    }
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
