//! `gudsl check [PATH…]`: reports every syntax and semantic problem in the given files and
//! folders (the current folder by default), checked together as one workspace, in the format
//! asked for (`report`): every diagnostic the editor shows, decided in one place
//! (`gudsl_host::diagnostics`). Exit code: 0 clean, 1 errors (or warnings with `--deny-warnings`),
//! 2 when a path could not be read (the others are still checked and reported).

use std::{path::PathBuf, process::ExitCode};

use clap::Args;
use gudsl_host::{diagnostics::file_diagnostics, pipeline::Preparations};
use gudsl_model::{hir::Severity, Analysis, FileId};

use crate::{
    report::{self, CheckedFile, Color, Finding, Format, Report},
    workspace,
};

#[derive(Args)]
pub struct CheckArgs {
    /// Files or folders (folders are searched for `.gudsl` files, skipping what `.gitignore`
    /// ignores); the current folder if none.
    paths: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
    /// Colour in the human formats: `auto` colours a terminal unless `NO_COLOR` is set.
    #[arg(long, value_enum, default_value_t = Color::Auto)]
    color: Color,
    /// Exit with 1 when there are warnings, not only when there are errors.
    #[arg(long)]
    deny_warnings: bool,
    /// Read the files models name only beneath this folder (default: the current folder; a
    /// model outside it reads beneath its own folder).
    #[arg(long, value_name = "DIR")]
    root: Option<PathBuf>,
}

pub fn run(args: &CheckArgs) -> ExitCode {
    let paths = if args.paths.is_empty() { vec![PathBuf::from(".")] } else { args.paths.clone() };
    let loaded = workspace::load(&paths);
    // The documents form one workspace.
    let (host, files) = workspace::analysis_host(&loaded.documents);
    let Some(report) =
        diagnose(loaded, &host.analysis(), &files, &Preparations::new(super::access(args.root.as_deref())))
    else {
        eprintln!("gudsl check: the analysis was cancelled");
        return ExitCode::from(2);
    };
    if let Err(error) = report::write(&report, args.format, args.color) {
        // A closed pipe (`gudsl check | head`) is not worth a message.
        if error.kind() != std::io::ErrorKind::BrokenPipe {
            eprintln!("gudsl check: {error}");
        }
        return ExitCode::from(2);
    }
    let failing = report.count(Severity::Error) + if args.deny_warnings { report.count(Severity::Warning) } else { 0 };
    if !report.unreadable.is_empty() {
        ExitCode::from(2)
    } else if failing > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Every problem of the loaded documents (one workspace, `files` in the same order), with the
/// paths that could not be read; `None` if the analysis was cancelled. The pipelines the check
/// prepares stay in `preparations`, for a run.
pub(crate) fn diagnose(
    loaded: workspace::Loaded,
    analysis: &Analysis,
    files: &[FileId],
    preparations: &Preparations,
) -> Option<Report> {
    let mut report = Report { unreadable: loaded.errors, ..Report::default() };
    for (document, &file) in loaded.documents.into_iter().zip(files) {
        let found = file_diagnostics(analysis, file, preparations).ok()?;
        let index = analysis.line_index(file).ok()?;
        let file_index = report.files.len();
        report.findings.extend(found.iter().map(|d| {
            Finding {
                file: file_index,
                severity: d.severity,
                code: d.code,
                message: d.message.clone(),
                range: d.range,
                related: d
                    .related
                    .iter()
                    .filter_map(|r| Some((files.iter().position(|f| *f == r.file)?, r.range, r.message.clone())))
                    .collect(),
            }
        }));
        report.files.push(CheckedFile {
            path: document.path.display().to_string(),
            text: document.text,
            index: index.clone(),
        });
    }
    Some(report)
}
