//! Quick fixes of a type's bases (E0230): a base named twice is removed; a class's base in the
//! clause of the other kind (`extends IShape` of an interface, `implements Base` of a class)
//! moves to its own clause. The clauses are written anew from their bases' text.

use crate::{
    ast::{self, AstNode},
    db::{Db, Workspace},
    hir::{items::TypeKind, DefKind, Scope, Semantics},
    syntax::{SyntaxNode, TextRange},
};

/// The fix for the base at `node`, with its title and its one edit: `None` where no single edit
/// is right (an enum as a base, an interface extending a class).
pub(super) fn fix_base(db: &dyn Db, workspace: Workspace, node: &SyntaxNode) -> Option<(String, (TextRange, String))> {
    let base = node.ancestors().find_map(ast::TypeRef::cast)?;
    let decl = base.syntax().ancestors().find_map(ast::TypeDecl::cast)?;
    let (extends, implements): (Vec<ast::TypeRef>, Vec<ast::TypeRef>) = match &decl {
        ast::TypeDecl::Class(c) => (c.extends().collect(), c.implements().collect()),
        ast::TypeDecl::Interface(i) => (i.extends().collect(), Vec::new()),
        _ => return None,
    };
    let sema = Semantics::new(db, workspace);
    let scope = Scope::at(decl.syntax());
    let resolve = |ty: &ast::TypeRef| ty.path().and_then(|p| sema.resolve(&scope, &p.text()));
    let here = resolve(&base)?;
    let written = base.syntax().text().to_string();
    let in_extends = extends.iter().any(|t| t.syntax() == base.syntax());
    let before = extends.iter().chain(&implements).take_while(|t| t.syntax() != base.syntax());
    let mut new_extends: Vec<String> = extends.iter().map(|t| t.syntax().text().to_string()).collect();
    let mut new_implements: Vec<String> = implements.iter().map(|t| t.syntax().text().to_string()).collect();
    let (from, to) =
        if in_extends { (&mut new_extends, &mut new_implements) } else { (&mut new_implements, &mut new_extends) };
    let index = if in_extends { &extends } else { &implements }.iter().position(|t| t.syntax() == base.syntax())?;
    from.remove(index);
    let title = if before.filter_map(resolve).any(|d| d.fqn == here.fqn) {
        format!("Remove the second `{written}`")
    } else {
        let DefKind::Type(ty) = &here.kind else { return None };
        match (&decl, in_extends, &ty.kind) {
            (ast::TypeDecl::Class(_), true, TypeKind::Interface(_)) => to.push(written.clone()),
            (ast::TypeDecl::Class(_), false, TypeKind::Class(_)) => to.push(written.clone()),
            _ => return None,
        }
        let clause = if in_extends { "implements" } else { "extends" };
        format!("Move `{written}` to `{clause}`")
    };
    Some((title, (clauses_range(&decl)?, clauses_text(&new_extends, &new_implements))))
}

/// From the first `extends`/`implements` clause of `decl` to the end of the last.
fn clauses_range(decl: &ast::TypeDecl) -> Option<TextRange> {
    let (extends, implements) = match decl {
        ast::TypeDecl::Class(c) => (
            c.extends_clause().map(|c| c.syntax().text_range()),
            c.implements_clause().map(|c| c.syntax().text_range()),
        ),
        ast::TypeDecl::Interface(i) => (i.extends_clause().map(|c| c.syntax().text_range()), None),
        _ => return None,
    };
    let first = extends.or(implements)?;
    Some(first.cover(implements.unwrap_or(first)))
}

/// `extends A, B implements I`: the clauses that have bases, `extends` first.
fn clauses_text(extends: &[String], implements: &[String]) -> String {
    let clause =
        |keyword: &str, bases: &[String]| (!bases.is_empty()).then(|| format!("{keyword} {}", bases.join(", ")));
    [clause("extends", extends), clause("implements", implements)].into_iter().flatten().collect::<Vec<_>>().join(" ")
}
