//! Names: two things of one name in one scope, a diagram or type declared in another file too,
//! and imports of names that do not exist.

use std::collections::HashMap;

use super::{Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasName},
    hir::items::import_item,
};
use crate::{hir::diagnostics::Related, syntax::TextRange};

/// Reports every name of `names` after the first of its spelling.
pub(super) fn duplicates(ctx: &mut Ctx, names: impl Iterator<Item = ast::Name>, what: &str) {
    let mut first: HashMap<String, TextRange> = HashMap::new();
    for name in names {
        let text = name.text();
        let range = name.syntax().text_range();
        match first.get(&text) {
            Some(&declared) => ctx.sink.error_with_related(
                DiagnosticCode::DuplicateName,
                range,
                format!("{what} `{text}` is declared more than once in this scope"),
                vec![Related { file: ctx.file, range: declared, message: format!("`{text}` is first declared here") }],
            ),
            None => drop(first.insert(text, range)),
        }
    }
}

/// Reports `name` (declared with fully qualified name `fqn`) if another file declares it too.
pub(super) fn unique_across_files(ctx: &mut Ctx, fqn: &str, name: &ast::Name, what: &str) {
    if !ctx.sema.declared_in_several_files(fqn) {
        return;
    }
    let here = ctx.file;
    let db = ctx.sema.db();
    if let Some(other) = ctx.sema.lookup(fqn).iter().find(|d| d.file != here) {
        let related = ctx.sema.declaration(other).map(|(_, focus)| Related {
            file: other.file,
            range: focus,
            message: format!("`{fqn}` is also declared here"),
        });
        ctx.sink.error_with_related(
            DiagnosticCode::DuplicateName,
            name.syntax().text_range(),
            format!("{what} `{fqn}` is also declared in {}", other.file.path(db)),
            related.into_iter().collect(),
        );
    }
}

/// An import: it must name a diagram or type; it enters `scope` either way.
pub(super) fn import(ctx: &mut Ctx, scope: &mut Scope, import: &ast::Import) {
    let path = match import.target() {
        Some(ast::ImportTarget::Name(path) | ast::ImportTarget::Wildcard(path)) => path,
        _ => return,
    };
    if ctx.sema.lookup(&path.text()).is_empty() {
        ctx.sink.error(
            DiagnosticCode::UnresolvedImport,
            path.syntax().text_range(),
            format!("cannot import `{}`: no diagram or type has this fully qualified name", path.text()),
        );
    }
    scope.imports.extend(import_item(import));
}

/// Two local variables of one name in one block of a body.
pub(super) fn duplicate_locals(ctx: &mut Ctx, body: &crate::syntax::SyntaxNode) {
    if !ast::owns_at_least(body, 2, |k| k == crate::syntax::SyntaxKind::VAR_DECL) {
        return;
    }
    for block in ast::own_descendants(body).filter(|n| n == body || ast::Block::can_cast(n.kind())) {
        duplicates(ctx, ast::support::children::<ast::VarDecl>(&block).filter_map(|d| d.name()), "variable");
    }
}
