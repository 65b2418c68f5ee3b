//! Edges and properties on every diagram of every listing: connecting states exactly the new
//! edge and deleting it gives the text back; reconnecting moves exactly its ends and back;
//! setting a property shows in the graph and setting it back gives the text back.

use super::tests_ops::{edge_ends, props, Run};
use super::*;
use crate::graph::{EdgeKind, Graph, GraphEdge, GraphKind, NodeShape};

/// The edges a test can state in `graph`: (kind, source, target, properties).
fn connections(graph: &Graph) -> Vec<(EdgeKind, String, String, Properties)> {
    let declared = |shapes: &[NodeShape]| -> Vec<String> {
        graph.nodes.iter().filter(|n| shapes.contains(&n.shape) && !n.range.is_empty()).map(|n| n.id.clone()).collect()
    };
    let mut out = Vec::new();
    match graph.kind {
        GraphKind::Class => {
            let classes = declared(&[NodeShape::Class]);
            let interfaces: Vec<String> = graph
                .nodes
                .iter()
                .filter(|n| n.shape == NodeShape::Interface || n.stereotype.as_deref() == Some("interface"))
                .map(|n| n.id.clone())
                .collect();
            if let [a, b, ..] = classes.as_slice() {
                let role = props(&[("name", "linked"), ("sourceMultiplicity", "0..*"), ("targetMultiplicity", "1")]);
                for kind in [EdgeKind::Association, EdgeKind::Aggregation, EdgeKind::Composition] {
                    out.push((kind, a.clone(), b.clone(), role.clone()));
                }
                out.push((EdgeKind::Association, b.clone(), a.clone(), Properties::new()));
                let extends =
                    |c: &String| graph.edges.iter().any(|e| e.kind == EdgeKind::Generalization && e.source.node == *c);
                if let Some(free) = classes.iter().find(|c| !extends(c)) {
                    let other = if free == a { b } else { a };
                    out.push((EdgeKind::Generalization, free.clone(), other.clone(), Properties::new()));
                }
            }
            if let (Some(class), Some(interface)) = (classes.first(), interfaces.first()) {
                out.push((EdgeKind::Realization, class.clone(), interface.clone(), Properties::new()));
            }
            let declared_interfaces = declared(&[NodeShape::Interface]);
            if let (Some(i), Some(j)) =
                (declared_interfaces.first(), interfaces.iter().find(|j| declared_interfaces.first() != Some(j)))
            {
                out.push((EdgeKind::Generalization, i.clone(), j.clone(), Properties::new()));
            }
        }
        GraphKind::Activity => {
            let nodes = declared(&[
                NodeShape::Start,
                NodeShape::Action,
                NodeShape::Decision,
                NodeShape::Fork,
                NodeShape::Join,
                NodeShape::Loop,
                NodeShape::LoopWindow,
                NodeShape::Calc,
                NodeShape::CalcRange,
            ]);
            let all = declared(&[NodeShape::Final]).into_iter().chain(nodes.iter().cloned()).collect::<Vec<_>>();
            if let (Some(from), Some(to)) = (nodes.first(), all.iter().find(|n| Some(*n) != nodes.first())) {
                out.push((
                    EdgeKind::Transition,
                    from.clone(),
                    to.clone(),
                    props(&[("guard", "ready"), ("arguments", "1, 2")]),
                ));
                out.push((EdgeKind::Transition, from.clone(), to.clone(), Properties::new()));
            }
        }
        GraphKind::Component | GraphKind::ComponentInstance => {
            let kind = if graph.kind == GraphKind::Component { EdgeKind::Connection } else { EdgeKind::Binding };
            let ports: Vec<(String, String)> = graph
                .nodes
                .iter()
                .filter(|n| !n.range.is_empty())
                .flat_map(|n| n.ports.iter().map(|p| (n.id.clone(), p.id.clone())))
                .collect();
            if let Some((first_owner, first)) = ports.first() {
                if let Some((_, other)) = ports.iter().find(|(o, _)| o != first_owner) {
                    out.push((kind, first.clone(), other.clone(), props(&[("name", "Linked")])));
                    out.push((kind, other.clone(), first.clone(), Properties::new()));
                }
            }
        }
    }
    out
}

#[test]
fn connecting_any_edge_kind_states_exactly_it_and_deleting_it_undoes() {
    for formatted in [false, true] {
        let mut run = Run::new(formatted);
        for file in run.files.clone() {
            for graph in file_graphs(&run.db, run.ws, file).clone() {
                for (kind, source, target, properties) in connections(&graph) {
                    let old = graph.clone();
                    let path = file.path(&run.db).clone();
                    let expected_label = properties
                        .get("name")
                        .cloned()
                        .or_else(|| properties.get("guard").map(|g| format!("[{g}] ({})", properties["arguments"])));
                    let (op_source, op_target) = (source.clone(), target.clone());
                    let op = GraphOp::Connect { kind, source: source.clone(), target: target.clone(), properties };
                    let name = kind.name();
                    // The new edge: one more of its kind between its ends (an edge's `#k` counts the
                    // edges between the same ends, so a new one can renumber another kind's).
                    let new_edge = move |after: &Graph| {
                        let same = |g: &Graph| -> Vec<GraphEdge> {
                            g.edges
                                .iter()
                                .filter(|e| e.kind == kind && e.source.id() == op_source && e.target.id() == op_target)
                                .cloned()
                                .collect()
                        };
                        let (before, now) = (same(&old), same(after));
                        assert_eq!(now.len(), before.len() + 1, "one more {kind:?} from {op_source} to {op_target}");
                        now.into_iter().find(|e| !before.iter().any(|b| b.range == e.range)).expect("a new edge")
                    };
                    let check_new = new_edge.clone();
                    let old_ends = edge_ends(&graph);
                    let check = move |after: &Graph| {
                        let edge = check_new(after);
                        assert_eq!(
                            (edge.kind, edge.source.id(), edge.target.id()),
                            (kind, source.as_str(), target.as_str()),
                            "{path}"
                        );
                        let mut expected = old_ends.clone();
                        expected.push(format!("{kind:?} {source} {target}"));
                        expected.sort();
                        assert_eq!(edge_ends(after), expected, "{path}: connecting {source} to {target}");
                        if expected_label.is_some() {
                            assert_eq!(edge.label, expected_label, "{path}");
                        }
                        if edge.kind == EdgeKind::Association && edge.label.as_deref() == Some("linked") {
                            assert_eq!(
                                (edge.source_label.as_deref(), edge.target_label.as_deref()),
                                (Some("0..*"), Some("1"))
                            );
                        }
                    };
                    let undo = move |after: &Graph| vec![GraphOp::Delete { element: new_edge(after).id }];
                    run.round_trip(file, &graph, name, op, check, undo);
                }
            }
        }
        for kind in [
            "association",
            "aggregation",
            "composition",
            "generalization",
            "realization",
            "transition",
            "connection",
            "binding",
        ] {
            assert!(run.made.get(kind).is_some_and(|&n| n > 0), "no {kind} was connected (formatted: {formatted})");
        }
    }
}

#[test]
fn reconnecting_any_edge_moves_exactly_its_end_and_back() {
    let mut run = Run::new(false);
    for file in run.files.clone() {
        for graph in file_graphs(&run.db, run.ws, file).clone() {
            for edge in
                graph.edges.iter().filter(|e| graph.nodes.iter().any(|n| n.id == e.source.node && !n.range.is_empty()))
            {
                // Another end of the kind it has.
                let same_kind =
                    |id: &str| -> Option<NodeShape> { graph.nodes.iter().find(|n| n.id == id).map(|n| n.shape) };
                let other = match edge.kind {
                    EdgeKind::Connection | EdgeKind::Binding => graph
                        .nodes
                        .iter()
                        .flat_map(|n| &n.ports)
                        .map(|p| p.id.clone())
                        .find(|p| p != edge.target.id() && p != edge.source.id()),
                    _ => graph
                        .nodes
                        .iter()
                        .filter(|n| {
                            !n.range.is_empty()
                                && Some(n.shape) == same_kind(&edge.target.node)
                                && n.id != edge.target.node
                        })
                        .map(|n| n.id.clone())
                        .next(),
                };
                let Some(other) = other else { continue };
                if edge.kind == EdgeKind::Realization
                    || graph.edges.iter().any(|e| e.source.id() == edge.source.id() && e.target.id() == other)
                {
                    continue; // a second edge between the same ends would renumber ids
                }
                let before = edge_ends(&graph);
                let there = GraphOp::Reconnect { edge: edge.id.clone(), source: None, target: Some(other.clone()) };
                let after = run.make(file, &graph, &there);
                let moved = after
                    .edges
                    .iter()
                    .find(|e| e.kind == edge.kind && e.source.id() == edge.source.id() && e.target.id() == other);
                let moved = moved
                    .unwrap_or_else(|| panic!("{}: {} was not reconnected to {other}", file.path(&run.db), edge.id))
                    .clone();
                let mut expected = before.clone();
                expected.remove(
                    expected
                        .iter()
                        .position(|e| *e == format!("{:?} {} {}", edge.kind, edge.source.id(), edge.target.id()))
                        .unwrap(),
                );
                expected.push(format!("{:?} {} {other}", edge.kind, edge.source.id()));
                expected.sort();
                assert_eq!(edge_ends(&after), expected, "{}: reconnecting {}", file.path(&run.db), edge.id);
                let back = GraphOp::Reconnect {
                    edge: moved.id.clone(),
                    source: None,
                    target: Some(edge.target.id().to_string()),
                };
                let back = run.make(file, &after, &back);
                assert_eq!(edge_ends(&back), before, "{}: reconnecting {} back", file.path(&run.db), edge.id);
                *run.made.entry(edge.kind.name()).or_default() += 1;
            }
        }
    }
    for kind in ["transition", "association", "generalization", "connection", "binding"] {
        assert!(run.made.get(kind).is_some_and(|&n| n > 0), "no {kind} was reconnected");
    }
}

#[test]
fn setting_any_property_shows_in_the_graph_and_setting_it_back_undoes() {
    let mut run = Run::new(false);
    for file in run.files.clone() {
        for graph in file_graphs(&run.db, run.ws, file).clone() {
            let mut targets: Vec<(String, &str, &str)> = Vec::new();
            for edge in &graph.edges {
                match edge.kind {
                    EdgeKind::Transition => {
                        targets.push((edge.id.clone(), "guard", "ready"));
                        targets.push((edge.id.clone(), "arguments", "1, 2"));
                    }
                    EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition => {
                        targets.push((edge.id.clone(), "name", "renamed"));
                        targets.push((edge.id.clone(), "targetMultiplicity", "3"));
                        if edge.target_label.is_some() {
                            targets.push((edge.id.clone(), "sourceMultiplicity", "2..*"));
                        } else {
                            // A lone multiplicity is the target's: a source end needs one.
                            let op = GraphOp::SetProperty {
                                element: edge.id.clone(),
                                property: "sourceMultiplicity".into(),
                                value: Some("2..*".into()),
                            };
                            let refused = graph_edit(&run.db, run.ws, file, &graph.id, &[op]).unwrap_err();
                            assert!(refused.0.contains("set `targetMultiplicity` first"), "{}", refused.0);
                            *run.made.entry("refused source multiplicity").or_default() += 1;
                        }
                    }
                    EdgeKind::Connection | EdgeKind::Binding => targets.push((edge.id.clone(), "name", "Named")),
                    _ => {}
                }
            }
            for node in graph.nodes.iter().filter(|n| !n.range.is_empty()) {
                match node.shape {
                    NodeShape::Action | NodeShape::Calc | NodeShape::CalcRange | NodeShape::Decision => {
                        targets.push((node.id.clone(), "parameters", "int p"))
                    }
                    NodeShape::Loop | NodeShape::LoopWindow => {
                        targets.push((node.id.clone(), "header", "var int k = 0; k < 2; k = k + 1"))
                    }
                    NodeShape::Instance => targets.push((node.id.clone(), "component", "Other.Component")),
                    _ => {}
                }
                for id in node.compartments.iter().flat_map(|c| &c.ids).filter(|i| !i.is_empty()) {
                    if id.ends_with("()") {
                        targets.push((id.clone(), "parameters", "int k"));
                        targets.push((id.clone(), "type", "double"));
                    } else if node.shape != NodeShape::Enum {
                        targets.push((id.clone(), "value", "7"));
                        if node.shape != NodeShape::Instance {
                            targets.push((id.clone(), "type", "double"));
                        }
                    }
                }
            }
            for (element, prop, value) in targets {
                let old = super::property(&run.db, run.ws, file, &graph.id, &element, prop)
                    .unwrap_or_else(|e| panic!("{}: {element}.{prop}: {}", file.path(&run.db), e.0));
                if old.as_deref() == Some(value) {
                    continue;
                }
                let before = file.text(&run.db).clone();
                let set =
                    GraphOp::SetProperty { element: element.clone(), property: prop.into(), value: Some(value.into()) };
                let after = run.make(file, &graph, &set);
                let now = super::property(&run.db, run.ws, file, &graph.id, &element, prop).ok().flatten();
                let shown =
                    if prop.ends_with("Multiplicity") { value.replace("..", " .. ") } else { value.to_string() };
                assert_eq!(now.as_deref(), Some(shown.as_str()), "{}: {element}.{prop}", file.path(&run.db));
                // The graph shows it: on the edge, in the node's label or lines.
                let seen = value.replace(" .. ", "..");
                let in_graph = after.edges.iter().filter(|e| e.id == element).any(|e| {
                    [&e.label, &e.source_label, &e.target_label]
                        .iter()
                        .any(|l| l.as_deref().is_some_and(|l| l.contains(&seen)))
                }) || after.nodes.iter().any(|n| {
                    (n.id == element || element.starts_with(&format!("{}.", n.id)))
                        && std::iter::once(&n.label).chain(n.compartments.iter().flat_map(|c| &c.lines)).any(|l| {
                            let first = value.split(';').next().unwrap().trim_start_matches("var ");
                            l.contains(first)
                                || l.contains(value.split(' ').next_back().unwrap())
                                || l.contains(value.rsplit('.').next().unwrap())
                        })
                });
                let hidden = prop == "value"
                    && !graph
                        .nodes
                        .iter()
                        .any(|n| n.shape == NodeShape::Instance && element.starts_with(&format!("{}.", n.id)));
                assert!(
                    in_graph || hidden,
                    "{}: {element}.{prop} = {value} does not show in the graph",
                    file.path(&run.db)
                );
                let back = GraphOp::SetProperty { element: element.clone(), property: prop.into(), value: old.clone() };
                let now_graph = run.graph(file, &graph.id);
                run.make(file, &now_graph, &back);
                assert_eq!(
                    file.text(&run.db),
                    &before,
                    "{}: setting {element}.{prop} back to {old:?}",
                    file.path(&run.db)
                );
                *run.made.entry(prop).or_default() += 1;
            }
        }
    }
    for p in [
        "guard",
        "arguments",
        "name",
        "sourceMultiplicity",
        "targetMultiplicity",
        "parameters",
        "header",
        "component",
        "value",
        "type",
        "refused source multiplicity",
    ] {
        assert!(run.made.get(p).is_some_and(|&n| n > 0), "no {p} was set");
    }
}
