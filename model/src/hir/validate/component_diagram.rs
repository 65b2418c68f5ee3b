//! Component diagrams (chapter 11.3.2–11.3.3): components built on classes of their kind,
//! unique ports and connection names, connectors typed by an interface of their role (sources
//! only provide, sinks only process), and connections that join a provider and a processor
//! connector of the diagram whose interfaces correspond (Sec. 11.3.1).

use std::collections::HashMap;

use super::{names, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasEnds, HasName},
    hir::{
        components::signature_key,
        definitions::{DefKind, Definition},
        items::{ClassKind, ConnectorRole, InterfaceRole, TypeKind},
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
    components.sort_by_key(|c| c.syntax().text_range().start());
    // Every port.connector of the diagram, for connection ends: its role and interface.
    let mut connectors: HashMap<String, (ConnectorRole, String)> = HashMap::new();
    let mut declared = std::collections::HashSet::new();
    for component in &components {
        let class = component_class(ctx, scope, component);
        if let (Some(class), Some(path)) = (class, component.class()) {
            if !declared.insert(class.fqn.clone()) {
                ctx.sink.error(
                    DiagnosticCode::DuplicateName,
                    path.syntax().text_range(),
                    format!("component `{}` is declared twice in this diagram: give its ports and connections in one declaration", class.fqn),
                );
            }
        }
        names::duplicates(ctx, component.ports().filter_map(|p| p.name()), "port");
        names::duplicates(ctx, component.connections().filter_map(|c| c.connection_name()), "connection");
        for port in component.ports() {
            let Some(port_name) = port.name().map(|n| n.text()) else { continue };
            names::duplicates(ctx, port.connectors().filter_map(|c| c.name()), "connector");
            for connector in port.connectors() {
                let (Some(role), Some(name), Some(interface)) =
                    (connector.role(), connector.name(), connector.interface())
                else {
                    continue;
                };
                // A second connector of one name is reported (E0205): the first one stays.
                connectors.entry(format!("{port_name}.{}", name.text())).or_insert((role, interface.text()));
                let fits = connector_interface(ctx, scope, role, &interface);
                role_of_kind(ctx, component.kind(), role, &name);
                if let (Some(class), Some(interface_def)) = (class, fits) {
                    implemented_by(ctx, &class.fqn, interface_def, &interface);
                }
            }
        }
    }
    for component in &components {
        for connection in component.connections() {
            let mut ends = Vec::new();
            for end in [connection.source(), connection.target()].into_iter().flatten() {
                match connectors.get(&end.text()) {
                    Some(connector) => ends.push(connector.clone()),
                    None => ctx.sink.error(
                        DiagnosticCode::UnresolvedConnector,
                        end.syntax().text_range(),
                        format!("no connector `{}` (`port.connector`) in this component diagram", end.text()),
                    ),
                }
            }
            let [(source, source_interface), (target, target_interface)] = &ends[..] else { continue };
            if source == target {
                ctx.sink.error(
                    DiagnosticCode::InvalidConnection,
                    connection.syntax().text_range(),
                    format!("a connection joins a provider and a processor, not two {}s", source.keyword()),
                );
                continue;
            }
            let (provider, processor) = match source {
                ConnectorRole::Provider => (source_interface, target_interface),
                ConnectorRole::Processor => (target_interface, source_interface),
            };
            corresponding_interfaces(ctx, scope, &connection, provider, processor);
        }
    }
}

/// The component's class implements the interfaces of its ports (Sec. 11.3.2.1: "interfaces by
/// inheritance", the default). One it does not implement is an anonymous interface, which the
/// text allows but whose methods the class then cannot call directly: a warning.
fn implemented_by(ctx: &mut Ctx, class: &str, def: &Definition, interface: &ast::Path) {
    if ctx.sema.is_subtype(class, &def.fqn) {
        return;
    }
    let simple = |fqn: &str| fqn.rsplit('.').next().unwrap_or(fqn).to_string();
    ctx.sink.warn(
        DiagnosticCode::InterfaceNotImplemented,
        interface.syntax().text_range(),
        format!(
            "`{}` does not implement `{}`: the port uses it as an anonymous interface (Sec. 11.3.2.1); \
             add `implements {}` to the class to call its methods directly",
            simple(class),
            simple(&def.fqn),
            simple(&def.fqn)
        ),
    );
}

/// A source only provides data and a sink only processes it (Sec. 11.3.2).
fn role_of_kind(ctx: &mut Ctx, kind: ClassKind, role: ConnectorRole, name: &ast::Name) {
    let wrong = match (kind, role) {
        (ClassKind::Source, ConnectorRole::Processor) => "a source only provides data: it has no processor connector",
        (ClassKind::Sink, ConnectorRole::Provider) => "a sink only processes data: it has no provider connector",
        _ => return,
    };
    ctx.sink.error(DiagnosticCode::InvalidConnectorInterface, name.syntax().text_range(), wrong.to_string());
}

/// The provider and the processor of a connection form a pair (Sec. 11.3.1): every
/// `provideX(…)` of the provider interface has its `processX(…)` in the processor interface.
fn corresponding_interfaces(
    ctx: &mut Ctx,
    scope: &Scope,
    connection: &ast::Connection,
    provider: &str,
    processor: &str,
) {
    let (Some(provider_def), Some(processor_def)) =
        (ctx.sema.resolve(scope, provider), ctx.sema.resolve(scope, processor))
    else {
        return;
    };
    let keys = |def, prefix: &str| -> Vec<String> {
        let DefKind::Type(ty) = &def else { return Vec::new() };
        ty.methods
            .iter()
            .filter_map(|m| {
                let suffix = m.name.strip_prefix(prefix)?;
                let params: Vec<_> = m.params.iter().map(|p| p.ty.clone()).collect();
                Some(signature_key(suffix, &params))
            })
            .collect()
    };
    let offered = keys(provider_def.kind.clone(), "provide");
    let accepted = keys(processor_def.kind.clone(), "process");
    let missing: Vec<String> =
        offered.iter().filter(|k| !accepted.contains(k)).map(|k| format!("process{k}")).collect();
    if !missing.is_empty() && !offered.is_empty() {
        ctx.sink.error(
            DiagnosticCode::InvalidConnection,
            connection.syntax().text_range(),
            format!(
                "provider `{}` and processor `{}` do not correspond: the processor lacks {}",
                provider_def.fqn,
                processor_def.fqn,
                missing.join(", ")
            ),
        );
    }
}

/// A component is built on a class, of the kind its keyword says (`sink` on a sink class): that
/// class, if it is one (of any kind).
fn component_class<'db>(ctx: &mut Ctx<'db>, scope: &Scope, component: &ast::Component) -> Option<&'db Definition> {
    let class = component.class()?;
    let kind = component.kind();
    let text = class.text();
    let def = ctx.sema.resolve(scope, &text);
    let is_class = def.filter(|d| matches!(&d.kind, DefKind::Type(ty) if matches!(ty.kind, TypeKind::Class(_))));
    match def.map(|d| &d.kind) {
        Some(DefKind::Type(ty)) if ty.kind == TypeKind::Class(kind) || kind == ClassKind::Class => {}
        Some(DefKind::Type(ty)) if ty.kind == TypeKind::Class(ClassKind::Class) => ctx.sink.error(
            DiagnosticCode::InvalidComponent,
            class.syntax().text_range(),
            format!(
                "`{text}` is a plain class, not a component class: declare it `public {} …` in its class diagram",
                kind_name(kind)
            ),
        ),
        Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Class(_)) => {
            let TypeKind::Class(declared) = ty.kind else { return is_class };
            // The keyword is what is wrong: the quick fix writes the class's kind.
            let keyword = [component.source_token(), component.filter_token(), component.sink_token()];
            let range = keyword.into_iter().flatten().next().map_or(class.syntax().text_range(), |t| t.text_range());
            ctx.sink.error_with_replacement(
                DiagnosticCode::InvalidComponent,
                range,
                format!(
                    "`{text}` is declared as a {} class, not a {}: write `{} {text}`",
                    kind_name(declared),
                    kind_name(kind),
                    kind_name(declared)
                ),
                kind_name(declared),
            );
        }
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
    is_class
}

/// A connector's interface is an interface of the connector's role: that interface, if it is.
fn connector_interface<'db>(
    ctx: &mut Ctx<'db>,
    scope: &Scope,
    role: ConnectorRole,
    interface: &ast::Path,
) -> Option<&'db Definition> {
    let text = interface.text();
    let range = interface.syntax().text_range();
    let expected = match role {
        ConnectorRole::Provider => InterfaceRole::Provider,
        ConnectorRole::Processor => InterfaceRole::Processor,
    };
    let def = ctx.sema.resolve(scope, &text);
    match def.map(|d| &d.kind) {
        Some(DefKind::Type(ty)) if ty.kind == TypeKind::Interface(expected) => return def,
        Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Interface(_)) => ctx.sink.error(
            DiagnosticCode::InvalidConnectorInterface,
            range,
            format!("a {0} connector needs a `{0}` interface; `{text}` is not one", role.keyword()),
        ),
        Some(other) => ctx.sink.error(
            DiagnosticCode::InvalidConnectorInterface,
            range,
            format!("`{text}` is {}, not an interface", describe(other)),
        ),
        None => ctx.sink.error(DiagnosticCode::InvalidConnectorInterface, range, format!("unknown interface `{text}`")),
    }
    None
}

/// The keyword of a class kind.
fn kind_name(kind: ClassKind) -> &'static str {
    match kind {
        ClassKind::Class => "class",
        ClassKind::Source => "source",
        ClassKind::Filter => "filter",
        ClassKind::Sink => "sink",
    }
}
