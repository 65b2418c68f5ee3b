//! The generator as salsa queries over the model's database (as `hir-ty` adds queries over
//! `hir-def`): a device diagram's kernel is generated once per revision of what it reads, and a
//! file's E0301 diagnostics are remembered; `gudsl check`, `gudsl wgsl`, the editor and a run
//! all ask these, so none generates a kernel the others already have.

use std::cell::Cell;

use gudsl_model::{
    db::{Db, SourceFile, Workspace},
    hir::{DefKind, Definition, Diagnostic, DiagnosticCode, Fqn, Semantics, Severity},
};

use crate::{is_kernel, kernel, CodegenError, Kernel};

thread_local! {
    /// How many kernels this thread has generated (tests count that a run generates each once;
    /// a query runs on the thread that asks it).
    static GENERATED: Cell<usize> = const { Cell::new(0) };
}

/// How many kernels this thread has generated so far.
pub fn generated_kernels() -> usize {
    GENERATED.get()
}

/// The kernel of the device diagram named `diagram`, or what cannot be generated; `None` when
/// no device diagram has the name.
#[salsa::tracked(returns(ref))]
pub fn device_kernel<'db>(
    db: &'db dyn Db,
    workspace: Workspace,
    diagram: Fqn<'db>,
) -> Option<Result<Kernel, Vec<CodegenError>>> {
    let sema = Semantics::new(db, workspace);
    let def = device_diagram_named(&sema, diagram.text(db))?;
    Some(generate_uncached(&sema, def))
}

/// The device diagram [`device_kernel`] generates for the name `fqn`: the first declared.
pub(crate) fn device_diagram_named<'db>(sema: &Semantics<'db>, fqn: &str) -> Option<&'db Definition> {
    sema.lookup(fqn).iter().find(|def| {
        matches!(def.kind, DefKind::Activity(_))
            && !gudsl_model::library::is_library(sema.db(), def.file)
            && is_kernel(sema, def)
    })
}

/// The kernel of `def`, the one the query for its name finds or not: generated now, and counted.
pub(crate) fn generate_uncached(sema: &Semantics<'_>, def: &Definition) -> Result<Kernel, Vec<CodegenError>> {
    GENERATED.set(GENERATED.get() + 1);
    kernel::generate(sema, def)
}

/// What cannot be generated of the device diagrams declared in `file` (E0301): at the construct
/// when it is in `file`, else at the diagram's name with the other file named.
#[salsa::tracked(returns(ref))]
pub fn device_diagnostics(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Diagnostic> {
    let sema = Semantics::new(db, workspace);
    let mut out = Vec::new();
    let diagrams = sema.file_diagrams(file).filter(|def| matches!(def.kind, DefKind::Activity(_)));
    for def in diagrams.filter(|def| is_kernel(&sema, def)) {
        let Some(Err(errors)) = device_kernel(db, workspace, Fqn::new(db, def.fqn.clone())) else { continue };
        for error in errors {
            let (range, message) = if error.file == file {
                (error.range, error.message.clone())
            } else {
                let Some((_, name)) = sema.declaration(def) else { continue };
                (name, format!("{} (in {})", error.message, error.file.path(db)))
            };
            out.push(Diagnostic {
                code: DiagnosticCode::NotGenerated,
                severity: Severity::Error,
                range,
                message,
                suggestion: None,
                related: Vec::new(),
            });
        }
    }
    out
}
