//! The graph of an activity diagram: its nodes by kind with their headers and statements, the
//! transitions with guards and arguments, and the swimlanes as groups.

use std::collections::HashMap;

use super::{
    attribute_line, edge_id, text, visibility_mark, Compartment, EdgeEnd, EdgeKind, Graph, GraphEdge, GraphGroup,
    GraphKind, GraphNode, NodeShape,
};
use crate::ast::{self, AstNode, HasModifiers, HasName};

pub(super) fn graph(id: String, diagram: &ast::ActivityDiagram) -> Graph {
    let mut graph = Graph::new(id.clone(), GraphKind::Activity, diagram.syntax());
    graph.parameters = diagram.params().map(|p| text(&p)).collect();
    graph.owner = diagram.owner().map(|o| text(&o));
    graph.variables = variables(diagram);
    let mut lanes: Vec<(Option<String>, Vec<ast::ActivityNode>)> = Vec::new();
    for lane in diagram.swimlanes() {
        let name = lane.name().map(|n| n.text()).unwrap_or_default();
        let lane_id = format!("{id}/{name}");
        graph.groups.push(GraphGroup { id: lane_id.clone(), label: name, owner: lane.owner().map(|p| p.text()) });
        lanes.push((Some(lane_id), lane.nodes().collect()));
    }
    lanes.push((None, diagram.nodes().collect()));
    // Nested nodes (Sec. 9.2.2.3) are in their container's lane, drawn inside it (`parent`).
    for (_, nodes) in &mut lanes {
        *nodes = nodes.iter().flat_map(|n| n.and_nested()).collect();
    }
    let mut node_ids: HashMap<String, String> = HashMap::new();
    for (lane_id, nodes) in &lanes {
        for node in nodes {
            let Some(name) = node.name().map(|n| n.text()) else { continue };
            let node_id = format!("{}/{name}", lane_id.as_deref().unwrap_or(&id));
            node_ids.entry(name.clone()).or_insert_with(|| node_id.clone());
            let mut drawn = activity_node(node, node_id, name, lane_id.clone());
            let container = node.container().and_then(|c| c.name()).map(|n| n.text());
            drawn.parent = container.and_then(|c| node_ids.get(&c).cloned());
            graph.nodes.push(drawn);
        }
    }
    for node in lanes.iter().flat_map(|(_, nodes)| nodes) {
        transitions(&mut graph, node, &node_ids, &id);
    }
    graph
}

/// The diagram's variables (`public int i = 0;`) and `var`/`const` declarations, in the order
/// written, as UML writes attributes.
fn variables(diagram: &ast::ActivityDiagram) -> Vec<String> {
    diagram
        .syntax()
        .children()
        .filter_map(|node| {
            let name = |n: Option<ast::Name>| n.map(|n| n.text()).unwrap_or_default();
            if let Some(v) = ast::Variable::cast(node.clone()) {
                let read_only = v.has_modifier(crate::syntax::SyntaxKind::CONST_KW);
                let is_ref = v.has_modifier(crate::syntax::SyntaxKind::REF_KW);
                return Some(attribute_line(
                    visibility_mark(&v),
                    &name(v.name()),
                    v.type_ref(),
                    is_ref,
                    v.initializer(),
                    read_only,
                ));
            }
            let v = ast::VarDecl::cast(node)?;
            let (is_ref, read_only) = (v.has_modifier(crate::syntax::SyntaxKind::REF_KW), v.is_const());
            Some(attribute_line("", &name(v.name()), v.type_ref(), is_ref, v.initializer(), read_only))
        })
        .collect()
}

/// A node of the diagram: its shape and stereotype by kind, its parameters in the label, its
/// loop header and statements as compartments, in its swimlane (`group`).
fn activity_node(node: &ast::ActivityNode, id: String, name: String, group: Option<String>) -> GraphNode {
    let shape = match node.kind() {
        ast::NodeKind::Start => NodeShape::Start,
        ast::NodeKind::Final => NodeShape::Final,
        ast::NodeKind::Action => NodeShape::Action,
        // A decision holding nodes (UML's conditional node) is a box that can hold them.
        ast::NodeKind::Decision if node.nested_nodes().next().is_some() => NodeShape::Action,
        ast::NodeKind::Decision => NodeShape::Decision,
        ast::NodeKind::Fork => NodeShape::Fork,
        ast::NodeKind::Join => NodeShape::Join,
        ast::NodeKind::Loop => NodeShape::Loop,
        ast::NodeKind::LoopWindow => NodeShape::LoopWindow,
        ast::NodeKind::Calc => NodeShape::Calc,
        ast::NodeKind::CalcRange => NodeShape::CalcRange,
    };
    // The kinds drawn as an action box say which they are.
    let boxed_decision = shape == NodeShape::Action && node.kind() == ast::NodeKind::Decision;
    let stereotype = (boxed_decision
        || matches!(shape, NodeShape::Loop | NodeShape::LoopWindow | NodeShape::Calc | NodeShape::CalcRange))
    .then(|| node.kind().keyword().to_string());
    let params: Vec<String> = node.params().map(|p| text(&p)).collect();
    let label = if params.is_empty() { name } else { format!("{name}({})", params.join(", ")) };
    let mut compartments = Vec::new();
    if let Some(header) = node.loop_header() {
        compartments.push(Compartment::plain(Some("header".into()), loop_section_lines(&header)));
    }
    let statements: Vec<String> = node.statements().map(|s| text(&s)).collect();
    if !statements.is_empty() {
        compartments.push(Compartment::plain(None, statements));
    }
    GraphNode {
        id,
        shape,
        label,
        stereotype,
        is_abstract: false,
        compartments,
        ports: Vec::new(),
        group,
        parent: None,
        range: node.syntax().text_range(),
    }
}

/// A node's transitions as edges, labelled with their guard and arguments; an unknown target
/// still shows, as a dangling edge to its name (in the diagram `id`).
fn transitions(graph: &mut Graph, node: &ast::ActivityNode, node_ids: &HashMap<String, String>, id: &str) {
    let Some(source) = node.name().and_then(|n| node_ids.get(&n.text()).cloned()) else { return };
    for transition in node.transitions() {
        let Some(target_name) = transition.target().map(|t| t.text()) else { continue };
        let target =
            EdgeEnd::node(node_ids.get(&target_name).cloned().unwrap_or_else(|| format!("{id}/{target_name}")));
        let source = EdgeEnd::node(source.clone());
        let guard = transition.guard().map(|g| match g.condition() {
            Some(c) => format!("[{}]", text(&c)),
            // An empty guard is taken when no other is: UML's `[else]`.
            None => "[else]".to_string(),
        });
        let args = transition.arg_list().map(|a| text(&a));
        let label = match (guard, args) {
            (Some(g), Some(a)) => Some(format!("{g} {a}")),
            (g, a) => g.or(a),
        };
        graph.edges.push(GraphEdge {
            id: edge_id(graph, &source, &target),
            kind: EdgeKind::Transition,
            source,
            target,
            label,
            source_label: None,
            target_label: None,
            range: transition.syntax().text_range(),
        });
    }
}

/// A loop header's sections as the dissertation names its areas (§10.2.1.4): `setup`, `test`
/// and `increment` of `(setup; test; increment)`, the `test` of a `while` loop `(test)`; a
/// header of another shape (an error the validator reports) shows its sections as written.
fn loop_section_lines(header: &ast::LoopHeader) -> Vec<String> {
    let sections: Vec<String> = header.sections().map(|s| text(&s)).collect();
    let names: &[&str] = match sections.len() {
        1 => &["test"],
        3 => &["setup", "test", "increment"],
        _ => return sections,
    };
    names.iter().zip(&sections).filter(|(_, s)| !s.is_empty()).map(|(name, s)| format!("{name}: {s}")).collect()
}
