//! Activity diagrams: owners that are classes, parameters and variables, unique swimlanes and
//! nodes, loopWindow headers, and node bodies (typed against the diagram's locals, the node's
//! header and the owner's members); then the control flow (`flow`).

use std::collections::HashMap;

use super::{calls, flow, names, types, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{
        definitions::DefKind,
        infer::{diagram_locals, header_declarations, misplaced_jumps, BodyRole, InferenceCtx},
        items::TypeKind,
        semantics::describe,
        ty::Ty,
    },
    syntax::SyntaxKind,
};

pub(super) fn check(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ActivityDiagram) {
    types::params(ctx, scope, diagram.param_list());
    if let Some(owner) = diagram.owner() {
        owner_is_a_class(ctx, scope, &owner);
    }
    let variable_names =
        diagram.variables().filter_map(|v| v.name()).chain(diagram.var_decls().filter_map(|v| v.name()));
    names::duplicates(ctx, variable_names, "variable");
    variables(ctx, scope, diagram);
    shared_params(ctx, scope, diagram);
    let mut nodes: Vec<ast::ActivityNode> = Vec::new();
    let mut owners = Vec::new();
    names::duplicates(ctx, diagram.swimlanes().filter_map(|s| s.name()), "swimlane");
    for lane in diagram.swimlanes() {
        if let Some(owner) = lane.owner() {
            owner_is_a_class(ctx, scope, &owner);
        }
        let owner = ctx.sema.activity_owner(scope, diagram, Some(&lane));
        nodes.extend(lane.nodes().flat_map(|n| n.and_nested()));
        owners.resize(nodes.len(), owner);
    }
    let owner = ctx.sema.activity_owner(scope, diagram, None);
    nodes.extend(diagram.nodes().flat_map(|n| n.and_nested()));
    owners.resize(nodes.len(), owner);
    names::duplicates(ctx, nodes.iter().filter_map(|n| n.name()), "node");
    let locals = diagram_locals(diagram);
    let by_name: HashMap<String, ast::ActivityNode> =
        nodes.iter().filter_map(|n| Some((n.name()?.text(), n.clone()))).collect();
    let mut results: Vec<(ast::ActivityNode, Option<Ty>)> = Vec::new();
    for (node, &owner) in nodes.iter().zip(&owners) {
        if node.kind() == ast::NodeKind::LoopWindow {
            loop_window_sections(ctx, node);
        }
        let container = node.container();
        if let Some(container) = &container {
            nested_in(ctx, node, container);
        }
        types::params(ctx, scope, node.param_list());
        let body = node.body();
        let value = node.return_value();
        for part in body.iter().map(|b| b.syntax()).chain(value.iter().map(|v| v.syntax())) {
            calls::expressions(ctx, scope, part);
        }
        if let Some(body) = &body {
            names::duplicate_locals(ctx, body.syntax());
            let in_loop = matches!(node.kind(), ast::NodeKind::Loop | ast::NodeKind::LoopWindow);
            for (range, message) in misplaced_jumps(body.syntax(), in_loop, "the node") {
                ctx.sink.error(DiagnosticCode::MisplacedJump, range, message);
            }
        }
        let header = node.loop_header();
        let mut value_ty = None;
        // A node with no body, header or value (`final f;`, `join j;`) has nothing to type.
        if body.is_some() || header.is_some() || value.is_some() {
            let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), owner);
            if matches!(node.kind(), ast::NodeKind::Calc | ast::NodeKind::CalcRange) {
                typing.set_role(BodyRole::KernelLaunch);
            }
            for (name, ty) in locals.iter().cloned().chain(header_declarations(node)) {
                typing.declare(name, ty);
            }
            typing.expect_transitions_to(&by_name);
            if let Some(header) = &header {
                typing.check_loop_header(header);
            }
            if let Some(body) = &body {
                typing.check(body.syntax());
            }
            value_ty = value.map(|v| typing.infer(&v));
        }
        if node.kind() == ast::NodeKind::Final && container.is_none() {
            results.push((node.clone(), value_ty));
        }
    }
    final_results(ctx, &results);
    flow::check(ctx, diagram, &nodes);
}

/// A node nested in `container` (Sec. 9.2.2.3): only action, decision, loop and loopWindow
/// nodes hold nodes (loop and conditional nodes, and actions as UML's structured nodes) —
/// told once, at the first node a container holds; a nested final node returns no value (it
/// ends its container's flow, not the diagram).
fn nested_in(ctx: &mut Ctx, node: &ast::ActivityNode, container: &ast::ActivityNode) {
    let first = container.nested_nodes().next().is_some_and(|n| n.syntax() == node.syntax());
    if !container.may_hold_nodes() && first {
        let range = node.name().map_or_else(|| node.syntax().text_range(), |n| n.syntax().text_range());
        ctx.sink.error(
            DiagnosticCode::NotAContainer,
            range,
            format!(
                "a {} node holds no nodes: only action, decision, loop and loopWindow nodes do (Sec. 9.2.2.3); move this node out and connect it with transitions",
                container.kind().keyword()
            ),
        );
    }
    if let Some(value) = node.return_value() {
        ctx.sink.error(
            DiagnosticCode::NotAContainer,
            value.syntax().text_range(),
            "a nested final node ends its container's flow, not the diagram: it returns no value".to_string(),
        );
    }
}

/// The variable section: types that exist, initial values typed against the diagram's
/// parameters and variables (and the diagram's owner's members) that fit their variables.
fn variables(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ActivityDiagram) {
    for variable in diagram.variables() {
        if let Some(ty) = variable.type_ref() {
            types::type_ref(ctx, scope, &ty);
        }
        if let Some(init) = variable.initializer() {
            calls::expressions(ctx, scope, init.syntax());
        }
    }
    for decl in diagram.var_decls() {
        calls::expressions(ctx, scope, decl.syntax());
    }
    let initialised = diagram.variables().any(|v| v.initializer().is_some());
    if !initialised && diagram.var_decls().next().is_none() {
        return;
    }
    let owner = ctx.sema.activity_owner(scope, diagram, None);
    let mut typing = InferenceCtx::new(ctx.sema, &mut ctx.sink, scope.clone(), owner);
    for (name, ty) in diagram_locals(diagram) {
        typing.declare(name, ty);
    }
    for variable in diagram.variables() {
        let Some(init) = variable.initializer() else { continue };
        let ty = typing.written_type(variable.type_ref());
        let name = variable.name().map(|n| n.text()).unwrap_or_default();
        typing.check_value(&ty, &init, &format!("`{name}`"));
    }
    for decl in diagram.var_decls() {
        typing.check(decl.syntax());
    }
}

/// The final nodes of a diagram end it alike (`final f return expr`, grammar of appendix B): if
/// one returns a value, every one does, and the values are of one type (the first's) — what
/// `call behavior` of the diagram yields.
fn final_results(ctx: &mut Ctx, results: &[(ast::ActivityNode, Option<Ty>)]) {
    let name = |node: &ast::ActivityNode| node.name().map(|n| n.text()).unwrap_or_default();
    let Some((first, first_ty)) = results.iter().find_map(|(node, ty)| Some((node, ty.as_ref()?))) else { return };
    let sema = ctx.sema;
    let returned = match first_ty {
        Ty::Unknown => "a value".to_string(),
        ty => format!("`{ty}`"),
    };
    for (node, ty) in results {
        let range = node.name().map_or_else(|| node.syntax().text_range(), |n| n.syntax().text_range());
        match ty {
            None => ctx.sink.error(
                DiagnosticCode::ReturnType,
                range,
                format!(
                    "final node `{}` returns nothing, but `{}` returns {returned}: write `final {} return …` \
                     (the final nodes of a diagram return values of one type)",
                    name(node),
                    name(first),
                    name(node)
                ),
            ),
            Some(ty) if !ty.assignable_to(first_ty, &mut |a, b| sema.is_subtype(a, b)) => {
                let value = node.return_value().map_or(range, |v| v.syntax().text_range());
                ctx.sink.error(
                    DiagnosticCode::ReturnType,
                    value,
                    format!(
                        "final node `{}` returns `{ty}`, but `{}` returns `{first_ty}` (the final nodes of a diagram \
                         return values of one type)",
                        name(node),
                        name(first)
                    ),
                );
            }
            Some(_) => {}
        }
    }
}

/// `shared` memory parameters only in diagrams owned by a class that implements `OpenCL`
/// (Sec. 10.2.1.5, 10.3.2.3).
fn shared_params(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ActivityDiagram) {
    let shared: Vec<ast::Param> = diagram.params().filter(|p| p.has_modifier(SyntaxKind::SHARED_KW)).collect();
    if shared.is_empty() {
        return;
    }
    let owners = diagram.owner().into_iter().chain(diagram.swimlanes().filter_map(|l| l.owner()));
    let sema = ctx.sema;
    if owners.filter_map(|o| sema.resolve(scope, &o.text())).any(|owner| sema.is_gpu_class(owner)) {
        return;
    }
    for param in shared {
        let range = param.name().map_or_else(|| param.syntax().text_range(), |n| n.syntax().text_range());
        ctx.sink.error(
            DiagnosticCode::SharedOutsideGpuClass,
            range,
            "`shared` memory parameters are only allowed in diagrams owned by a class that implements `OpenCL`"
                .to_string(),
        );
    }
}

/// A diagram's or swimlane's owner names a class.
fn owner_is_a_class(ctx: &mut Ctx, scope: &Scope, path: &ast::Path) {
    let text = path.text();
    let range = path.syntax().text_range();
    match ctx.sema.resolve(scope, &text).map(|d| &d.kind) {
        Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Class(_)) => {}
        Some(other) => ctx.sink.error(
            DiagnosticCode::OwnerNotAClass,
            range,
            format!("the owner `{text}` is {}; an owner must be a class", describe(other)),
        ),
        None => ctx.sink.error(DiagnosticCode::UnresolvedOwner, range, format!("unknown owner class `{text}`")),
    }
}

/// A loopWindow header has as many tests and increments as setups.
fn loop_window_sections(ctx: &mut Ctx, node: &ast::ActivityNode) {
    let Some(header) = node.loop_header() else { return };
    let counts: Vec<usize> = header.sections().map(|s| s.parts().count()).collect();
    if counts.len() != 3 || counts.windows(2).any(|w| w[0] != w[1]) {
        ctx.sink.error(
            DiagnosticCode::LoopWindowMismatch,
            header.syntax().text_range(),
            format!(
                "a loopWindow needs as many tests and increments as setups (setup; test; increment), found {}",
                counts.iter().map(|c| c.to_string()).collect::<Vec<_>>().join("; ")
            ),
        );
    }
}
