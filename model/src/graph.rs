//! Graph view: every diagram as nodes (with compartments and ports), edges (with kinds and
//! labels) and groups (swimlanes), independent of any renderer.
//!
//! Ids come from names, never positions (DESIGN.md, "Identity"): a class is its fully qualified
//! name, an activity node `Diagram/swimlane/node`, a transition `source->target#k` (k counting
//! transitions between the same two nodes), a port `Component.port.connector`. They survive
//! whitespace, comment and reordering edits.

use std::collections::HashMap;

use crate::{
    ast::{self, AstNode, HasEnds, HasModifiers, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{DefKind, Scope, Semantics},
    syntax::TextRange,
};

/// The kind of a diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GraphKind {
    Class,
    Activity,
    Component,
    ComponentInstance,
}

/// What a node is drawn as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeShape {
    Class,
    Interface,
    Enum,
    Attribute,
    /// A type of another diagram, drawn for an edge that leaves this one.
    External,
    Start,
    Final,
    Action,
    Decision,
    Fork,
    Join,
    Loop,
    LoopWindow,
    Calc,
    CalcRange,
    Component,
    Instance,
}

/// A titled list of text lines inside a node (fields, methods, expressions, values).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Compartment {
    pub title: Option<String>,
    pub lines: Vec<String>,
}

/// A port on a node's boundary.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphPort {
    pub id: String,
    pub label: String,
    /// `provider` (lollipop) or `processor` (socket); `None` for a port instance's own box.
    pub provider: Option<bool>,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphNode {
    pub id: String,
    pub shape: NodeShape,
    pub label: String,
    /// «interface», «source», «attribute», … or a node kind's header.
    pub stereotype: Option<String>,
    pub is_abstract: bool,
    pub compartments: Vec<Compartment>,
    pub ports: Vec<GraphPort>,
    /// The swimlane it belongs to (activity diagrams).
    pub group: Option<String>,
    /// Where it is declared, for round trips to the text.
    pub range: TextRange,
}

/// The kind of an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EdgeKind {
    Generalization,
    Realization,
    Association,
    Aggregation,
    Composition,
    Transition,
    Connection,
    Binding,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphEdge {
    pub id: String,
    pub kind: EdgeKind,
    /// Node ids, or port ids for connections and bindings.
    pub source: String,
    pub target: String,
    /// `[guard]`, `(args)`, a connection's name, an association's role.
    pub label: Option<String>,
    /// Multiplicity at the source and target end.
    pub source_label: Option<String>,
    pub target_label: Option<String>,
}

/// A swimlane.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphGroup {
    pub id: String,
    pub label: String,
    pub owner: Option<String>,
}

/// One diagram's graph.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Graph {
    /// The diagram's fully qualified name.
    pub id: String,
    pub kind: GraphKind,
    pub nodes: Vec<GraphNode>,
    pub edges: Vec<GraphEdge>,
    pub groups: Vec<GraphGroup>,
}

/// The graphs of every diagram of a file (nested diagrams included, each its own graph).
#[salsa::tracked(returns(ref))]
pub fn file_graphs(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Graph> {
    let root = parse(db, file).syntax_node();
    let sema = Semantics::new(db, workspace);
    root.descendants()
        .filter_map(ast::Diagram::cast)
        .filter_map(|diagram| {
            let id = Scope::at(diagram.syntax()).namespaces.last()?.clone();
            Some(match &diagram {
                ast::Diagram::ClassDiagram(d) => class_graph(&sema, id, d),
                ast::Diagram::ActivityDiagram(d) => activity_graph(id, d),
                ast::Diagram::ComponentDiagram(d) => component_graph(&sema, id, d),
                ast::Diagram::ComponentInstanceDiagram(d) => instance_graph(id, d),
            })
        })
        .collect()
}

fn text(node: &impl AstNode) -> String {
    node.syntax().text().to_string().split_whitespace().collect::<Vec<_>>().join(" ")
}

fn visibility_mark(node: &impl HasModifiers) -> &'static str {
    match node.modifiers().and_then(|m| m.visibility()) {
        Some(ast::Visibility::Public) => "+ ",
        Some(ast::Visibility::Protected) => "# ",
        Some(ast::Visibility::Private) => "- ",
        None => "",
    }
}

fn class_graph(sema: &Semantics, id: String, diagram: &ast::ClassDiagram) -> Graph {
    let scope = Scope::at(diagram.syntax());
    let mut graph =
        Graph { id: id.clone(), kind: GraphKind::Class, nodes: Vec::new(), edges: Vec::new(), groups: Vec::new() };
    let mut known: Vec<String> = Vec::new();
    for decl in diagram.type_decls() {
        let Some(name) = decl.name().map(|n| n.text()) else { continue };
        let fqn = format!("{id}.{name}");
        known.push(fqn.clone());
        let (shape, stereotype, is_abstract, template) = match &decl {
            ast::TypeDecl::Class(c) => {
                let stereotype = match c.kind() {
                    ast::ClassKind::Class => None,
                    ast::ClassKind::Source => Some("source".to_string()),
                    ast::ClassKind::Filter => Some("filter".to_string()),
                    ast::ClassKind::Sink => Some("sink".to_string()),
                };
                let params: Vec<String> = c.template_params().filter_map(|t| t.name()).map(|n| n.text()).collect();
                (NodeShape::Class, stereotype, c.is_abstract(), params)
            }
            ast::TypeDecl::Interface(i) => {
                let stereotype = match i.role() {
                    ast::InterfaceRole::Plain => "interface",
                    ast::InterfaceRole::Provider => "provider interface",
                    ast::InterfaceRole::Processor => "processor interface",
                };
                (NodeShape::Interface, Some(stereotype.to_string()), false, Vec::new())
            }
            ast::TypeDecl::Enum(_) => (NodeShape::Enum, Some("enumeration".to_string()), false, Vec::new()),
            ast::TypeDecl::AttributeDef(_) => (NodeShape::Attribute, Some("attribute".to_string()), false, Vec::new()),
        };
        let label = if template.is_empty() { name.clone() } else { format!("{name}<{}>", template.join(", ")) };
        let mut fields = Vec::new();
        let mut methods = Vec::new();
        for member in decl.members() {
            match &member {
                ast::Member::Field(f) => {
                    let ty = f.type_ref().map(|t| text(&t)).unwrap_or_default();
                    let name = f.name().map(|n| n.text()).unwrap_or_default();
                    fields.push(format!("{}{name} : {ty}", visibility_mark(f)));
                }
                ast::Member::Method(m) => {
                    let ret = m.return_type().map(|t| text(&t)).unwrap_or_default();
                    let params: Vec<String> = m
                        .params()
                        .map(|p| {
                            format!(
                                "{} : {}",
                                p.name().map(|n| n.text()).unwrap_or_default(),
                                p.type_ref().map(|t| text(&t)).unwrap_or_default()
                            )
                        })
                        .collect();
                    let name = m.name().map(|n| n.text()).unwrap_or_default();
                    methods.push(format!("{}{name}({}) : {ret}", visibility_mark(m), params.join(", ")));
                }
                ast::Member::Association(_) => {}
            }
        }
        let mut compartments =
            vec![Compartment { title: None, lines: fields }, Compartment { title: None, lines: methods }];
        if let ast::TypeDecl::Enum(e) = &decl {
            compartments = vec![Compartment {
                title: None,
                lines: e.values().filter_map(|v| v.name()).map(|n| n.text()).collect(),
            }];
        }
        graph.nodes.push(GraphNode {
            id: fqn.clone(),
            shape,
            label,
            stereotype,
            is_abstract,
            compartments,
            ports: Vec::new(),
            group: None,
            range: decl.syntax().text_range(),
        });
        // Edges: generalization, realization, associations.
        let edge = |graph: &mut Graph,
                    kind: EdgeKind,
                    target: String,
                    label: Option<String>,
                    ends: (Option<String>, Option<String>)| {
            let k = graph.edges.iter().filter(|e| e.source == fqn && e.target == target && e.kind == kind).count();
            graph.edges.push(GraphEdge {
                id: format!("{fqn}->{target}#{k}"),
                kind,
                source: fqn.clone(),
                target,
                label,
                source_label: ends.0,
                target_label: ends.1,
            });
        };
        let resolve =
            |path: &str| sema.resolve(&scope, path).map(|d| d.fqn.clone()).unwrap_or_else(|| path.to_string());
        let (extends, implements): (Vec<ast::TypeRef>, Vec<ast::TypeRef>) = match &decl {
            ast::TypeDecl::Class(c) => (c.extends().collect(), c.implements().collect()),
            ast::TypeDecl::Interface(i) => (i.extends().collect(), Vec::new()),
            _ => (Vec::new(), Vec::new()),
        };
        for base in extends.iter().filter_map(|t| t.path()) {
            edge(&mut graph, EdgeKind::Generalization, resolve(&base.text()), None, (None, None));
        }
        for base in implements.iter().filter_map(|t| t.path()) {
            edge(&mut graph, EdgeKind::Realization, resolve(&base.text()), None, (None, None));
        }
        for member in decl.members() {
            if let ast::Member::Association(a) = member {
                let Some(target) = a.target().and_then(|t| t.path()) else { continue };
                let kind = match a.kind() {
                    ast::AssociationKind::Plain => EdgeKind::Association,
                    ast::AssociationKind::Aggregation => EdgeKind::Aggregation,
                    ast::AssociationKind::Composition => EdgeKind::Composition,
                };
                let bounds = |m: Option<ast::Multiplicity>| {
                    m.map(|m| match m.bounds() {
                        (Some(a), Some(b)) => format!("{a}..{b}"),
                        (Some(a), None) => a,
                        _ => String::new(),
                    })
                };
                let role = a.name().map(|n| n.text());
                edge(
                    &mut graph,
                    kind,
                    resolve(&target.text()),
                    role,
                    (bounds(a.target_multiplicity()), bounds(a.own_multiplicity())),
                );
            }
        }
    }
    // Types of other diagrams that edges reach.
    let external: Vec<String> = graph.edges.iter().map(|e| e.target.clone()).filter(|t| !known.contains(t)).collect();
    for target in external {
        if graph.nodes.iter().any(|n| n.id == target) {
            continue;
        }
        let is_interface = sema.definition(&target).is_some_and(
            |d| matches!(&d.kind, DefKind::Type(ty) if matches!(ty.kind, crate::hir::items::TypeKind::Interface(_))),
        );
        graph.nodes.push(GraphNode {
            id: target.clone(),
            shape: NodeShape::External,
            label: target.rsplit('.').next().unwrap_or(&target).to_string(),
            stereotype: is_interface.then(|| "interface".to_string()),
            is_abstract: false,
            compartments: Vec::new(),
            ports: Vec::new(),
            group: None,
            range: TextRange::default(),
        });
    }
    graph
}

fn activity_graph(id: String, diagram: &ast::ActivityDiagram) -> Graph {
    let mut graph =
        Graph { id: id.clone(), kind: GraphKind::Activity, nodes: Vec::new(), edges: Vec::new(), groups: Vec::new() };
    let mut lanes: Vec<(Option<String>, Vec<ast::ActivityNode>)> = Vec::new();
    for lane in diagram.swimlanes() {
        let name = lane.name().map(|n| n.text()).unwrap_or_default();
        let lane_id = format!("{id}/{name}");
        graph.groups.push(GraphGroup { id: lane_id.clone(), label: name, owner: lane.owner().map(|p| p.text()) });
        lanes.push((Some(lane_id), lane.nodes().collect()));
    }
    lanes.push((None, diagram.nodes().collect()));
    let mut node_ids: HashMap<String, String> = HashMap::new();
    for (lane_id, nodes) in &lanes {
        for node in nodes {
            let Some(name) = node.name().map(|n| n.text()) else { continue };
            let node_id = match lane_id {
                Some(lane) => format!("{lane}/{name}"),
                None => format!("{id}/{name}"),
            };
            node_ids.entry(name.clone()).or_insert_with(|| node_id.clone());
            let shape = match node.kind() {
                ast::NodeKind::Start => NodeShape::Start,
                ast::NodeKind::Final => NodeShape::Final,
                ast::NodeKind::Action => NodeShape::Action,
                ast::NodeKind::Decision => NodeShape::Decision,
                ast::NodeKind::Fork => NodeShape::Fork,
                ast::NodeKind::Join => NodeShape::Join,
                ast::NodeKind::Loop => NodeShape::Loop,
                ast::NodeKind::LoopWindow => NodeShape::LoopWindow,
                ast::NodeKind::Calc => NodeShape::Calc,
                ast::NodeKind::CalcRange => NodeShape::CalcRange,
            };
            let stereotype = match node.kind() {
                ast::NodeKind::Loop => Some("loop".to_string()),
                ast::NodeKind::LoopWindow => Some("loopWindow".to_string()),
                ast::NodeKind::Calc => Some("calc".to_string()),
                ast::NodeKind::CalcRange => Some("calcRange".to_string()),
                _ => None,
            };
            let params: Vec<String> = node.params().map(|p| text(&p)).collect();
            let label = if params.is_empty() { name.clone() } else { format!("{name}({})", params.join(", ")) };
            let mut compartments = Vec::new();
            if let Some(header) = node.loop_header() {
                let sections: Vec<String> = header.sections().map(|s| text(&s)).collect();
                compartments.push(Compartment { title: Some("header".into()), lines: sections });
            }
            let statements: Vec<String> = node.statements().map(|s| text(&s)).collect();
            if !statements.is_empty() {
                compartments.push(Compartment { title: None, lines: statements });
            }
            graph.nodes.push(GraphNode {
                id: node_id,
                shape,
                label,
                stereotype,
                is_abstract: false,
                compartments,
                ports: Vec::new(),
                group: lane_id.clone(),
                range: node.syntax().text_range(),
            });
        }
    }
    for (_, nodes) in &lanes {
        for node in nodes {
            let Some(source) = node.name().and_then(|n| node_ids.get(&n.text()).cloned()) else { continue };
            for transition in node.transitions() {
                let Some(target_name) = transition.target().map(|t| t.text()) else { continue };
                // Unknown targets still show, as dangling edges to their name.
                let target = node_ids.get(&target_name).cloned().unwrap_or_else(|| format!("{id}/{target_name}"));
                let k = graph.edges.iter().filter(|e| e.source == source && e.target == target).count();
                let guard = transition.guard().map(|g| match g.condition() {
                    Some(c) => format!("[{}]", text(&c)),
                    None => "[]".to_string(),
                });
                let args = transition.arg_list().map(|a| text(&a));
                let label = match (guard, args) {
                    (Some(g), Some(a)) => Some(format!("{g} {a}")),
                    (g, a) => g.or(a),
                };
                graph.edges.push(GraphEdge {
                    id: format!("{source}->{target}#{k}"),
                    kind: EdgeKind::Transition,
                    source: source.clone(),
                    target,
                    label,
                    source_label: None,
                    target_label: None,
                });
            }
        }
    }
    graph
}

fn component_graph(sema: &Semantics, id: String, diagram: &ast::ComponentDiagram) -> Graph {
    let scope = Scope::at(diagram.syntax());
    let mut graph = Graph { id, kind: GraphKind::Component, nodes: Vec::new(), edges: Vec::new(), groups: Vec::new() };
    let mut stack: Vec<ast::Component> = diagram.components().collect();
    stack.reverse();
    let mut port_owner: HashMap<String, String> = HashMap::new();
    let mut all = Vec::new();
    while let Some(component) = stack.pop() {
        let mut nested: Vec<ast::Component> = component.components().collect();
        nested.reverse();
        stack.extend(nested);
        let Some(class) = component.class() else { continue };
        let fqn = sema.resolve(&scope, &class.text()).map(|d| d.fqn.clone()).unwrap_or_else(|| class.text());
        let mut ports = Vec::new();
        for port in component.ports() {
            let Some(port_name) = port.name().map(|n| n.text()) else { continue };
            for connector in port.connectors() {
                let Some(name) = connector.name().map(|n| n.text()) else { continue };
                let interface = connector.interface().map(|i| i.text()).unwrap_or_default();
                let port_id = format!("{fqn}.{port_name}.{name}");
                port_owner.insert(format!("{port_name}.{name}"), port_id.clone());
                ports.push(GraphPort {
                    id: port_id,
                    label: format!("{port_name}.{name} : {}", interface.rsplit('.').next().unwrap_or(&interface)),
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
            range: component.syntax().text_range(),
        });
        all.push(component);
    }
    for component in &all {
        for connection in component.connections() {
            let (Some(source), Some(target)) = (connection.source(), connection.target()) else { continue };
            let source = port_owner.get(&source.text()).cloned().unwrap_or_else(|| source.text());
            let target = port_owner.get(&target.text()).cloned().unwrap_or_else(|| target.text());
            let k = graph.edges.iter().filter(|e| e.source == source && e.target == target).count();
            graph.edges.push(GraphEdge {
                id: format!("{source}->{target}#{k}"),
                kind: EdgeKind::Connection,
                source,
                target,
                label: connection.connection_name().map(|n| n.text()),
                source_label: None,
                target_label: None,
            });
        }
    }
    graph
}

fn instance_graph(id: String, diagram: &ast::ComponentInstanceDiagram) -> Graph {
    let mut graph =
        Graph { id, kind: GraphKind::ComponentInstance, nodes: Vec::new(), edges: Vec::new(), groups: Vec::new() };
    for instance in diagram.instances() {
        let Some(name) = instance.name().map(|n| n.text()) else { continue };
        let component = instance.component().map(|c| c.text()).unwrap_or_default();
        let values: Vec<String> = instance.field_values().map(|f| text(&f)).collect();
        let ports = instance
            .port_instances()
            .flat_map(|pi| {
                let pi_name = pi.name().map(|n| n.text()).unwrap_or_default();
                let name = name.clone();
                pi.connectors()
                    .filter_map(move |c| {
                        let connector = c.name()?.text();
                        Some(GraphPort {
                            id: format!("{name}.{pi_name}.{connector}"),
                            label: format!("{pi_name}.{connector}"),
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
            compartments: vec![Compartment { title: None, lines: values }],
            ports,
            group: None,
            range: instance.syntax().text_range(),
        });
        for binding in instance.bindings() {
            let ends: Vec<String> = [binding.source(), binding.target()]
                .into_iter()
                .flatten()
                .map(|p| {
                    let segments: Vec<String> = p.segments().map(|s| s.text()).collect();
                    if segments.len() == 2 {
                        format!("{name}.{}", segments.join("."))
                    } else {
                        segments.join(".")
                    }
                })
                .collect();
            if let [source, target] = ends.as_slice() {
                let k = graph.edges.iter().filter(|e| &e.source == source && &e.target == target).count();
                graph.edges.push(GraphEdge {
                    id: format!("{source}->{target}#{k}"),
                    kind: EdgeKind::Binding,
                    source: source.clone(),
                    target: target.clone(),
                    label: None,
                    source_label: None,
                    target_label: None,
                });
            }
        }
    }
    graph
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    fn seed(name: &str) -> String {
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/seed").join(name))
            .unwrap()
    }

    fn graphs_of(files: &[(&str, String)]) -> Vec<Graph> {
        let db = RootDatabase::default();
        let inputs: Vec<SourceFile> =
            files.iter().map(|(p, t)| SourceFile::new(&db, p.to_string(), t.clone())).collect();
        let ws = Workspace::new(&db, inputs.clone());
        file_graphs(&db, ws, inputs[0]).clone()
    }

    #[test]
    fn class_graph_of_listing26() {
        let g = &graphs_of(&[
            ("a", seed("listing26_component_classes_example.gudsl")),
            ("b", seed("listing01_type_definitions.gudsl")),
        ])[0];
        assert_eq!(g.id, "ComponentClassDefinitions");
        let camera = g.nodes.iter().find(|n| n.id == "ComponentClassDefinitions.Camera").unwrap();
        assert_eq!(camera.stereotype.as_deref(), Some("source"));
        assert_eq!(camera.compartments[0].lines, ["+ width : int", "+ height : int"]);
        let realizes: Vec<&str> =
            g.edges.iter().filter(|e| e.kind == EdgeKind::Realization).map(|e| e.id.as_str()).collect();
        assert!(
            realizes.contains(&"ComponentClassDefinitions.Camera->ComponentClassDefinitions.IImageProvider#0"),
            "{realizes:?}"
        );
    }

    #[test]
    fn activity_graph_ids_survive_whitespace_and_comment_edits() {
        let text = seed("listing08_member_access.gudsl");
        let before = &graphs_of(&[("a", text.clone())])[0];
        let edited = text
            .replace("    swimlane", "  // a comment\n\n    swimlane")
            .replace("=> filterImage;", "=>   filterImage ;");
        let after = &graphs_of(&[("a", edited)])[0];
        let ids = |g: &Graph| {
            (
                g.nodes.iter().map(|n| n.id.clone()).collect::<Vec<_>>(),
                g.edges.iter().map(|e| e.id.clone()).collect::<Vec<_>>(),
            )
        };
        assert_eq!(ids(before), ids(after));
        assert!(before.nodes.iter().any(|n| n.id == "AdMemberAccess/Swimlane1/load"));
        assert!(before
            .edges
            .iter()
            .any(|e| e.id == "AdMemberAccess/Swimlane1/filterImage->AdMemberAccess/Swimlane1/filterImage#0"
                && e.label.as_deref() == Some("[i < 10]")));
        assert_eq!(before.groups[0].owner.as_deref(), Some("TypeDefinitions.Image"));
    }

    #[test]
    fn component_and_instance_graphs() {
        let defs = seed("listing26_component_classes_example.gudsl");
        let g = &graphs_of(&[("c", seed("listing27_component_example.gudsl")), ("d", defs.clone())])[0];
        let camera = g.nodes.iter().find(|n| n.id == "ComponentClassDefinitions.Camera").unwrap();
        assert_eq!(
            camera.ports[0].id,
            "ComponentClassDefinitions.Camera.CameraImageProviderPort.CameraImageProviderPort"
        );
        assert_eq!(camera.ports[0].provider, Some(true));
        let connection = g.edges.iter().find(|e| e.label.as_deref() == Some("CameraToFilter")).unwrap();
        assert_eq!(
            connection.target,
            "ComponentClassDefinitions.MeanFilter.MeanImageProcessorPort.FilterImageProcessorPort"
        );
        let g = &graphs_of(&[("i", seed("listing28_component_instance_example.gudsl"))])[0];
        assert_eq!(
            g.nodes.iter().map(|n| n.label.as_str()).collect::<Vec<_>>(),
            ["Camera1 : Camera", "Camera2 : Camera", "MeanFilter1 : MeanFilter", "Viewer1 : Viewer"]
        );
        assert_eq!(g.nodes[0].compartments[0].lines, ["width = 640", "height = 480"]);
        assert!(g.edges.iter().any(|e| e.source == "Camera1.Camera1ProviderPort.CameraImageProviderPort"
            && e.target == "MeanFilter1.MeanProcessorPort.MeanImageProcessorPort"));
    }

    #[test]
    fn every_sample_diagram_has_a_graph() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
        let db = RootDatabase::default();
        let mut files = Vec::new();
        for dir in ["seed", "framework"] {
            for entry in std::fs::read_dir(root.join(dir)).unwrap().flatten() {
                let path = entry.path();
                if path.extension().is_some_and(|e| e == "gudsl") {
                    files.push(SourceFile::new(
                        &db,
                        path.display().to_string(),
                        std::fs::read_to_string(&path).unwrap(),
                    ));
                }
            }
        }
        let ws = Workspace::new(&db, files.clone());
        let mut total = 0;
        for file in &files {
            let diagrams =
                parse(&db, *file).syntax_node().descendants().filter(|n| ast::Diagram::can_cast(n.kind())).count();
            let graphs = file_graphs(&db, ws, *file);
            assert_eq!(graphs.len(), diagrams, "{}", file.path(&db));
            for graph in graphs {
                let mut ids: Vec<&str> = graph.nodes.iter().map(|n| n.id.as_str()).collect();
                ids.sort();
                ids.dedup();
                assert_eq!(ids.len(), graph.nodes.len(), "duplicate node ids in {}", graph.id);
            }
            total += diagrams;
        }
        assert!(total > 40, "{total}");
    }
}
