//! UML's control nodes where an activity diagram's text leaves them implicit: GU-DSL writes
//! guarded transitions straight out of an action (`[i < 10] => a; [else] => b;`) and several
//! transitions into one node, where UML draws a decision diamond that the branches leave and a
//! merge diamond that the flows meet at. The drawing gets those diamonds as nodes of its own
//! (ids `node#decision`, `node#merge`); each transition keeps its id and label, and runs from
//! the decision or into the merge.

use std::borrow::Cow;

use gudsl_model::graph::{EdgeEnd, EdgeKind, Graph, GraphEdge, GraphKind, GraphNode, NodeShape};

/// The graph as drawn: `graph` with the decision and merge diamonds it leaves implicit.
pub(super) fn with_control_nodes(graph: &Graph) -> Cow<'_, Graph> {
    if graph.kind != GraphKind::Activity {
        return Cow::Borrowed(graph);
    }
    let is_node = |id: &str| graph.nodes.iter().any(|n| n.id == id);
    // A node's transitions out (or in) to other nodes of the diagram.
    let transitions = |id: &str, outgoing: bool| -> Vec<&GraphEdge> {
        graph
            .edges
            .iter()
            .filter(|e| e.kind == EdgeKind::Transition && e.source.node != e.target.node)
            .filter(|e| is_node(&e.source.node) && is_node(&e.target.node))
            .filter(|e| if outgoing { e.source.node == id } else { e.target.node == id })
            .collect()
    };
    // Branches: several transitions out of a node that is no decision or fork, some guarded.
    let branching: Vec<&GraphNode> = graph
        .nodes
        .iter()
        .filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Fork))
        .filter(|n| {
            let out = transitions(&n.id, true);
            out.len() >= 2 && out.iter().any(|e| e.label.as_deref().is_some_and(|l| l.starts_with('[')))
        })
        .collect();
    // Meetings: several transitions into a node that is no decision, merge or join.
    let meeting: Vec<&GraphNode> = graph
        .nodes
        .iter()
        .filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Join))
        .filter(|n| transitions(&n.id, false).len() >= 2)
        .collect();
    if branching.is_empty() && meeting.is_empty() {
        return Cow::Borrowed(graph);
    }
    let mut drawn = graph.clone();
    let branches = |id: &str| branching.iter().any(|n| n.id == id);
    let meets = |id: &str| meeting.iter().any(|n| n.id == id);
    for edge in drawn.edges.iter_mut() {
        let (from, to) = (edge.source.node.clone(), edge.target.node.clone());
        if edge.kind != EdgeKind::Transition || from == to || !is_node(&from) || !is_node(&to) {
            continue;
        }
        if branches(&from) {
            edge.source.node = format!("{from}#decision");
        }
        if meets(&to) {
            edge.target.node = format!("{to}#merge");
        }
    }
    for (node, decision) in branching.iter().map(|n| (n, true)).chain(meeting.iter().map(|n| (n, false))) {
        let id = format!("{}#{}", node.id, if decision { "decision" } else { "merge" });
        drawn.nodes.push(GraphNode {
            id: id.clone(),
            shape: NodeShape::Decision,
            label: String::new(),
            stereotype: None,
            is_abstract: false,
            compartments: Vec::new(),
            ports: Vec::new(),
            group: node.group.clone(),
            range: node.range,
        });
        let (source, target) = if decision { (node.id.clone(), id.clone()) } else { (id.clone(), node.id.clone()) };
        drawn.edges.push(GraphEdge {
            id,
            kind: EdgeKind::Transition,
            source: EdgeEnd { node: source, port: None },
            target: EdgeEnd { node: target, port: None },
            label: None,
            source_label: None,
            target_label: None,
            range: node.range,
        });
    }
    Cow::Owned(drawn)
}
