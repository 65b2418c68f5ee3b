//! Inheritance (Sec. 9.1.1): a class extends classes and implements interfaces, an interface
//! extends interfaces, no type derives from itself, and a generic type gets as many template
//! arguments as it has parameters.

use super::{Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode},
    hir::{
        definitions::{DefKind, Definition},
        items::TypeKind,
        semantics::describe,
    },
};

/// What `decl` (declared as `fqn`) extends and implements: the kinds, and no cycle.
pub(super) fn bases(ctx: &mut Ctx, scope: &Scope, fqn: &str, decl: &ast::TypeDecl) {
    let (extends, implements): (Vec<ast::TypeRef>, Vec<ast::TypeRef>) = match decl {
        ast::TypeDecl::Class(c) => (c.extends().collect(), c.implements().collect()),
        ast::TypeDecl::Interface(i) => (i.extends().collect(), Vec::new()),
        _ => return,
    };
    let is_class = matches!(decl, ast::TypeDecl::Class(_));
    let what = if is_class { "class" } else { "interface" };
    let mut named = std::collections::HashSet::new();
    for (base, implementing) in extends.iter().map(|b| (b, false)).chain(implements.iter().map(|b| (b, true))) {
        let Some(path) = base.path() else { continue };
        let Some(def) = ctx.sema.resolve(scope, &path.text()) else { continue };
        let DefKind::Type(ty) = &def.kind else { continue };
        if !named.insert(&def.fqn) {
            ctx.sink.error(
                DiagnosticCode::InvalidInheritance,
                base.syntax().text_range(),
                format!("{what} `{fqn}` names `{}` twice among its bases: remove this one", def.fqn),
            );
            continue;
        }
        let fix = match (is_class, implementing, &ty.kind) {
            (true, false, TypeKind::Class(_)) | (true, true, TypeKind::Interface(_)) => None,
            (false, _, TypeKind::Interface(_)) => None,
            (true, false, TypeKind::Interface(_)) => Some(format!(": write `implements {}`", path.text())),
            (true, true, TypeKind::Class(_)) => Some(format!(": write `extends {}`", path.text())),
            (false, _, TypeKind::Class(_)) => Some(": an interface extends interfaces only".to_string()),
            _ => Some(String::new()),
        };
        if let Some(fix) = fix {
            let verb = if implementing { "implement" } else { "extend" };
            ctx.sink.error(
                DiagnosticCode::InvalidInheritance,
                base.syntax().text_range(),
                format!("{what} `{fqn}` cannot {verb} {} `{}`{fix}", describe(&def.kind), def.fqn),
            );
        }
        if let Some(cycle) = cycle_through(ctx, def, fqn) {
            ctx.sink.error(
                DiagnosticCode::InheritanceCycle,
                base.syntax().text_range(),
                format!("`{fqn}` derives from itself: {fqn} → {}", cycle.join(" → ")),
            );
        }
    }
}

/// The chain of bases from `start` back to `fqn`, if there is one (`start` first).
fn cycle_through(ctx: &Ctx, start: &Definition, fqn: &str) -> Option<Vec<String>> {
    let mut seen = std::collections::HashSet::new();
    let mut stack = vec![vec![start]];
    while let Some(chain) = stack.pop() {
        let last = *chain.last().expect("chains are never empty");
        if last.fqn == fqn {
            return Some(chain.iter().map(|d| d.fqn.clone()).collect());
        }
        if !seen.insert(last.fqn.clone()) {
            continue;
        }
        for base in ctx.sema.bases(last) {
            let mut longer = chain.clone();
            longer.push(base);
            stack.push(longer);
        }
    }
    None
}

/// `ImageContainer<int>`: as many template arguments as the type has parameters.
pub(super) fn template_arguments(ctx: &mut Ctx, ty: &ast::TypeRef, def: &Definition) {
    let DefKind::Type(item) = &def.kind else { return };
    let given = ty.type_args().count();
    let expected = item.template_params.len();
    if given == expected {
        return;
    }
    let wanted = match expected {
        0 => "no template arguments".to_string(),
        1 => format!("1 template argument (`<{}>`)", item.template_params[0]),
        n => format!("{n} template arguments (`<{}>`)", item.template_params.join(", ")),
    };
    let range = ty.type_arg_list().map_or_else(|| ty.syntax().text_range(), |list| list.syntax().text_range());
    let name = ty.path().map(|p| p.text()).unwrap_or_default();
    ctx.sink.error(DiagnosticCode::TemplateArity, range, format!("`{name}` takes {wanted}, {given} given"));
}
