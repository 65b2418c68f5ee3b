//! One module per `gudsl` subcommand, and what the commands that act on a model share: loading
//! and checking it, refusing one with errors.

pub mod batch;
pub mod calibrate_phases;
pub mod check;
pub mod fmt;
pub mod pipeline;
pub mod render;
pub mod run;
pub mod settings;
pub mod wgsl;

#[cfg(test)]
mod tests;

use std::{
    path::{Path, PathBuf},
    process::ExitCode,
};

use gudsl_host::{access::Access, pipeline::Preparations};
use gudsl_model::{
    analysis::FileId,
    hir::{DiagnosticCode, Severity},
    AnalysisHost,
};

use crate::{
    report::{self, Color, Format},
    workspace,
};

/// What a command's models may read: the files beneath `root` (`--root`), else beneath the
/// current folder (a model outside it: beneath its own folder; `docs/security.md`).
pub fn access(root: Option<&Path>) -> Access {
    Access::new(vec![root.unwrap_or(Path::new(".")).to_path_buf()], true)
}

/// A model loaded and checked without errors: its files, the report of its warnings, and the
/// pipelines the check prepared.
pub struct Checked {
    pub host: AnalysisHost,
    pub files: Vec<FileId>,
    pub report: report::Report,
    pub preparations: Preparations,
}

/// The files under `paths`, loaded into one workspace and checked; or, when a path could not be
/// read (exit code 2), the model has errors (1) or a file a pipeline reads is missing or
/// malformed (E0404, 2), the exit code after printing why `command` does nothing.
pub fn checked_model(paths: &[PathBuf], root: Option<&Path>, command: &str) -> Result<Checked, ExitCode> {
    checked_model_but_inputs(paths, root, command, false)
}

/// [`checked_model`], where `inputs_given` says the files the pipelines read are given on the
/// command line (`run --set`, `--inputs`): the model's own missing or malformed ones (E0404)
/// are left out, as each run is checked with its values again.
pub fn checked_model_but_inputs(
    paths: &[PathBuf],
    root: Option<&Path>,
    command: &str,
    inputs_given: bool,
) -> Result<Checked, ExitCode> {
    let loaded = workspace::load(paths);
    let unreadable = !loaded.errors.is_empty();
    let (host, files) = workspace::analysis_host(&loaded.documents);
    let preparations = Preparations::new(access(root));
    let Some(report) = check::diagnose(loaded, &host.analysis(), &files, &preparations) else {
        eprintln!("gudsl {command}: the analysis was cancelled");
        return Err(ExitCode::from(2));
    };
    let mut report = report;
    if inputs_given {
        report.findings.retain(|f| f.code != DiagnosticCode::PipelineInput);
    }
    if unreadable {
        eprintln!("gudsl {command}: a path could not be read; nothing is done");
        return Err(refuse(&report, 2));
    }
    if report.count(Severity::Error) > 0 {
        eprintln!("gudsl {command}: the model has errors; nothing is done");
        let unreadable_input = report.findings.iter().any(|f| f.code == DiagnosticCode::PipelineInput);
        return Err(refuse(&report, if unreadable_input { 2 } else { 1 }));
    }
    Ok(Checked { host, files, report, preparations })
}

/// Prints the problems and the unreadable paths (as `gudsl check` does) and exits with `code`.
pub fn refuse(report: &report::Report, code: u8) -> ExitCode {
    let _ = report::write(report, Format::Human, Color::Auto);
    ExitCode::from(code)
}
