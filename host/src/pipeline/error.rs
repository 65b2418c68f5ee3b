//! Why a pipeline cannot be prepared or stopped: a [`PipelineError`] with its kind, the
//! instance it concerns and its place in the model file; its diagnostic code follows from the
//! kind.

use gudsl_model::{hir::DiagnosticCode, syntax::TextRange};

/// A problem that stops a pipeline, at a place of the model file when it has one.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PipelineError {
    pub kind: ErrorKind,
    /// The instance it concerns, if any.
    pub stage: Option<String>,
    /// Where in the model file (an instance's name, a parameter's value).
    pub range: Option<TextRange>,
    pub message: String,
}

/// What kind of problem: as the diagnostic codes say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A file that cannot be read or is not what the component expects (E0404).
    Input,
    /// Images that cannot meet (E0405).
    Mismatch,
    /// A component the runtime cannot run, a diagram with nothing to run (E0405 when it is
    /// run; the model itself is right).
    NotRunnable,
    /// A stage failed while running.
    Failed,
    /// An output that cannot be written.
    Output,
    Cancelled,
    /// A setting that cannot act in this pipeline (a warning, E0406): the run goes on.
    Ineffective,
}

impl PipelineError {
    /// Its diagnostic code: E0404 for an input, E0406 for a setting that cannot act, E0405 for
    /// the rest.
    pub fn code(&self) -> DiagnosticCode {
        match self.kind {
            ErrorKind::Input => DiagnosticCode::PipelineInput,
            ErrorKind::Ineffective => DiagnosticCode::PipelineIneffective,
            _ => DiagnosticCode::PipelineMismatch,
        }
    }
}

impl std::fmt::Display for PipelineError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.stage {
            Some(stage) => write!(f, "`{stage}`: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}
