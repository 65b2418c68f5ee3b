//! What statements and expressions name: types (`var T x`, `new T(…)`, `x as T`), activity
//! diagrams (`call behavior X(…)`, with their arity) and class methods (`call Class::m(…)`).

use super::{unresolved_message, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode},
    hir::{definitions::DefKind, diagnostics::arguments, semantics::describe},
    syntax::{SyntaxKind, SyntaxNode},
};

/// The types and behaviors named anywhere inside `node`.
pub(super) fn expressions(ctx: &mut Ctx, scope: &Scope, node: &SyntaxNode) {
    use SyntaxKind::{CALL_BEHAVIOR_EXPR, CALL_METHOD_EXPR, TYPE_REF};
    if !ast::owns_at_least(node, 1, |k| matches!(k, TYPE_REF | CALL_BEHAVIOR_EXPR | CALL_METHOD_EXPR)) {
        return;
    }
    for descendant in ast::own_descendants(node) {
        match descendant.kind() {
            SyntaxKind::TYPE_REF if descendant.parent().is_some_and(|p| p.kind() != SyntaxKind::TYPE_ARGS) => {
                if let Some(ty) = ast::TypeRef::cast(descendant) {
                    super::types::type_ref(ctx, scope, &ty);
                }
            }
            SyntaxKind::CALL_BEHAVIOR_EXPR => {
                if let Some(call) = ast::CallBehaviorExpr::cast(descendant) {
                    call_behavior(ctx, scope, &call);
                }
            }
            SyntaxKind::CALL_METHOD_EXPR => {
                if let Some(call) = ast::CallMethodExpr::cast(descendant) {
                    call_method(ctx, scope, &call);
                }
            }
            _ => {}
        }
    }
}

/// `call behavior X(…)`: X is an activity diagram, called with as many arguments as it takes.
fn call_behavior(ctx: &mut Ctx, scope: &Scope, call: &ast::CallBehaviorExpr) {
    let Some(path) = call.behavior() else { return };
    let text = path.text();
    let range = path.syntax().text_range();
    match ctx.sema.resolve(scope, &text).map(|d| &d.kind) {
        Some(DefKind::Activity(signature)) => {
            let given = call.args().count();
            let expected = signature.params.len();
            // Without an argument list the diagram's parameters are taken from the caller.
            if call.arg_list().is_some() && given != expected {
                ctx.sink.error(
                    DiagnosticCode::TransitionArity,
                    range,
                    format!("activity diagram `{text}` takes {}, {given} given", arguments(expected)),
                );
            }
        }
        Some(other) => ctx.sink.error(
            DiagnosticCode::UnresolvedBehavior,
            range,
            format!("`call behavior` needs an activity diagram, but `{text}` is {}", describe(other)),
        ),
        None => ctx.sink.error(DiagnosticCode::UnresolvedBehavior, range, format!("unknown activity diagram `{text}`")),
    }
}

/// `call Class::method(…)`: the class exists and has (or inherits) the method.
fn call_method(ctx: &mut Ctx, scope: &Scope, call: &ast::CallMethodExpr) {
    let (Some(class), Some(method)) = (call.class(), call.method()) else { return };
    let class_text = class.text();
    let Some(def) = ctx.sema.resolve(scope, &class_text) else {
        let message = unresolved_message(ctx, &class_text, "class", format!("unknown class `{class_text}`"));
        ctx.sink.error(DiagnosticCode::UnresolvedType, class.syntax().text_range(), message);
        return;
    };
    if !matches!(def.kind, DefKind::Type(_)) {
        ctx.sink.error(
            DiagnosticCode::UnresolvedType,
            class.syntax().text_range(),
            format!("`{class_text}` is {}, not a class", describe(&def.kind)),
        );
        return;
    }
    let name = method.text();
    if !ctx.sema.has_method(&def.fqn, &name) {
        ctx.sink.error(
            DiagnosticCode::UnresolvedMethod,
            method.syntax().text_range(),
            format!("`{}` has no method `{name}`", def.fqn),
        );
    }
}
