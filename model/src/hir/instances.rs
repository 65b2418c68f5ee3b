//! Component instances as the component diagrams define them: the class an instance instantiates
//! and its components, the port each port instance instantiates, the connector each connector
//! instance stands for, and the instance, port and connector a binding end names (chapter 11.3.4).

use std::collections::{HashMap, HashSet};

use super::{components::ComponentInfo, definitions::Definition, items::ConnectorItem, scope::Scope, Semantics};
use crate::ast::{self, AstNode, HasName};

/// One instance of a component-instance diagram.
#[derive(Debug, Clone)]
pub struct Instance<'db> {
    /// The class it instantiates, if the name resolves.
    pub class: Option<&'db Definition>,
    /// The components built on that class (a class can be a component of several diagrams).
    pub components: &'db [ComponentInfo],
    /// Its port instances by name.
    pub ports: HashMap<String, PortInstance>,
}

/// A port instance: the component's port it instantiates, and for each of its connector
/// instances the port's connector it stands for (matched by interface, as in Listing 24, where
/// a connector instance gets a new name).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortInstance {
    pub port: String,
    pub connectors: HashMap<String, String>,
}

/// What a binding end (`portInstance.connector` or `instance.portInstance.connector`) names.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BindingEnd {
    pub instance: String,
    pub port_instance: String,
    /// The component's port and connector (`port.connector` of the component diagram).
    pub port: String,
    pub connector: String,
}

/// Why a binding end names nothing.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum UnresolvedEnd {
    /// Neither two nor three segments.
    Malformed,
    NoInstance(String),
    NoPortInstance {
        instance: String,
        port_instance: String,
    },
    /// A connector neither the port instance nor its port has; `known` are those they have.
    NoConnector {
        port_instance: String,
        connector: String,
        known: Vec<String>,
    },
}

/// The instances of one component-instance diagram, by name (the last of a duplicated name).
#[derive(Debug, Clone)]
pub struct Instances<'db> {
    by_name: HashMap<String, Instance<'db>>,
    /// The connections of the component diagrams that declare the instances' components.
    connections: Vec<&'db (String, String)>,
}

impl<'db> Semantics<'db> {
    /// What an instance instantiates, from where it is written.
    pub fn instance(&self, instance: &ast::ComponentInstance) -> Instance<'db> {
        let class = instance.component().and_then(|path| self.resolve(&Scope::at(instance.syntax()), &path.text()));
        let components = class.map_or(&[][..], |def| self.components(&def.fqn));
        let mut ports = HashMap::new();
        for port_instance in instance.port_instances() {
            let (Some(name), Some(port)) = (port_instance.name(), port_instance.port()) else { continue };
            let port = port.text();
            let port_connectors: Vec<&ConnectorItem> = components
                .iter()
                .flat_map(|info| info.item.ports.iter())
                .filter(|p| p.name == port)
                .flat_map(|p| p.connectors.iter())
                .collect();
            let mut connectors = HashMap::new();
            for connector in port_instance.connectors() {
                let (Some(connector_name), Some(interface)) = (connector.name(), connector.interface()) else {
                    continue;
                };
                let simple = interface.last_segment().map(|s| s.text()).unwrap_or_default();
                let matched = port_connectors
                    .iter()
                    .find(|c| c.interface.rsplit('.').next() == Some(simple.as_str()))
                    .map_or_else(|| connector_name.text(), |c| c.name.clone());
                connectors.insert(connector_name.text(), matched);
            }
            ports.insert(name.text(), PortInstance { port, connectors });
        }
        Instance { class, components, ports }
    }

    /// The instances of a component-instance diagram.
    pub fn instances(&self, diagram: &ast::ComponentInstanceDiagram) -> Instances<'db> {
        let by_name: HashMap<String, Instance<'db>> = diagram
            .instances()
            .filter_map(|instance| Some((instance.name()?.text(), self.instance(&instance))))
            .collect();
        let diagrams: HashSet<&str> =
            by_name.values().flat_map(|i| i.components.iter()).map(|info| info.diagram.as_str()).collect();
        let connections = self
            .diagram_connections()
            .iter()
            .filter(|(diagram, _)| diagrams.contains(diagram.as_str()))
            .flat_map(|(_, connections)| connections)
            .collect();
        Instances { by_name, connections }
    }
}

impl<'db> Instances<'db> {
    pub fn get(&self, name: &str) -> Option<&Instance<'db>> {
        self.by_name.get(name)
    }

    /// What a binding end written in instance `owner` names.
    pub fn binding_end(&self, owner: &str, end: &ast::Path) -> Result<BindingEnd, UnresolvedEnd> {
        let segments: Vec<String> = end.segments().map(|s| s.text()).collect();
        let (instance, port_instance, connector) = match segments.as_slice() {
            [pi, c] => (owner.to_string(), pi.clone(), c.clone()),
            [inst, pi, c] => (inst.clone(), pi.clone(), c.clone()),
            _ => return Err(UnresolvedEnd::Malformed),
        };
        let Some(found) = self.by_name.get(&instance) else { return Err(UnresolvedEnd::NoInstance(instance)) };
        let Some(port) = found.ports.get(&port_instance) else {
            return Err(UnresolvedEnd::NoPortInstance { instance, port_instance });
        };
        // The instance's name for a connector, or the port's own name for it.
        let declared: Vec<&str> = found
            .components
            .iter()
            .flat_map(|info| &info.item.ports)
            .filter(|p| p.name == port.port)
            .flat_map(|p| p.connectors.iter().map(|c| c.name.as_str()))
            .collect();
        let connector = match port.connectors.get(&connector) {
            Some(declared_name) => declared_name.clone(),
            None if declared.contains(&connector.as_str()) || found.components.is_empty() => connector,
            None => {
                let mut known: Vec<String> = port.connectors.keys().cloned().collect();
                known.sort();
                for name in declared {
                    if !known.iter().any(|k| k == name) {
                        known.push(name.to_string());
                    }
                }
                return Err(UnresolvedEnd::NoConnector { port_instance, connector, known });
            }
        };
        Ok(BindingEnd { instance, port_instance, port: port.port.clone(), connector })
    }

    /// Whether a component diagram of the instances' components connects the connectors of
    /// these two ends (either way).
    pub fn connects(&self, a: &BindingEnd, b: &BindingEnd) -> bool {
        let (a, b) = (format!("{}.{}", a.port, a.connector), format!("{}.{}", b.port, b.connector));
        self.connections.iter().any(|(source, target)| (*source == a && *target == b) || (*source == b && *target == a))
    }
}
