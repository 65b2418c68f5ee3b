//! Names: two things of one name in one scope, a diagram or type declared in another file too,
//! and imports of names that do not exist.

use std::collections::HashSet;

use super::{Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasName},
    hir::items::import_item,
};

/// Reports every name of `names` after the first of its spelling.
pub(super) fn duplicates(ctx: &mut Ctx, names: impl Iterator<Item = ast::Name>, what: &str) {
    let mut seen: HashSet<String> = HashSet::new();
    for name in names {
        let text = name.text();
        if !seen.insert(text.clone()) {
            ctx.sink.error(
                DiagnosticCode::DuplicateName,
                name.syntax().text_range(),
                format!("{what} `{text}` is declared more than once in this scope"),
            );
        }
    }
}

/// Reports `name` (declared with fully qualified name `fqn`) if another file declares it too.
pub(super) fn unique_across_files(ctx: &mut Ctx, fqn: &str, name: &ast::Name, what: &str) {
    let here = ctx.file;
    let db = ctx.sema.db();
    if let Some(other) = ctx.sema.lookup(fqn).iter().find(|d| d.file != here) {
        ctx.sink.error(
            DiagnosticCode::DuplicateName,
            name.syntax().text_range(),
            format!("{what} `{fqn}` is also declared in {}", other.file.path(db)),
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
    for block in body.descendants().filter(|n| n == body || ast::Block::can_cast(n.kind())) {
        duplicates(ctx, block.children().filter_map(ast::VarDecl::cast).filter_map(|d| d.name()), "variable");
    }
}
