//! The report for people, through `codespan-reporting`: each problem with the source lines it
//! points at (or, concise, one `path:line:col: error[E0201]: message` line), unreadable paths
//! as errors on stderr, and a one-line summary.

use std::{io, ops::Range};

use codespan_reporting::{
    diagnostic::{Diagnostic, Label},
    files::{Error, Files},
    term::{self, termcolor::StandardStream, Config, DisplayStyle},
};
use gudsl_model::hir::Severity;

use super::{Color, Report};

pub enum Style {
    Rich,
    Concise,
}

/// The checked files as `codespan-reporting` reads them: lines as the model counts them
/// (`\n`, `\r\n` and a lone `\r` each end one).
struct CheckedFiles<'a>(&'a Report);

impl<'a> Files<'a> for CheckedFiles<'a> {
    type FileId = usize;
    type Name = &'a str;
    type Source = &'a str;

    fn name(&'a self, id: usize) -> Result<&'a str, Error> {
        Ok(&self.0.files.get(id).ok_or(Error::FileMissing)?.path)
    }

    fn source(&'a self, id: usize) -> Result<&'a str, Error> {
        Ok(&self.0.files.get(id).ok_or(Error::FileMissing)?.text)
    }

    fn line_index(&'a self, id: usize, byte_index: usize) -> Result<usize, Error> {
        let file = self.0.files.get(id).ok_or(Error::FileMissing)?;
        let offset =
            u32::try_from(byte_index).map_err(|_| Error::IndexTooLarge { given: byte_index, max: file.text.len() })?;
        Ok(file.index.line_col(offset.into(), gudsl_model::text::ColumnUnit::Utf8).line as usize)
    }

    /// A line with its terminator, as `codespan-reporting` expects.
    fn line_range(&'a self, id: usize, line_index: usize) -> Result<Range<usize>, Error> {
        let file = self.0.files.get(id).ok_or(Error::FileMissing)?;
        let line = file
            .index
            .line_range(line_index)
            .ok_or(Error::LineTooLarge { given: line_index, max: file.index.line_count() - 1 })?;
        let end = file.index.line_range(line_index + 1).map_or(file.index.text_len(), |next| next.start());
        Ok(usize::from(line.start())..usize::from(end))
    }
}

pub fn write(report: &Report, style: Style, color: Color) -> io::Result<()> {
    let files = CheckedFiles(report);
    let config = Config {
        display_style: match style {
            Style::Rich => DisplayStyle::Rich,
            Style::Concise => DisplayStyle::Short,
        },
        ..Config::default()
    };
    let mut stdout = color.stdout();
    for finding in &report.findings {
        let diagnostic = match finding.severity {
            Severity::Error => Diagnostic::error(),
            Severity::Warning => Diagnostic::warning(),
        }
        .with_code(finding.code.as_str())
        .with_message(&finding.message)
        .with_labels(
            std::iter::once(Label::primary(finding.file, finding.range))
                .chain(
                    finding
                        .related
                        .iter()
                        .map(|(file, range, message)| Label::secondary(*file, *range).with_message(message.clone())),
                )
                .collect(),
        );
        emit(&mut stdout, &config, &files, &diagnostic)?;
    }
    let mut stderr = color.stderr();
    for unreadable in &report.unreadable {
        let diagnostic = Diagnostic::error().with_message(unreadable.to_string());
        emit(&mut stderr, &config, &files, &diagnostic)?;
    }
    let plural = |n: usize, what: &str| format!("{n} {what}{}", if n == 1 { "" } else { "s" });
    let mut summary = format!(
        "checked {}: {}, {}",
        plural(report.files.len(), "file"),
        plural(report.count(Severity::Error), "error"),
        plural(report.count(Severity::Warning), "warning")
    );
    if !report.unreadable.is_empty() {
        summary += &format!("; {} could not be read", plural(report.unreadable.len(), "path"));
    }
    eprintln!("{summary}");
    Ok(())
}

fn emit(
    stream: &mut StandardStream,
    config: &Config,
    files: &CheckedFiles,
    diagnostic: &Diagnostic<usize>,
) -> io::Result<()> {
    term::emit_to_write_style(&mut stream.lock(), config, files, diagnostic).map_err(|error| match error {
        Error::Io(error) => error,
        other => io::Error::other(other.to_string()),
    })
}
