//! Validation: the rules every diagram kind states, one family a module, each reading the model
//! only through [`Semantics`] and reporting into a [`Diagnostics`] sink. [`check_file`] walks a
//! file's diagrams in order, builds each one's scope, and hands the diagram to the rules of its
//! kind; [`file_diagnostics`] adds the syntax errors.
//!
//! Other files are reached only through `Semantics` (per-name `lookup` queries), so a file is
//! re-checked exactly when a name it uses changes meaning.

mod activity;
mod calls;
mod class_diagram;
mod component_diagram;
mod flow;
mod inheritance;
mod instance_diagram;
mod names;
mod objects;
mod recursion;
mod types;

use super::{
    diagnostics::{Diagnostic, DiagnosticCode, Diagnostics, Severity},
    scope::Scope,
    semantics::Semantics,
};
use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
};

/// What every rule works with: the model, the file being checked, and the sink.
pub(crate) struct Ctx<'db> {
    pub(crate) sema: Semantics<'db>,
    pub(crate) file: SourceFile,
    pub(crate) sink: Diagnostics,
}

impl Ctx<'_> {
    /// Whether a syntax error of the file lies in `range`: what the error cut short is checked
    /// once it is fixed (one mistake, one diagnostic).
    pub(crate) fn syntax_error_in(&self, range: crate::syntax::TextRange) -> bool {
        parse(self.sema.db(), self.file).errors().iter().any(|e| range.contains_range(e.range))
    }
}

/// The semantic diagnostics of one file, in the order the rules found them.
#[salsa::tracked(returns(ref))]
pub fn check_file(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Diagnostic> {
    let mut ctx = Ctx { sema: Semantics::new(db, workspace), file, sink: Diagnostics::default() };
    let source = parse(db, file).source_file();
    names::duplicates(&mut ctx, source.diagrams().filter_map(|d| d.name()), "diagram");
    for diagram in source.diagrams() {
        check_diagram(&mut ctx, &Scope::default(), &diagram);
    }
    ctx.sink.into_vec()
}

/// Every problem of `file`: syntax errors first, then semantic ones, by position.
#[salsa::tracked(returns(ref))]
pub fn file_diagnostics(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Diagnostic> {
    let mut diagnostics: Vec<Diagnostic> = parse(db, file)
        .errors()
        .iter()
        .map(|e| Diagnostic {
            code: DiagnosticCode::Syntax(e.code),
            severity: Severity::Error,
            range: e.range,
            message: e.message.clone(),
            suggestion: None,
            related: Vec::new(),
        })
        .collect();
    diagnostics.extend(check_file(db, workspace, file).iter().cloned());
    diagnostics.sort_by_key(|d| (d.range.start(), d.range.end()));
    diagnostics
}

/// The message for a name that resolves to nothing: ambiguous when several types have that
/// simple name (`what` says what was wanted), else `unknown`.
fn unresolved_message(ctx: &Ctx, text: &str, what: &str, unknown: String) -> String {
    let candidates = ctx.sema.candidates(text);
    if candidates.len() > 1 {
        format!("ambiguous {what} `{text}`: qualify it or import one of {}", candidates.join(", "))
    } else {
        unknown
    }
}

/// A diagram and the diagrams nested in it, each in its own namespace.
fn check_diagram(ctx: &mut Ctx, outer: &Scope, diagram: &ast::Diagram) {
    let Some(name) = diagram.name() else { return };
    let mut scope = outer.clone();
    scope.enter(&name.text());
    for import in ast::support::children::<ast::Import>(diagram.syntax()) {
        names::import(ctx, &mut scope, &import);
    }
    let nested: Vec<ast::Diagram> = ast::support::children::<ast::Diagram>(diagram.syntax()).collect();
    // Class diagrams are namespaces and merge across files; other diagrams must be unique.
    if !matches!(diagram, ast::Diagram::ClassDiagram(_)) {
        names::unique_across_files(ctx, scope.innermost(), &name, "diagram");
    }
    match diagram {
        ast::Diagram::ClassDiagram(d) => class_diagram::check(ctx, &scope, d, &nested),
        ast::Diagram::ActivityDiagram(d) => activity::check(ctx, &scope, d),
        ast::Diagram::ComponentDiagram(d) => {
            names::duplicates(ctx, nested.iter().filter_map(|d| d.name()), "diagram");
            component_diagram::check(ctx, &scope, d);
        }
        ast::Diagram::ComponentInstanceDiagram(d) => {
            names::duplicates(ctx, nested.iter().filter_map(|d| d.name()), "diagram");
            instance_diagram::check(ctx, &scope, d);
            let fqn = crate::hir::Fqn::new(ctx.sema.db(), scope.innermost().to_string());
            let plan = crate::hir::pipeline::pipeline_plan(ctx.sema.db(), ctx.sema.workspace(), fqn);
            for problem in plan.iter().filter(|p| p.file == ctx.file).flat_map(|p| &p.diagnostics) {
                ctx.sink.add(problem.clone());
            }
        }
    }
    for nested in &nested {
        check_diagram(ctx, &scope, nested);
    }
}
