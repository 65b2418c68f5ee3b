//! `gudsl check PATH…`: reports every problem in the given files and folders, for people
//! (`path:line:col: error[E0001]: message`) or machines (`--format json`).

use std::{path::PathBuf, process::ExitCode};

use clap::{Args, ValueEnum};
use gudsl_model::text::{ColumnUnit, LineIndex};
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
    let mut diagnostics = Vec::new();
    for document in &documents {
        let parse = gudsl_model::parse(&document.text);
        if parse.errors().is_empty() {
            continue;
        }
        let index = LineIndex::new(&document.text);
        for error in parse.errors() {
            let start = index.line_col(error.range.start(), ColumnUnit::Char);
            let end = index.line_col(error.range.end(), ColumnUnit::Char);
            diagnostics.push(Diagnostic {
                path: document.path.display().to_string(),
                line: start.line + 1,
                column: start.col + 1,
                end_line: end.line + 1,
                end_column: end.col + 1,
                severity: "error",
                code: error.code.as_str(),
                message: error.message.clone(),
            });
        }
    }
    let report = Report { files: documents.len(), errors: diagnostics.len(), diagnostics };
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
            eprintln!("checked {}: {}", plural(report.files, "file"), plural(report.errors, "error"));
        }
    }
    if report.errors > 0 {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
