//! The graphs of component diagrams (components with their ports, connections port to port)
//! and component-instance diagrams (instances with field values and port instances, bindings).

use std::collections::HashMap;

use super::{
    edge_id, text, Compartment, EdgeEnd, EdgeKind, Graph, GraphEdge, GraphKind, GraphNode, GraphPort, NodeShape,
};
use crate::{
    ast::{self, AstNode, HasEnds, HasName},
    hir::{Scope, Semantics},
};

pub(super) fn component_graph(sema: &Semantics, id: String, diagram: &ast::ComponentDiagram) -> Graph {
    let scope = Scope::at(diagram.syntax());
    let mut graph = Graph::new(id, GraphKind::Component, diagram.syntax());
    // Components with the fqn of the one they are nested in, parents before their children.
    let mut stack: Vec<(ast::Component, Option<String>)> = diagram.components().map(|c| (c, None)).collect();
    stack.reverse();
    // `port.connector` as connections write it -> the end it names.
    let mut port_owner: HashMap<String, EdgeEnd> = HashMap::new();
    let mut all = Vec::new();
    while let Some((component, parent)) = stack.pop() {
        let fqn = component
            .class()
            .map(|class| sema.resolve(&scope, &class.text()).map(|d| d.fqn.clone()).unwrap_or_else(|| class.text()));
        // The components of one that names no class (being typed) nest in its parent.
        let holder = fqn.clone().or(parent.clone());
        let mut nested: Vec<(ast::Component, Option<String>)> =
            component.components().map(|c| (c, holder.clone())).collect();
        nested.reverse();
        stack.extend(nested);
        let Some(fqn) = fqn else { continue };
        let mut ports = Vec::new();
        for port in component.ports() {
            let Some(port_name) = port.name().map(|n| n.text()) else { continue };
            for connector in port.connectors() {
                let Some(name) = connector.name().map(|n| n.text()) else { continue };
                let interface = connector.interface().map(|i| i.text()).unwrap_or_default();
                let port_id = format!("{fqn}.{port_name}.{name}");
                let end = EdgeEnd { node: fqn.clone(), port: Some(port_id.clone()) };
                port_owner.insert(format!("{port_name}.{name}"), end);
                // UML's property strings mark a port that does not block.
                let mode = match (port.is_async(), port.is_buffered()) {
                    (true, true) => " {async, buffered}",
                    (true, false) => " {async}",
                    _ => "",
                };
                ports.push(GraphPort {
                    id: port_id,
                    label: format!("{}{mode}", port_label(&port_name, &name, &interface)),
                    provider: Some(connector.role() == Some(ast::ConnectorRole::Provider)),
                });
            }
        }
        let stereotype = format!("{:?}", component.kind()).to_lowercase();
        graph.nodes.push(GraphNode {
            id: fqn.clone(),
            shape: NodeShape::Component,
            label: fqn.rsplit('.').next().unwrap_or(&fqn).to_string(),
            stereotype: Some(stereotype),
            is_abstract: false,
            compartments: Vec::new(),
            ports,
            group: None,
            parent,
            range: component.syntax().text_range(),
        });
        all.push(component);
    }
    for component in &all {
        for connection in component.connections() {
            let (Some(source), Some(target)) = (connection.source(), connection.target()) else { continue };
            // A connection end no port declares still shows, dangling, under its name.
            let end =
                |path: ast::Path| port_owner.get(&path.text()).cloned().unwrap_or_else(|| EdgeEnd::node(path.text()));
            let (source, target) = (end(source), end(target));
            graph.edges.push(GraphEdge {
                id: edge_id(&graph, &source, &target),
                kind: EdgeKind::Connection,
                source,
                target,
                label: connection.connection_name().map(|n| n.text()),
                source_label: None,
                target_label: None,
                range: connection.syntax().text_range(),
            });
        }
    }
    graph
}

/// A connector's label: `port.connector : Interface`, the port's name once where the connector
/// has the same name, the interface by its simple name.
fn port_label(port: &str, connector: &str, interface: &str) -> String {
    let name = if port == connector { port.to_string() } else { format!("{port}.{connector}") };
    match interface.rsplit('.').next().filter(|i| !i.is_empty()) {
        Some(interface) => format!("{name} : {interface}"),
        None => name,
    }
}

/// A port instance's connector in a component-instance diagram, as short as the
/// dissertation's figures draw it: the port instance's name (`Out`), with the connector's where
/// the port has several (`Out.frame`). Its interface is the component diagram's to show.
fn instance_port_label(port: &str, connector: &str, several: bool) -> String {
    if several {
        format!("{port}.{connector}")
    } else {
        port.to_string()
    }
}

pub(super) fn instance_graph(id: String, diagram: &ast::ComponentInstanceDiagram) -> Graph {
    let mut graph = Graph::new(id, GraphKind::ComponentInstance, diagram.syntax());
    for instance in diagram.instances() {
        let Some(name) = instance.name().map(|n| n.text()) else { continue };
        let component = instance.component().map(|c| c.text()).unwrap_or_default();
        let (values, value_ids): (Vec<String>, Vec<String>) = instance
            .field_values()
            .map(|f| (text(&f), format!("{name}.{}", f.name().map(|n| n.text()).unwrap_or_default())))
            .unzip();
        let ports = instance
            .port_instances()
            .flat_map(|pi| {
                let pi_name = pi.name().map(|n| n.text()).unwrap_or_default();
                let name = name.clone();
                let several = pi.connectors().count() > 1;
                pi.connectors()
                    .filter_map(move |c| {
                        let connector = c.name()?.text();
                        let values: Vec<String> = c.field_values().map(|v| text(&v)).collect();
                        let mut label = instance_port_label(&pi_name, &connector, several);
                        if !values.is_empty() {
                            label.push_str(&format!(" ({})", values.join(", ")));
                        }
                        Some(GraphPort {
                            id: format!("{name}.{pi_name}.{connector}"),
                            label,
                            provider: Some(c.role() == Some(ast::ConnectorRole::Provider)),
                        })
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        graph.nodes.push(GraphNode {
            id: name.clone(),
            shape: NodeShape::Instance,
            label: format!("{name} : {}", component.rsplit('.').next().unwrap_or(&component)),
            stereotype: None,
            is_abstract: false,
            // Field values, if it sets any.
            compartments: if values.is_empty() {
                Vec::new()
            } else {
                let statics = vec![false; values.len()];
                vec![Compartment { title: None, lines: values, ids: value_ids, statics }]
            },
            ports,
            group: None,
            parent: None,
            range: instance.syntax().text_range(),
        });
        for binding in instance.bindings() {
            // `portInstance.connector` in this instance, or `instance.portInstance.connector`.
            let ends: Vec<EdgeEnd> = [binding.source(), binding.target()]
                .into_iter()
                .flatten()
                .map(|p| {
                    let mut segments: Vec<String> = p.segments().map(|s| s.text()).collect();
                    if segments.len() == 2 {
                        segments.insert(0, name.clone());
                    }
                    EdgeEnd { node: segments[0].clone(), port: Some(segments.join(".")) }
                })
                .collect();
            if let [source, target] = ends.as_slice() {
                graph.edges.push(GraphEdge {
                    id: edge_id(&graph, source, target),
                    kind: EdgeKind::Binding,
                    source: source.clone(),
                    target: target.clone(),
                    label: binding.connection_name().map(|n| n.text()),
                    source_label: None,
                    target_label: None,
                    range: binding.syntax().text_range(),
                });
            }
        }
    }
    graph
}
