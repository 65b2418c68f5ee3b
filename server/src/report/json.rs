//! The report as one JSON document, for scripts: every problem with its path, 1-based start
//! and end (columns count characters), severity, code, message and related places, the counts,
//! and the paths that could not be read.

use std::io;

use gudsl_model::hir::Severity;
use serde::Serialize;

use super::Report;

#[derive(Serialize)]
struct Diagnostic<'a> {
    path: &'a str,
    line: u32,
    column: u32,
    end_line: u32,
    end_column: u32,
    severity: &'static str,
    code: &'static str,
    message: &'a str,
    /// Other places that explain it (a duplicate's first declaration).
    related: Vec<Related<'a>>,
}

#[derive(Serialize)]
struct Related<'a> {
    path: &'a str,
    line: u32,
    column: u32,
    end_line: u32,
    end_column: u32,
    message: &'a str,
}

#[derive(Serialize)]
struct Unreadable {
    path: String,
    message: String,
}

#[derive(Serialize)]
struct Document<'a> {
    files: usize,
    errors: usize,
    warnings: usize,
    diagnostics: Vec<Diagnostic<'a>>,
    unreadable: Vec<Unreadable>,
}

pub fn write(report: &Report, out: &mut impl io::Write) -> io::Result<()> {
    let diagnostics = report
        .findings
        .iter()
        .map(|finding| {
            let (start, end) = report.span(finding);
            Diagnostic {
                path: report.path(finding),
                line: start.line,
                column: start.column,
                end_line: end.line,
                end_column: end.column,
                severity: finding.severity.as_str(),
                code: finding.code.as_str(),
                message: &finding.message,
                related: finding
                    .related
                    .iter()
                    .map(|(file, range, message)| {
                        let (start, end) = report.span_in(*file, *range);
                        Related {
                            path: &report.files[*file].path,
                            line: start.line,
                            column: start.column,
                            end_line: end.line,
                            end_column: end.column,
                            message,
                        }
                    })
                    .collect(),
            }
        })
        .collect();
    let unreadable = report
        .unreadable
        .iter()
        .map(|u| Unreadable { path: u.path.display().to_string(), message: u.message.clone() })
        .collect();
    let document = Document {
        files: report.files.len(),
        errors: report.count(Severity::Error),
        warnings: report.count(Severity::Warning),
        diagnostics,
        unreadable,
    };
    serde_json::to_writer_pretty(&mut *out, &document)?;
    writeln!(out)
}
