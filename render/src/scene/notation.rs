//! UML's control nodes where an activity diagram's text leaves them implicit: GU-DSL writes
//! guarded transitions straight out of an action (`[i < 10] => a; [] => b;`, the unguarded or
//! empty-guarded one drawn `[else]`) and several
//! transitions into one node, where UML draws a decision diamond that the branches leave and a
//! merge diamond that the flows meet at. The drawing gets those diamonds as nodes of its own
//! (ids `node#decision`, `node#merge`); each transition keeps its id and label, and runs from
//! the decision or into the merge. Edges end on a diamond's outline, not its bounding box
//! (`clip_to_diamond`).

use std::{
    borrow::Cow,
    collections::{HashMap, HashSet},
};

use gudsl_model::graph::{EdgeEnd, EdgeKind, Graph, GraphEdge, GraphKind, GraphNode, NodeShape};

use super::{Point, Rect};

/// The graph as drawn: `graph` with the decision and merge diamonds it leaves implicit.
pub(super) fn with_control_nodes(graph: &Graph) -> Cow<'_, Graph> {
    if graph.kind != GraphKind::Activity {
        return Cow::Borrowed(graph);
    }
    // The flows: transitions between two different nodes of the diagram, counted per node (one
    // pass: this runs on every drawing, hundreds of nodes in an editor).
    let ids: HashSet<&str> = graph.nodes.iter().map(|n| n.id.as_str()).collect();
    let is_flow = |e: &GraphEdge| {
        e.kind == EdgeKind::Transition
            && e.source.node != e.target.node
            && ids.contains(e.source.node.as_str())
            && ids.contains(e.target.node.as_str())
    };
    let mut out: HashMap<&str, (usize, bool)> = HashMap::new();
    let mut into: HashMap<&str, usize> = HashMap::new();
    for e in graph.edges.iter().filter(|e| is_flow(e)) {
        let (count, guarded) = out.entry(e.source.node.as_str()).or_default();
        *count += 1;
        *guarded |= e.label.as_deref().is_some_and(|l| l.starts_with('['));
        *into.entry(e.target.node.as_str()).or_default() += 1;
    }
    // Branches: several transitions out of a node that is no decision or fork, some guarded.
    let branching: Vec<&GraphNode> = graph
        .nodes
        .iter()
        .filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Fork))
        .filter(|n| out.get(n.id.as_str()).is_some_and(|&(count, guarded)| count >= 2 && guarded))
        .collect();
    // Meetings: several transitions into a node that is no decision, merge or join.
    let meeting: Vec<&GraphNode> = graph
        .nodes
        .iter()
        .filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Join))
        .filter(|n| into.get(n.id.as_str()).is_some_and(|&count| count >= 2))
        .collect();
    if branching.is_empty() && meeting.is_empty() {
        return Cow::Borrowed(graph);
    }
    let branches: HashSet<&str> = branching.iter().map(|n| n.id.as_str()).collect();
    let meets: HashSet<&str> = meeting.iter().map(|n| n.id.as_str()).collect();
    let mut drawn = graph.clone();
    for (edge, before) in drawn.edges.iter_mut().zip(&graph.edges) {
        if !is_flow(before) {
            continue;
        }
        if branches.contains(before.source.node.as_str()) {
            edge.source.node = format!("{}#decision", before.source.node);
            // The unguarded branch is taken when no guard holds: UML's `[else]`.
            if !before.label.as_deref().is_some_and(|l| l.starts_with('[')) {
                edge.label = Some(before.label.as_ref().map_or("[else]".to_string(), |args| format!("[else] {args}")));
            }
        }
        if meets.contains(before.target.node.as_str()) {
            edge.target.node = format!("{}#merge", before.target.node);
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
            parent: node.parent.clone(),
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

/// How far `p` lies out of the diamond inscribed in `rect`: 1 on its outline, less inside.
pub(crate) fn diamond_distance(p: Point, rect: Rect) -> f64 {
    let (a, b) = (rect.width / 2.0, rect.height / 2.0);
    (p.x - rect.x - a).abs() / a.max(1e-9) + (p.y - rect.y - b).abs() / b.max(1e-9)
}

/// Moves a route's end (its last point if `at_end`, else its first), which lies on the bounding
/// box of a diamond, along its last segment (extended past the box where it must be) onto the
/// diamond's outline.
pub(super) fn clip_to_diamond(route: &mut [Point], at_end: bool, rect: Rect) {
    let len = route.len();
    if len < 2 {
        return;
    }
    let (end, from) = if at_end { (len - 1, len - 2) } else { (0, 1) };
    let (p, e) = (route[from], route[end]);
    let along = |t: f64| Point { x: p.x + (e.x - p.x) * t, y: p.y + (e.y - p.y) * t };
    let distance = |t: f64| diamond_distance(along(t), rect);
    // The distance is convex along the ray: find its least value (ternary search), then where it
    // first falls to 1 (bisection).
    let (mut lo, mut hi) = (0.0f64, 4.0f64);
    for _ in 0..80 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if distance(m1) < distance(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    let nearest = (lo + hi) / 2.0;
    if distance(0.0) <= 1.0 || distance(nearest) > 1.0 {
        return; // the segment starts inside the diamond, or never meets it
    }
    let (mut outside, mut inside) = (0.0, nearest);
    for _ in 0..60 {
        let mid = (outside + inside) / 2.0;
        if distance(mid) > 1.0 {
            outside = mid;
        } else {
            inside = mid;
        }
    }
    route[end] = along(inside);
}
