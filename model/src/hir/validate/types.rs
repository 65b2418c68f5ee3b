//! Type references (a built-in, a GPU type, a template parameter or a declared type), parameter
//! lists, and attribute uses (`[A.B(field = value)]`).

use super::{unresolved_message, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasName},
    hir::{
        definitions::DefKind,
        infer::InferenceCtx,
        items::ImportItem,
        items::TypeKind,
        semantics::describe,
        spelling::closest,
        ty::{common_builtin_type_names, is_builtin_type_name},
    },
    syntax::SyntaxNode,
};

/// Checks that a type names something, and its type arguments likewise.
pub(super) fn type_ref(ctx: &mut Ctx, scope: &Scope, ty: &ast::TypeRef) {
    for arg in ty.type_args() {
        type_ref(ctx, scope, &arg);
    }
    let Some(path) = ty.path() else { return };
    let text = path.text();
    if text.is_empty() || is_builtin_type_name(&text) || scope.type_params.contains(&text) {
        return;
    }
    match ctx.sema.resolve(scope, &text) {
        Some(def) if matches!(def.kind, DefKind::Type(_)) => super::inheritance::template_arguments(ctx, ty, def),
        Some(def) => ctx.sink.error(
            DiagnosticCode::UnresolvedType,
            path.syntax().text_range(),
            format!("`{text}` names {} `{}`, not a type", describe(&def.kind), def.fqn),
        ),
        None => {
            let unknown =
                format!("unknown type `{text}`: declare it in a class diagram or import the diagram that does");
            let message = unresolved_message(ctx, &text, "type", unknown);
            let suggestion = misspelt_type(ctx, scope, &text);
            ctx.sink.error_with_suggestion(
                DiagnosticCode::UnresolvedType,
                path.syntax().text_range(),
                message,
                suggestion.as_deref(),
            );
        }
    }
}

/// The type in scope a simple name that resolves to nothing most likely meant (none for a
/// qualified or an ambiguous name: those are not typos of a simple name).
pub(super) fn misspelt_type(ctx: &Ctx, scope: &Scope, text: &str) -> Option<String> {
    if text.contains('.') || ctx.sema.candidates(text).len() > 1 {
        return None;
    }
    let candidates = types_in_scope(ctx, scope);
    closest(text, candidates.iter().map(String::as_str)).map(str::to_string)
}

/// What a misspelt type name is compared with: the built-in types, and the types of the
/// enclosing namespaces and of the namespaces imported with `.*` (the names a simple name can
/// mean here, read from the namespaces a lookup reads anyway — not the workspace's every type).
fn types_in_scope(ctx: &Ctx, scope: &Scope) -> Vec<String> {
    let mut names = common_builtin_type_names();
    let wildcards = scope.imports.iter().filter_map(|i| match i {
        ImportItem::Wildcard(namespace) => Some(namespace.as_str()),
        _ => None,
    });
    for namespace in scope.namespaces.iter().map(String::as_str).chain(wildcards) {
        let members = ctx.sema.namespace_members(namespace);
        let types = members.iter().filter(|(_, defs)| matches!(defs[0].kind, DefKind::Type(_)));
        names.extend(types.map(|(name, _)| name.clone()));
    }
    names
}

/// A parameter list: unique names, types that resolve.
pub(super) fn params(ctx: &mut Ctx, scope: &Scope, list: Option<ast::ParamList>) {
    let Some(list) = list else { return };
    super::names::duplicates(ctx, list.params().filter_map(|p| p.name()), "parameter");
    for param in list.params() {
        if let Some(ty) = param.type_ref() {
            type_ref(ctx, scope, &ty);
        }
    }
}

/// `[A.B(field = value)]` before a declaration: the attribute exists and declares each field.
pub(super) fn attribute_uses(ctx: &mut Ctx, scope: &Scope, node: &SyntaxNode) {
    for list in ast::support::children::<ast::AttributeList>(node) {
        for use_ in list.uses() {
            let Some(path) = use_.path() else { continue };
            let text = path.text();
            let attribute = match ctx.sema.resolve(scope, &text).map(|d| &d.kind) {
                Some(DefKind::Type(ty)) if ty.kind == TypeKind::Attribute => ty.clone(),
                Some(other) => {
                    ctx.sink.error(
                        DiagnosticCode::InvalidAttributeUse,
                        path.syntax().text_range(),
                        format!("`{text}` is {}, not an attribute", describe(other)),
                    );
                    continue;
                }
                None => {
                    ctx.sink.error(
                        DiagnosticCode::InvalidAttributeUse,
                        path.syntax().text_range(),
                        format!("unknown attribute `{text}`"),
                    );
                    continue;
                }
            };
            let mut given = std::collections::HashSet::new();
            for arg in use_.args() {
                let Some(field) = arg.name() else { continue };
                if !given.insert(field.text()) {
                    let message = format!("attribute field `{}` is given a value more than once", field.text());
                    ctx.sink.error(DiagnosticCode::DuplicateName, field.syntax().text_range(), message);
                    continue;
                }
                let Some(declared) = attribute.fields.iter().find(|f| f.name == field.text()) else {
                    ctx.sink.error_with_suggestion(
                        DiagnosticCode::InvalidAttributeUse,
                        field.syntax().text_range(),
                        format!("attribute `{text}` has no field `{}`", field.text()),
                        closest(&field.text(), attribute.fields.iter().map(|f| f.name.as_str())),
                    );
                    continue;
                };
                let (Some(value), Some(def)) = (arg.value(), ctx.sema.resolve(scope, &text)) else { continue };
                let field_ty = ctx.sema.ty(&declared.ty, &Scope::of(def));
                let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), None);
                typing.check_value(&field_ty, &value, &format!("attribute field `{}`", field.text()));
            }
        }
    }
}
