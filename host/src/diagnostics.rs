//! A file's diagnostics, decided in one place for `gudsl check`, the other commands and the
//! editor (rust-analyzer's `DiagnosticCollection` is the shape): the model's (syntax, then
//! semantics), and when those have no error, what of its device diagrams cannot be generated
//! (E0301, a query of the code generator) and what keeps its pipelines from running (E0404,
//! E0405, prepared once in [`Preparations`]).

use gudsl_model::{
    hir::{Diagnostic, Severity},
    Analysis, Cancellable, FileId,
};

use crate::pipeline::Preparations;

/// Every problem of `file`, model first; `pipelines` keeps what its pipelines' check prepared.
pub fn file_diagnostics(analysis: &Analysis, file: FileId, pipelines: &Preparations) -> Cancellable<Vec<Diagnostic>> {
    let (model, _) = analysis.diagnostics(file)?;
    let mut out = model.to_vec();
    if out.iter().any(|d| d.severity == Severity::Error) {
        return Ok(out);
    }
    let device = analysis
        .with_semantics(|sema| gudsl_codegen::queries::device_diagnostics(sema.db(), sema.workspace(), file).clone())?;
    out.extend(device);
    out.extend(pipelines.file_diagnostics(analysis, file)?);
    Ok(out)
}
