//! Component diagrams (chapter 11.3.2–11.3.3): components built on classes, unique ports,
//! connectors typed by an interface of their role, and connections that join a provider and a
//! processor connector of the diagram.

use std::collections::HashMap;

use super::{names, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasEnds, HasName},
    hir::{
        definitions::DefKind,
        items::{ConnectorRole, InterfaceRole, TypeKind},
        semantics::describe,
    },
};

pub(super) fn check(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ComponentDiagram) {
    let mut components = Vec::new();
    let mut stack: Vec<ast::Component> = diagram.components().collect();
    while let Some(component) = stack.pop() {
        stack.extend(component.components());
        components.push(component);
    }
    // Every port.connector of the diagram, for connection ends.
    let mut connectors: HashMap<String, ConnectorRole> = HashMap::new();
    for component in &components {
        if let Some(class) = component.class() {
            component_class(ctx, scope, &class);
        }
        names::duplicates(ctx, component.ports().filter_map(|p| p.name()), "port");
        for port in component.ports() {
            let Some(port_name) = port.name().map(|n| n.text()) else { continue };
            for connector in port.connectors() {
                let (Some(role), Some(name), Some(interface)) =
                    (connector.role(), connector.name(), connector.interface())
                else {
                    continue;
                };
                connectors.insert(format!("{port_name}.{}", name.text()), role);
                connector_interface(ctx, scope, role, &interface);
            }
        }
    }
    for component in &components {
        for connection in component.connections() {
            let mut roles = Vec::new();
            for end in [connection.source(), connection.target()].into_iter().flatten() {
                match connectors.get(&end.text()) {
                    Some(&role) => roles.push(role),
                    None => ctx.sink.error(
                        DiagnosticCode::UnresolvedConnector,
                        end.syntax().text_range(),
                        format!("no connector `{}` (`port.connector`) in this component diagram", end.text()),
                    ),
                }
            }
            if let [source, target] = roles[..] {
                if source == target {
                    ctx.sink.error(
                        DiagnosticCode::InvalidConnection,
                        connection.syntax().text_range(),
                        format!("a connection joins a provider and a processor, not two {}s", role_name(source)),
                    );
                }
            }
        }
    }
}

/// A component is built on a class.
fn component_class(ctx: &mut Ctx, scope: &Scope, class: &ast::Path) {
    let text = class.text();
    match ctx.sema.resolve(scope, &text).map(|d| &d.kind) {
        Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Class(_)) => {}
        Some(other) => ctx.sink.error(
            DiagnosticCode::InvalidComponent,
            class.syntax().text_range(),
            format!("a component is built on a class, but `{text}` is {}", describe(other)),
        ),
        None => ctx.sink.error(
            DiagnosticCode::InvalidComponent,
            class.syntax().text_range(),
            format!("unknown component class `{text}`"),
        ),
    }
}

/// A connector's interface is an interface of the connector's role.
fn connector_interface(ctx: &mut Ctx, scope: &Scope, role: ConnectorRole, interface: &ast::Path) {
    let text = interface.text();
    let range = interface.syntax().text_range();
    let expected = match role {
        ConnectorRole::Provider => InterfaceRole::Provider,
        ConnectorRole::Processor => InterfaceRole::Processor,
    };
    match ctx.sema.resolve(scope, &text).map(|d| &d.kind) {
        Some(DefKind::Type(ty)) if ty.kind == TypeKind::Interface(expected) => {}
        Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Interface(_)) => ctx.sink.error(
            DiagnosticCode::InvalidConnectorInterface,
            range,
            format!("a {0} connector needs a `{0}` interface; `{text}` is not one", role_name(role)),
        ),
        Some(other) => ctx.sink.error(
            DiagnosticCode::InvalidConnectorInterface,
            range,
            format!("`{text}` is {}, not an interface", describe(other)),
        ),
        None => ctx.sink.error(DiagnosticCode::InvalidConnectorInterface, range, format!("unknown interface `{text}`")),
    }
}

/// The message-ready name of a connector role.
fn role_name(role: ConnectorRole) -> &'static str {
    match role {
        ConnectorRole::Provider => "provider",
        ConnectorRole::Processor => "processor",
    }
}
