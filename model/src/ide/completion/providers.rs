//! The providers of completion, one for each kind of place, tried in order: the first that
//! applies at the cursor answers ([`ALL`]); where none does, the declaration level's snippets.

use std::collections::BTreeSet;

use crate::{
    ast::{self, AstNode, HasName},
    hir::{
        items::{InterfaceRole, TypeKind},
        DefKind, Scope,
    },
    syntax::{SyntaxKind::*, SyntaxNode},
};

use super::{
    context::{skip_trivia_back, Ctx},
    finish, item,
    names::{locals_in_scope, type_members, with_types},
    snippet, CompletionItem, CompletionKind, Completions,
};

/// A provider: its proposals where it applies, `None` elsewhere.
type Provider = fn(&Ctx) -> Option<Completions>;

/// Every provider, in the order they are asked.
pub(super) const ALL: [Provider; 8] =
    [node_names, connectors, receiver_members, namespace_members, port_interfaces, instance_fields, types, body];

/// `=> |`: the nodes of this activity diagram.
fn node_names(ctx: &Ctx) -> Option<Completions> {
    if ctx.before_kind != Some(FAT_ARROW) {
        return None;
    }
    let mut items = Vec::new();
    if let Some(diagram) = ctx.at.ancestors().find_map(ast::ActivityDiagram::cast) {
        for node in diagram.syntax().descendants().filter_map(ast::ActivityNode::cast) {
            if let Some(name) = node.name() {
                let detail = format!("{:?}", node.kind()).to_lowercase();
                items.push(item(name.text(), CompletionKind::Node, Some(detail)));
            }
        }
    }
    Some(finish(items))
}

/// Bindings and connections after `source`, `target` or a `.`: port instances, ports and
/// connectors.
fn connectors(ctx: &Ctx) -> Option<Completions> {
    let link = ctx.at.ancestors().find(|a| matches!(a.kind(), BINDING | CONNECTION))?;
    if !matches!(ctx.before_kind, Some(SOURCE_KW | TARGET_KW | DOT)) {
        return None;
    }
    let mut items = Vec::new();
    connector_candidates(&link, ctx.path_before_dot().as_deref(), &mut items);
    Some(finish(items))
}

/// `receiver.|` in an expression: the fields and methods of the receiver's declared type (not a
/// typed receiver: `Enum.Value`, `Diagram.Type` are qualified names, [`namespace_members`]).
fn receiver_members(ctx: &Ctx) -> Option<Completions> {
    let dot = ctx.before.as_ref().filter(|t| t.kind() == DOT)?;
    if dot.parent().is_none_or(|p| p.kind() != MEMBER_EXPR) {
        return None;
    }
    let receiver = dot.prev_token().and_then(|t| skip_trivia_back(&t)).filter(|r| r.kind() == IDENT)?;
    let resolved =
        crate::ide::navigation::type_of_name_at(ctx.db, ctx.workspace, ctx.file, receiver.text_range().start())?;
    let def = resolved.qualified.as_deref().and_then(|fqn| ctx.sema.definition(fqn))?;
    let mut items = Vec::new();
    type_members(&ctx.sema, def, &mut items);
    (!items.is_empty()).then(|| finish(items))
}

/// `A.B.|` in a qualified name: what the namespace contains, and an enum's values.
fn namespace_members(ctx: &Ctx) -> Option<Completions> {
    let prefix = ctx.path_before_dot()?;
    let sema = &ctx.sema;
    let namespace = sema.resolve(&Scope::at(&ctx.at), &prefix).map(|d| d.fqn.clone()).unwrap_or(prefix);
    let children: BTreeSet<(String, bool)> = sema
        .namespace_members(&namespace)
        .iter()
        .map(|(name, defs)| (name.clone(), matches!(defs[0].kind, DefKind::Type(_))))
        .collect();
    let mut items = Vec::new();
    for (name, is_type) in children {
        let kind = if is_type { CompletionKind::Type } else { CompletionKind::Namespace };
        items.push(item(name, kind, Some(namespace.clone())));
    }
    if let Some(DefKind::Type(ty)) = sema.definition(&namespace).map(|d| &d.kind) {
        for value in &ty.enum_values {
            items.push(item(value.clone(), CompletionKind::EnumValue, Some(namespace.clone())));
        }
    }
    Some(finish(items))
}

/// `provider name : |` in a port: interfaces of that role.
fn port_interfaces(ctx: &Ctx) -> Option<Completions> {
    if ctx.before_kind != Some(COLON) || !ctx.at.ancestors().any(|a| a.kind() == CONNECTOR || a.kind() == PORT) {
        return None;
    }
    let role = ctx.at.ancestors().find_map(ast::Connector::cast).and_then(|c| c.role());
    let mut items = Vec::new();
    for defs in ctx.sema.def_map().definitions.values() {
        let def = &defs[0];
        if let DefKind::Type(ty) = &def.kind {
            let fits = matches!(
                (ty.kind, role),
                (TypeKind::Interface(InterfaceRole::Provider), Some(ast::ConnectorRole::Provider))
                    | (TypeKind::Interface(InterfaceRole::Processor), Some(ast::ConnectorRole::Processor))
                    | (TypeKind::Interface(_), None)
            );
            if fits {
                items.push(item(def.fqn.clone(), CompletionKind::Interface, None));
            }
        }
    }
    Some(finish(items))
}

/// `X instantiates T (|`: the component class's fields.
fn instance_fields(ctx: &Ctx) -> Option<Completions> {
    let instance = ctx.at.ancestors().find_map(ast::ComponentInstance::cast)?;
    let in_args = ctx.at.ancestors().any(|a| a.kind() == NAMED_ARG_LIST);
    if !in_args || !matches!(ctx.before_kind, Some(L_PAREN | COMMA)) {
        return None;
    }
    let mut items = Vec::new();
    if let Some(def) = instance.component().and_then(|p| ctx.sema.resolve(&Scope::at(&ctx.at), &p.text())) {
        if let DefKind::Type(ty) = &def.kind {
            for field in &ty.fields {
                let mut it = item(field.name.clone(), CompletionKind::Field, Some(def.fqn.clone()));
                it.snippet = Some(format!("{} = $1", field.name));
                items.push(it);
            }
        }
    }
    Some(finish(items))
}

/// Type positions: after a visibility or qualifier, in a parameter list, after `var`, `new`,
/// `as`, `extends`, `implements`, `owner`, `instantiates`, `:` of an association.
fn types(ctx: &Ctx) -> Option<Completions> {
    let type_position = matches!(
        ctx.before_kind,
        Some(
            PUBLIC_KW
                | PROTECTED_KW
                | PRIVATE_KW
                | VAR_KW
                | CONST_KW
                | REF_KW
                | NEW_KW
                | AS_KW
                | EXTENDS_KW
                | IMPLEMENTS_KW
                | UNSIGNED_KW
                | OWNER_KW
                | INSTANTIATES_KW
                | L_ANGLE
        )
    ) || (matches!(ctx.before_kind, Some(L_PAREN | COMMA))
        && ctx.at.ancestors().any(|a| a.kind() == PARAM_LIST))
        || ctx.at.ancestors().any(|a| a.kind() == TYPE_REF);
    type_position.then(|| with_types(&ctx.sema, &ctx.at, &ctx.typed, Vec::new()))
}

/// Inside a node or method body: statements, locals, the owner's members.
fn body(ctx: &Ctx) -> Option<Completions> {
    let body = ctx.at.ancestors().find(|a| matches!(a.kind(), NODE_BODY | BLOCK))?;
    let mut items: Vec<CompletionItem> = Vec::new();
    for keyword in ["var", "const", "if", "for", "loop", "do", "switch", "return", "call behavior", "new"] {
        items.push(item(keyword, CompletionKind::Keyword, None));
    }
    if body.kind() == NODE_BODY || body.ancestors().any(|a| a.kind() == NODE_BODY) {
        items.push(snippet("=> transition", "=> ${1:target};", "transition to a node"));
        items.push(snippet("[guard] => transition", "[${1:condition}] => ${2:target};", "guarded transition"));
    }
    locals_in_scope(&body, &mut items);
    if let Some(owner) = ctx.sema.owner_at(&ctx.at) {
        type_members(&ctx.sema, owner, &mut items);
    }
    Some(finish(items))
}

/// What may follow in a connection (`port.connector`) or binding
/// (`portInstance.connector`, `instance.portInstance.connector`) after `prefix`.
fn connector_candidates(link: &SyntaxNode, prefix: Option<&str>, items: &mut Vec<CompletionItem>) {
    let segments: Vec<&str> = prefix.map(|p| p.split('.').collect()).unwrap_or_default();
    if link.kind() == CONNECTION {
        let Some(diagram) = link.ancestors().find_map(ast::ComponentDiagram::cast) else { return };
        for port in diagram.syntax().descendants().filter_map(ast::Port::cast) {
            let Some(name) = port.name().map(|n| n.text()) else { continue };
            match segments.as_slice() {
                [] => items.push(item(name, CompletionKind::Interface, Some("port".into()))),
                [p] if *p == name => {
                    for c in port.connectors().filter_map(|c| c.name()) {
                        items.push(item(c.text(), CompletionKind::Field, Some(format!("connector of {name}"))));
                    }
                }
                _ => {}
            }
        }
        return;
    }
    let Some(diagram) = link.ancestors().find_map(ast::ComponentInstanceDiagram::cast) else { return };
    let own = link.ancestors().find_map(ast::ComponentInstance::cast);
    let port_instances =
        |instance: &ast::ComponentInstance| -> Vec<ast::PortInstance> { instance.port_instances().collect() };
    let connectors_of = |pi: &ast::PortInstance, items: &mut Vec<CompletionItem>| {
        for c in pi.connectors().filter_map(|c| c.name()) {
            items.push(item(c.text(), CompletionKind::Field, Some("connector".into())));
        }
    };
    match segments.as_slice() {
        [] => {
            if let Some(own) = &own {
                for pi in port_instances(own).iter().filter_map(|p| p.name()) {
                    items.push(item(pi.text(), CompletionKind::Interface, Some("port instance".into())));
                }
            }
            for instance in diagram.instances().filter_map(|i| i.name()) {
                items.push(item(instance.text(), CompletionKind::Variable, Some("instance".into())));
            }
        }
        [first] => {
            if let Some(pi) = own.iter().flat_map(port_instances).find(|p| p.name().is_some_and(|n| n.text() == *first))
            {
                connectors_of(&pi, items);
            }
            if let Some(instance) = diagram.instances().find(|i| i.name().is_some_and(|n| n.text() == *first)) {
                for pi in port_instances(&instance).iter().filter_map(|p| p.name()) {
                    items.push(item(pi.text(), CompletionKind::Interface, Some("port instance".into())));
                }
            }
        }
        [instance, port_instance] => {
            if let Some(instance) = diagram.instances().find(|i| i.name().is_some_and(|n| n.text() == *instance)) {
                if let Some(pi) =
                    instance.port_instances().find(|p| p.name().is_some_and(|n| n.text() == *port_instance))
                {
                    connectors_of(&pi, items);
                }
            }
        }
        _ => {}
    }
}
