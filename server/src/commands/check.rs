//! `gudsl check PATH…`: reports every syntax and semantic problem in the given files and
//! folders (checked together as one workspace), for people
//! (`path:line:col: error[E0001]: message`) or machines (`--format json`).

use std::{path::PathBuf, process::ExitCode};

use clap::{Args, ValueEnum};
use gudsl_model::text::ColumnUnit;
use serde::Serialize;

use crate::workspace;

#[derive(Args)]
pub struct CheckArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Human)]
    format: Format,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Format {
    Human,
    Json,
}

/// One problem, positioned for people: 1-based lines and columns (columns count characters).
#[derive(Serialize)]
struct Diagnostic {
    path: String,
    line: u32,
    column: u32,
    end_line: u32,
    end_column: u32,
    severity: &'static str,
    code: &'static str,
    message: String,
}

#[derive(Serialize)]
struct Report {
    files: usize,
    errors: usize,
    warnings: usize,
    diagnostics: Vec<Diagnostic>,
}

pub fn run(args: &CheckArgs) -> ExitCode {
    let documents = match workspace::load(&args.paths) {
        Ok(documents) => documents,
        Err(error) => {
            eprintln!("gudsl check: {error}");
            return ExitCode::from(2);
        }
    };
    // The documents form one workspace.
    let (host, files) = workspace::analysis_host(&documents);
    let analysis = host.analysis();
    let mut diagnostics = Vec::new();
    for (document, &file) in documents.iter().zip(&files) {
        let Ok((found, index)) = analysis.diagnostics(file) else {
            eprintln!("gudsl check: the analysis was cancelled");
            return ExitCode::from(2);
        };
        for diagnostic in found {
            let start = index.line_col(diagnostic.range.start(), ColumnUnit::Char);
            let end = index.line_col(diagnostic.range.end(), ColumnUnit::Char);
            diagnostics.push(Diagnostic {
                path: document.path.display().to_string(),
                line: start.line + 1,
                column: start.col + 1,
                end_line: end.line + 1,
                end_column: end.col + 1,
                severity: diagnostic.severity.as_str(),
                code: diagnostic.code.as_str(),
                message: diagnostic.message.clone(),
            });
        }
    }
    let errors = diagnostics.iter().filter(|d| d.severity == "error").count();
    let warnings = diagnostics.len() - errors;
    let report = Report { files: documents.len(), errors, warnings, diagnostics };
    match args.format {
        Format::Json => match serde_json::to_string_pretty(&report) {
            Ok(json) => println!("{json}"),
            Err(error) => {
                eprintln!("gudsl check: {error}");
                return ExitCode::from(2);
            }
        },
        Format::Human => {
            for d in &report.diagnostics {
                println!("{}:{}:{}: {}[{}]: {}", d.path, d.line, d.column, d.severity, d.code, d.message);
            }
            let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
            eprintln!(
                "checked {}: {}, {}",
                plural(report.files, "file"),
                plural(report.errors, "error"),
                plural(report.warnings, "warning")
            );
        }
    }
    if report.errors > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
