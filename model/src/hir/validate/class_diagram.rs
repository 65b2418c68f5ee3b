//! Class diagrams: unique declarations, their type references and attribute uses, member names,
//! field initialisers and method bodies (typed), `shared` parameters only in OpenCL classes, and
//! a processor counterpart for every provider method (chapter 11.3.1).

use super::{calls, inheritance, names, objects, recursion, types, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{
        components::signature_key,
        infer::{implementing_behavior, misplaced_jumps, returns_on_every_path, BodyRole, InferenceCtx},
        items::{type_signature, InterfaceRole, TypeSignature},
        ty::Ty,
    },
    syntax::SyntaxKind,
};

pub(super) fn check(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ClassDiagram, nested: &[ast::Diagram]) {
    let names = diagram.type_decls().filter_map(|t| t.name()).chain(nested.iter().filter_map(|d| d.name()));
    names::duplicates(ctx, names, "declaration");
    for decl in diagram.type_decls() {
        if let Some(name) = decl.name() {
            let fqn = scope.qualify(&name.text());
            names::unique_across_files(ctx, &fqn, &name, "type");
            inheritance::bases(ctx, scope, &fqn, &decl);
            objects::methods(ctx, scope, &fqn, &decl);
        }
        type_decl(ctx, scope, &decl);
        if let ast::TypeDecl::Enum(e) = &decl {
            enum_values(ctx, scope, e);
        }
    }
}

fn type_decl(ctx: &mut Ctx, outer: &Scope, decl: &ast::TypeDecl) {
    let mut scope = outer.clone();
    if let ast::TypeDecl::Class(c) = decl {
        scope.type_params.extend(c.template_params().filter_map(|t| t.name()).map(|n| n.text()));
        for ty in c.extends().chain(c.implements()) {
            types::type_ref(ctx, &scope, &ty);
        }
    }
    if let ast::TypeDecl::Interface(i) = decl {
        scope.type_params.extend(i.template_params().filter_map(|t| t.name()).map(|n| n.text()));
        for ty in i.extends() {
            types::type_ref(ctx, &scope, &ty);
        }
        if i.role() == InterfaceRole::Provider {
            provider_methods(ctx, i);
        }
    }
    types::attribute_uses(ctx, &scope, decl.syntax());
    let gpu_class = match decl {
        ast::TypeDecl::Class(class) => ctx.sema.implements_opencl(&scope, class.extends().chain(class.implements())),
        _ => false,
    };
    if let (true, Some(name)) = (gpu_class, decl.name()) {
        recursion::check(ctx, &scope, &outer.qualify(&name.text()), decl);
    }
    let members: Vec<ast::Member> = decl.members().collect();
    let field_names = members.iter().filter_map(|m| match m {
        ast::Member::Field(f) => f.name(),
        ast::Member::Association(a) => a.name(),
        ast::Member::Method(_) => None,
    });
    names::duplicates(ctx, field_names, "field");
    if !gpu_class {
        let fields = members.iter().filter_map(|m| match m {
            ast::Member::Field(f) if f.has_modifier(SyntaxKind::SHARED_KW) => f.name(),
            _ => None,
        });
        for name in fields {
            ctx.sink.error(
                DiagnosticCode::SharedOutsideGpuClass,
                name.syntax().text_range(),
                "`shared` memory is only allowed in classes that implement the `OpenCL` interface".to_string(),
            );
        }
    }
    for member in &members {
        match member {
            ast::Member::Field(f) => {
                if let Some(ty) = f.type_ref() {
                    types::type_ref(ctx, &scope, &ty);
                }
                if let Some(init) = f.initializer() {
                    calls::expressions(ctx, &scope, init.syntax());
                    let owner = ctx.sema.owner_at(init.syntax());
                    let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), owner);
                    let field_ty = typing.written_type(f.type_ref());
                    let name = f.name().map(|n| n.text()).unwrap_or_default();
                    typing.check_value(&field_ty, &init, &format!("field `{name}`"));
                }
            }
            ast::Member::Association(a) => {
                if let Some(ty) = a.target() {
                    types::type_ref(ctx, &scope, &ty);
                }
                multiplicities(ctx, a);
            }
            ast::Member::Method(m) => method(ctx, &scope, m, gpu_class),
        }
    }
}

/// An association end's multiplicity `[lower .. upper]` has `lower <= upper` (UML: `*` is
/// unbounded; `[5 .. 1]` admits no number of objects).
fn multiplicities(ctx: &mut Ctx, association: &ast::Association) {
    for multiplicity in association.own_multiplicity().into_iter().chain(association.target_multiplicity()) {
        let (Some(lower), Some(upper)) = multiplicity.bounds() else { continue };
        let (Ok(low), Ok(high)) = (lower.parse::<u64>(), upper.parse::<u64>()) else { continue };
        if low > high {
            ctx.sink.error_with_replacement(
                DiagnosticCode::InvertedMultiplicity,
                multiplicity.syntax().text_range(),
                format!(
                    "multiplicity `[{lower} .. {upper}]` admits no number of objects: write `[{upper} .. {lower}]`"
                ),
                &format!("[{upper} .. {lower}]"),
            );
        }
    }
}

/// An enum's values: unique names, integer values (`A = 1`) of names that exist.
fn enum_values(ctx: &mut Ctx, scope: &Scope, decl: &ast::Enum) {
    names::duplicates(ctx, decl.values().filter_map(|v| v.name()), "enum value");
    for value in decl.values().filter_map(|v| v.value()) {
        let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), None);
        typing.check_value(&Ty::Int, &value, "an enum value");
    }
}

fn method(ctx: &mut Ctx, scope: &Scope, method: &ast::Method, gpu_class: bool) {
    if let Some(ty) = method.return_type() {
        types::type_ref(ctx, scope, &ty);
    }
    types::params(ctx, scope, method.param_list());
    if !gpu_class {
        shared_params(ctx, method);
    }
    if let Some(body) = method.body() {
        calls::expressions(ctx, scope, body.syntax());
        names::duplicate_locals(ctx, body.syntax());
        for (range, message) in misplaced_jumps(body.syntax(), false, "the method") {
            ctx.sink.error(DiagnosticCode::MisplacedJump, range, message);
        }
        let owner = ctx.sema.owner_at(body.syntax());
        let name = method.name().map(|n| n.text()).unwrap_or_default();
        let cut_short = ctx.syntax_error_in(body.syntax().text_range());
        let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), owner);
        if method.has_modifier(SyntaxKind::GLOBAL_KW) {
            typing.set_role(BodyRole::GlobalMethod);
        }
        for param in method.params() {
            if let Some(name) = param.name() {
                typing.declare(name.text(), param.type_ref());
            }
        }
        typing.expect_returns(name.clone(), method.return_type());
        typing.check(body.syntax());
        let returns_a_value = method.return_type().is_some_and(|t| t.builtin().is_none_or(|b| b.text() != "void"));
        // A syntax error in the body may have cut it short: its `return` is told once it is fixed.
        if returns_a_value && !returns_on_every_path(body.syntax()) && !cut_short {
            if let Some(call) = implementing_behavior(&body) {
                typing.check_implementing_behavior(&call);
                return;
            }
            let end = body.syntax().last_token().map_or_else(|| body.syntax().text_range(), |t| t.text_range());
            ctx.sink.error(
                DiagnosticCode::MissingReturn,
                end,
                format!("`{name}` returns a value, but its body can end without `return`"),
            );
        }
    }
}

/// `shared` memory parameters only in classes that implement `OpenCL` (chapter 10.3.2.3).
fn shared_params(ctx: &mut Ctx, method: &ast::Method) {
    for param in method.params() {
        if param.has_modifier(SyntaxKind::SHARED_KW) {
            let range = param.name().map_or_else(|| param.syntax().text_range(), |n| n.syntax().text_range());
            ctx.sink.error(
                DiagnosticCode::SharedOutsideGpuClass,
                range,
                "`shared` memory parameters are only allowed in classes that implement the `OpenCL` interface"
                    .to_string(),
            );
        }
    }
}

/// A provider interface's `provideX(…)` methods need a processor interface with the
/// corresponding `processX(…)` signature (chapter 11.3.1).
fn provider_methods(ctx: &mut Ctx, interface: &ast::Interface) {
    let processors = ctx.sema.processor_signatures();
    for member in interface.members() {
        let ast::Member::Method(method) = member else { continue };
        let Some(name) = method.name() else { continue };
        let text = name.text();
        let Some(suffix) = text.strip_prefix("provide") else { continue };
        let params: Vec<TypeSignature> = method.params().map(|p| type_signature(p.type_ref())).collect();
        let key = signature_key(suffix, &params);
        if !processors.contains(&key) {
            ctx.sink.error(
                DiagnosticCode::MissingProcessorSignature,
                name.syntax().text_range(),
                format!("provider method `{text}` has no processor counterpart: declare `process{key}` in a processor interface"),
            );
        }
    }
}
