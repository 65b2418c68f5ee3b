//! What `gudsl check` found, and the formats it is written in: for people (a source snippet
//! under each problem, coloured on a terminal, or one line each), for scripts (JSON), for
//! GitHub code scanning (SARIF 2.1.0) and for GitHub Actions annotations.

mod github;
mod human;
mod json;
mod sarif;

use std::io::{self, IsTerminal};

use clap::ValueEnum;
use codespan_reporting::term::termcolor;
use gudsl_model::{
    hir::{DiagnosticCode, Severity},
    syntax::TextRange,
    text::{ColumnUnit, LineIndex},
};

use crate::workspace::LoadError;

/// A checked document.
pub struct CheckedFile {
    /// The path as the user named it.
    pub path: String,
    pub text: String,
    pub index: LineIndex,
}

/// One problem in one checked file.
pub struct Finding {
    /// Index into [`Report::files`].
    pub file: usize,
    pub severity: Severity,
    pub code: DiagnosticCode,
    pub message: String,
    pub range: TextRange,
    /// Other places that explain it (file index, range, message): a duplicate's first
    /// declaration.
    pub related: Vec<(usize, TextRange, String)>,
}

/// Everything one run found: the files checked, their problems (in file order, each file's in
/// text order) and the paths that could not be read.
#[derive(Default)]
pub struct Report {
    pub files: Vec<CheckedFile>,
    pub findings: Vec<Finding>,
    pub unreadable: Vec<LoadError>,
}

/// A 1-based line and column (columns count characters, as editors show them).
#[derive(Clone, Copy)]
pub struct Position {
    pub line: u32,
    pub column: u32,
}

impl Report {
    pub fn count(&self, severity: Severity) -> usize {
        self.findings.iter().filter(|f| f.severity == severity).count()
    }

    /// Where a finding starts and ends.
    pub fn span(&self, finding: &Finding) -> (Position, Position) {
        self.span_in(finding.file, finding.range)
    }

    /// Where `range` of checked file `file` starts and ends.
    pub fn span_in(&self, file: usize, range: TextRange) -> (Position, Position) {
        let index = &self.files[file].index;
        let at = |offset| {
            let at = index.line_col(offset, ColumnUnit::Char);
            Position { line: at.line + 1, column: at.col + 1 }
        };
        (at(range.start()), at(range.end()))
    }

    pub fn path(&self, finding: &Finding) -> &str {
        &self.files[finding.file].path
    }
}

/// How the report is written.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Each problem with the source lines it points at.
    Human,
    /// One line per problem: `path:line:col: error[E0201]: message`.
    Concise,
    /// One JSON document, for scripts.
    Json,
    /// SARIF 2.1.0, for GitHub code scanning and other SARIF viewers.
    Sarif,
    /// GitHub Actions workflow commands: annotations on the pull request.
    Github,
}

/// Whether the human formats use colour.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Color {
    /// On a terminal, unless `NO_COLOR` is set.
    Auto,
    Always,
    Never,
}

impl Color {
    fn for_stream(self, is_terminal: bool) -> termcolor::ColorChoice {
        let no_color = std::env::var_os("NO_COLOR").is_some_and(|v| !v.is_empty());
        match self {
            Color::Always => termcolor::ColorChoice::Always,
            Color::Auto if is_terminal && !no_color => termcolor::ColorChoice::Auto,
            _ => termcolor::ColorChoice::Never,
        }
    }

    pub fn stdout(self) -> termcolor::StandardStream {
        termcolor::StandardStream::stdout(self.for_stream(io::stdout().is_terminal()))
    }

    pub fn stderr(self) -> termcolor::StandardStream {
        termcolor::StandardStream::stderr(self.for_stream(io::stderr().is_terminal()))
    }
}

/// Writes `report` in `format`: problems on stdout, unreadable paths and the summary on stderr
/// (in the machine formats the unreadable paths are part of the document too).
pub fn write(report: &Report, format: Format, color: Color) -> io::Result<()> {
    match format {
        Format::Human => human::write(report, human::Style::Rich, color),
        Format::Concise => human::write(report, human::Style::Concise, color),
        Format::Json => json::write(report, &mut io::stdout().lock()),
        Format::Sarif => sarif::write(report, &mut io::stdout().lock()),
        Format::Github => github::write(report, &mut io::stdout().lock()),
    }
}
