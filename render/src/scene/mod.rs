//! The scene: a diagram measured and laid out, as plain data — every box, text line, port,
//! edge polyline, label and swimlane at its place (as usvg resolves an SVG into a render tree).
//! [`build`] makes it from a graph: it sizes each node from its measured text (`measure`),
//! lays the graph out (`crate::layout`), routes connections port to port, and places the labels
//! (`labels`). The writers (`svg`, `json`) only draw or serialise it.

mod arrange;
mod connections;
mod frame;
pub(crate) mod labels;
pub(crate) mod measure;
mod nesting;
pub(crate) mod notation;

pub use arrange::Hints;
pub use frame::Frame;

use std::collections::HashMap;

use gudsl_model::graph::{EdgeEnd, EdgeKind, Graph, GraphKind, NodeShape};

pub use crate::geometry::{Point, Rect};
use crate::{
    layout::{layered, layered_left_to_right, LayoutInput, LayoutNode, Spacing},
    text::{self, Style},
};
use measure::{content, label_size, port_anchors, port_on_left, text_top, Content, PORT_INSET, PORT_REACH};
use measure::{FONT_SIZE, LABEL_SIZE, PADDING};

/// A line of text at its baseline's start (or centre).
#[derive(Debug, Clone, PartialEq)]
pub struct TextLine {
    pub x: f64,
    pub y: f64,
    pub text: String,
    pub style: Style,
}

/// A laid-out diagram.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The diagram's fully qualified name.
    pub id: String,
    pub width: f64,
    pub height: f64,
    /// The frame around the diagram, with its name tab.
    pub frame: Frame,
    pub lanes: Vec<Lane>,
    pub edges: Vec<SceneEdge>,
    pub nodes: Vec<SceneNode>,
}

/// A swimlane: a partition around its nodes' column, titled `lane : owner`.
#[derive(Debug, Clone, PartialEq)]
pub struct Lane {
    pub id: String,
    pub rect: Rect,
    /// The title, centred at the top.
    pub title: TextLine,
}

#[derive(Debug, Clone, PartialEq)]
pub struct SceneNode {
    pub id: String,
    pub shape: NodeShape,
    pub rect: Rect,
    /// Stereotype and name, centred.
    pub header: Vec<TextLine>,
    pub compartments: Vec<SceneCompartment>,
    pub ports: Vec<ScenePort>,
    /// Everything the node says, unwrapped and uncollapsed: its tooltip.
    pub title: String,
    /// The node it is drawn inside (a nested component's parent).
    pub parent: Option<String>,
}

/// A compartment: the line above it and its text lines.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneCompartment {
    pub separator_y: f64,
    pub lines: Vec<TextLine>,
}

/// A port: its label inside the box, the row where its symbol sits on the border, and where
/// connections meet it.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenePort {
    pub id: String,
    pub text: TextLine,
    pub symbol_y: f64,
    pub anchor: Point,
    /// `provider` (lollipop) or `processor` (socket); `None`: no symbol.
    pub provider: Option<bool>,
    /// On the left border (a processor; its label starts at `text.x`), else on the right one
    /// (its label ends at `text.x`).
    pub left: bool,
}

#[derive(Debug, Clone, PartialEq)]
pub struct SceneEdge {
    pub id: String,
    pub kind: EdgeKind,
    /// The ids of its ends (a port's for connections and bindings).
    pub source: String,
    pub target: String,
    /// From the source's border (or port) to the target's.
    pub points: Vec<Point>,
    /// The label along the edge: a guard, arguments, a connection's name.
    pub label: Option<EdgeLabel>,
    /// The labels at its source and target end (UML's association ends: the target's role
    /// name and multiplicity at the target, the source's multiplicity at the source).
    pub tail_label: Option<EdgeLabel>,
    pub head_label: Option<EdgeLabel>,
}

/// An edge label: its box and lines, each with its baseline offset from the previous one.
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeLabel {
    pub rect: Rect,
    pub lines: Vec<(f64, String)>,
}

/// A graph's edge with both ends found: node indices, and port indices on them.
struct ResolvedEdge<'g> {
    edge: &'g gudsl_model::graph::GraphEdge,
    from: (usize, Option<usize>),
    to: (usize, Option<usize>),
}

/// Measures and lays out a graph, around the nodes `hints` pins or keeps where they were.
pub fn build(graph: &Graph, hints: Hints) -> Scene {
    let graph = &*notation::with_control_nodes(graph);
    let mut contents: Vec<Content> = graph.nodes.iter().map(content).collect();
    // A node the user resized is drawn at that size, never smaller than its text.
    for (node, content) in graph.nodes.iter().zip(&mut contents) {
        if let Some((width, height)) = hints.pins.and_then(|p| p.get(&node.id)).and_then(|pin| pin.size()) {
            content.width = content.width.max(width);
            content.height = content.height.max(height);
        }
    }
    let by_id: HashMap<&str, usize> = graph.nodes.iter().enumerate().map(|(i, n)| (n.id.as_str(), i)).collect();
    let resolve = |end: &EdgeEnd| {
        let node = *by_id.get(end.node.as_str())?;
        let port = end.port.as_ref().and_then(|id| graph.nodes[node].ports.iter().position(|p| &p.id == id));
        Some((node, port))
    };
    // Edges whose ends are both in the graph (dangling ones are not drawn).
    let edges: Vec<ResolvedEdge> = graph
        .edges
        .iter()
        .filter_map(|edge| Some(ResolvedEdge { edge, from: resolve(&edge.source)?, to: resolve(&edge.target)? }))
        .collect();
    let reaches: Vec<(f64, f64)> = graph.nodes.iter().map(port_reach).collect();
    let mut input = LayoutInput {
        // Each node with the room its port symbols take beside it.
        nodes: contents
            .iter()
            .zip(&reaches)
            .map(|(c, reach)| LayoutNode { width: reach.0 + c.width + reach.1, height: c.height })
            .collect(),
        edges: Vec::new(),
        groups: graph
            .nodes
            .iter()
            .map(|n| n.group.as_ref().and_then(|g| graph.groups.iter().position(|group| &group.id == g)))
            .collect(),
        labels: Vec::new(),
        flow: graph.kind != GraphKind::Class,
        firm: Vec::new(),
        end_labels: Vec::new(),
    };
    let texts: Vec<labels::EdgeTexts> = edges.iter().map(|e| labels::texts(e.edge)).collect();
    for (e, texts) in edges.iter().zip(&texts) {
        // Generalization and realization point upwards in UML: lay them out parent first.
        let upwards = matches!(e.edge.kind, EdgeKind::Generalization | EdgeKind::Realization);
        input.edges.push(if upwards { (e.to.0, e.from.0) } else { (e.from.0, e.to.0) });
        input.firm.push(upwards);
        // The layout makes room for the labels of the edges it routes (not port to port).
        let routed_by_layout = !(e.from.1.is_some() && e.to.1.is_some());
        let middle = Some(&texts.middle).filter(|m| routed_by_layout && !m.is_empty());
        input.labels.push(middle.map(|m| label_size(m)));
        let end =
            |lines: &Vec<String>| Some(lines).filter(|l| routed_by_layout && !l.is_empty()).map(|l| label_size(l));
        let (tail, head) = (end(&texts.tail), end(&texts.head));
        input.end_labels.push(if upwards { [head, tail] } else { [tail, head] });
    }
    // The frame's heading comes first; the diagram is laid out below it.
    let heading = frame::Heading::measure(graph);
    // Dataflow runs left to right: sources, filters, sinks; class and activity diagrams top
    // down. Between the columns of a dataflow run the ports' symbols and tracks.
    let mut nesting = nesting::Nesting::of(graph);
    let mut layout = match graph.kind {
        GraphKind::Component | GraphKind::ComponentInstance => {
            let spacing = Spacing { rank_gap: 20.0, ..Spacing::default() };
            if nesting.is_flat() {
                layered_left_to_right(&input, spacing)
            } else {
                nesting.layout(&input, &mut contents, &reaches, spacing)
            }
        }
        GraphKind::Class | GraphKind::Activity => layered(&input, Spacing::default()),
    };
    for (at, reach) in layout.positions.iter_mut().zip(&reaches) {
        at.x += reach.0;
    }
    // The layout starts at its margin; the frame's body starts below the heading.
    let (body_x, body_y) = heading.body_offset();
    let margin = Spacing::default().margin;
    layout.translate(body_x - margin, body_y - margin);
    for ((route, ends), e) in layout.edges.iter_mut().zip(&mut layout.end_labels).zip(&edges) {
        if matches!(e.edge.kind, EdgeKind::Generalization | EdgeKind::Realization) {
            route.reverse(); // drawn from the child to the parent
            ends.swap(0, 1);
        }
    }
    let to_place: Vec<arrange::Node> = graph
        .nodes
        .iter()
        .zip(&contents)
        .zip(&reaches)
        .enumerate()
        .map(|(i, ((n, c), reach))| arrange::Node {
            id: &n.id,
            width: c.width,
            height: c.height,
            reach: *reach,
            held: nesting.is_nested(i),
        })
        .collect();
    let to_route: Vec<arrange::Edge> = edges
        .iter()
        .zip(&input.end_labels)
        .map(|(e, ends)| arrange::Edge {
            id: &e.edge.id,
            source: e.edge.source.id(),
            target: e.edge.target.id(),
            from: e.from.0,
            to: e.to.0,
            end_label_width: ends.iter().flatten().map(|size| size.0).fold(0.0, f64::max),
        })
        .collect();
    arrange::arrange(&mut layout, &to_place, &to_route, hints, Point { x: body_x, y: body_y });
    // Nested components stay where their parents hold them, wherever those went.
    nesting.follow(&mut layout.positions);
    let anchors: Vec<Vec<Point>> = graph
        .nodes
        .iter()
        .zip(&contents)
        .zip(&layout.positions)
        .map(|((node, content), at)| port_anchors(node, content, *at))
        .collect();
    let boxes: Vec<Rect> = layout
        .positions
        .iter()
        .zip(&contents)
        .map(|(p, c)| Rect { x: p.x, y: p.y, width: c.width, height: c.height })
        .collect();
    // A nested component's parent is in the way of what runs outside it, its text (header and
    // port rows) in the way of everything.
    let text_areas = (0..boxes.len())
        .filter(|&i| contents[i].nested > 0.0)
        .map(|i| Rect { height: boxes[i].height - contents[i].nested, ..boxes[i] });
    let obstacles: Vec<Rect> = boxes.iter().copied().chain(text_areas).collect();
    // Connections and bindings run between ports, orthogonally (`connections`).
    let (wired, wires): (Vec<usize>, Vec<connections::Connection>) = edges
        .iter()
        .enumerate()
        .filter_map(|(k, e)| {
            let (from_port, to_port) = (e.from.1?, e.to.1?);
            let (from, to) = (anchors[e.from.0][from_port], anchors[e.to.0][to_port]);
            let faces = |node: usize, at: Point| if at.x < boxes[node].x { -1.0 } else { 1.0 };
            Some((
                k,
                connections::Connection {
                    from,
                    from_faces: faces(e.from.0, from),
                    to,
                    to_faces: faces(e.to.0, to),
                    from_port: e.edge.source.id(),
                    to_port: e.edge.target.id(),
                    // Its ends' ancestors hold it: it runs inside them.
                    inside: nesting.lineage(e.from.0).skip(1).chain(nesting.lineage(e.to.0).skip(1)).collect(),
                },
            ))
        })
        .unzip();
    for (k, route) in wired.into_iter().zip(connections::route(&wires, &obstacles)) {
        layout.edges[k] = route;
    }
    // The drawing holds every route.
    for point in layout.edges.iter().flatten() {
        layout.width = layout.width.max(point.x + 20.0);
        layout.height = layout.height.max(point.y + 20.0);
    }
    // Edges end on a diamond's outline.
    for (route, e) in layout.edges.iter_mut().zip(&edges) {
        for (node, at_end) in [(e.from.0, false), (e.to.0, true)] {
            if graph.nodes[node].shape == NodeShape::Decision && e.from.0 != e.to.0 {
                notation::clip_to_diamond(route, at_end, boxes[node]);
            }
        }
    }
    let corner = Point { x: BODY_INSET, y: heading.body_top() };
    let shared: Vec<Vec<usize>> = edges.iter().map(|e| nesting.holding_both(e.from.0, e.to.0)).collect();
    let labels =
        labels::place_all(&texts, &layout.edges, &layout.labels, &layout.end_labels, &obstacles, &shared, corner);

    // The drawing grows to hold edge labels that reach past the boxes, and lane titles.
    let width = labels.iter().flat_map(labels::Placed::all).map(|l| l.x + l.width + 8.0).fold(layout.width, f64::max);
    let height =
        labels.iter().flat_map(labels::Placed::all).map(|l| l.y + l.height + 8.0).fold(layout.height, f64::max);
    // Each swimlane's span: its nodes, the routes and labels of the edges between them, and
    // its title; the frame's body holds them all.
    let lane_spans: Vec<Option<(f64, f64)>> = graph
        .groups
        .iter()
        .map(|group| {
            let inside = |node: usize| graph.nodes[node].group.as_ref() == Some(&group.id);
            let mut members: Vec<Rect> = (0..boxes.len()).filter(|&i| inside(i)).map(|i| boxes[i]).collect();
            for ((e, route), label) in edges.iter().zip(&layout.edges).zip(&labels) {
                if inside(e.from.0) && inside(e.to.0) && !members.is_empty() {
                    members.extend(route.iter().map(|p| Rect { x: p.x, y: p.y, width: 0.0, height: 0.0 }));
                    members.extend(label.all());
                }
            }
            lane_span(group, &members, BODY_INSET)
        })
        .collect();
    let width = lane_spans.iter().flatten().fold(width, |w, &(_, right)| w.max(right + BODY_INSET));
    let (min_width, min_height) = heading.min_size();
    let (width, height) = (width.max(min_width), height.max(min_height));
    let frame = heading.place(width, height);
    // Lanes fill the frame's body, from under the heading to the frame's bottom.
    let body_top = heading.body_top();
    let body = Rect {
        x: BODY_INSET,
        y: body_top,
        width: frame.rect.width - 8.0,
        height: frame.rect.y + frame.rect.height - 4.0 - body_top,
    };

    let lanes =
        graph.groups.iter().zip(lane_spans).filter_map(|(group, span)| Some(lane_of(group, span?, body))).collect();
    let scene_edges = edges
        .iter()
        .zip(layout.edges)
        .zip(texts)
        .zip(labels)
        .map(|(((e, points), texts), at)| SceneEdge {
            id: e.edge.id.clone(),
            kind: e.edge.kind,
            source: e.edge.source.id().to_string(),
            target: e.edge.target.id().to_string(),
            label: at.middle.map(|rect| edge_label(texts.middle, rect)),
            tail_label: at.tail.map(|rect| edge_label(texts.tail, rect)),
            head_label: at.head.map(|rect| edge_label(texts.head, rect)),
            points,
        })
        .collect();
    let nodes = graph
        .nodes
        .iter()
        .zip(&contents)
        .zip(&boxes)
        .map(|((node, content), rect)| scene_node(node, content, *rect))
        .collect();
    Scene { id: graph.id.clone(), width, height, frame, lanes, edges: scene_edges, nodes }
}

/// The room a node's port symbols and their tracks take left and right of its box.
fn port_reach(node: &gudsl_model::graph::GraphNode) -> (f64, f64) {
    let reach = PORT_REACH + connections::TRACKS;
    let left = node.ports.iter().any(measure::port_on_left);
    let right = node.ports.iter().any(|p| !measure::port_on_left(p));
    (if left { reach } else { 0.0 }, if right { reach } else { 0.0 })
}

fn lane_title(group: &gudsl_model::graph::GraphGroup) -> String {
    match &group.owner {
        Some(owner) => format!("{} : {owner}", group.label),
        None => group.label.clone(),
    }
}

/// How far inside the drawing's left and right edges the frame's body is (4 inside the frame).
const BODY_INSET: f64 = frame::MARGIN + 4.0;

/// The left and right of a swimlane's partition around its members, at least as wide as its
/// title, and right of `body_left` (none without members).
fn lane_span(group: &gudsl_model::graph::GraphGroup, members: &[Rect], body_left: f64) -> Option<(f64, f64)> {
    if members.is_empty() {
        return None;
    }
    let mut left = members.iter().map(|b| b.x).fold(f64::INFINITY, f64::min) - 14.0;
    let mut right = members.iter().map(|b| b.x + b.width).fold(f64::NEG_INFINITY, f64::max) + 14.0;
    let missing = text::width(&lane_title(group), FONT_SIZE, Style::Bold) + 16.0 - (right - left);
    if missing > 0.0 {
        left -= missing / 2.0;
        right += missing / 2.0;
    }
    let shift = (body_left - left).max(0.0);
    Some((left + shift, right + shift))
}

/// A swimlane's partition from `left` to `right` (`lane_span`), as tall as the frame's `body`
/// and inside it.
fn lane_of(group: &gudsl_model::graph::GraphGroup, (left, right): (f64, f64), body: Rect) -> Lane {
    let title = lane_title(group);
    let left = left.max(body.x);
    let right = right.min(body.x + body.width);
    Lane {
        id: group.id.clone(),
        rect: Rect { x: left, y: body.y, width: right - left, height: body.height },
        title: TextLine {
            x: (left + right) / 2.0,
            y: body.y + text::ascent(FONT_SIZE) + 2.0,
            text: title,
            style: Style::Bold,
        },
    }
}

fn edge_label(lines: Vec<String>, rect: Rect) -> EdgeLabel {
    let lines = lines
        .into_iter()
        .enumerate()
        .map(|(n, line)| (if n == 0 { text::ascent(LABEL_SIZE) } else { text::line_height(LABEL_SIZE) }, line))
        .collect();
    EdgeLabel { rect, lines }
}

/// The activity nodes the dissertation draws like UML expansion regions (chapter 10): loops
/// and loop windows iterate over their ranges, calc and calcRange nodes over a GPU work grid.
fn is_expansion_region(shape: NodeShape) -> bool {
    matches!(shape, NodeShape::Loop | NodeShape::LoopWindow | NodeShape::Calc | NodeShape::CalcRange)
}

/// A node's text lines and port rows at their places: the header centred, compartments
/// left-aligned under their separators, then the ports.
fn scene_node(node: &gudsl_model::graph::GraphNode, content: &Content, rect: Rect) -> SceneNode {
    let line_h = text::line_height(FONT_SIZE);
    let ascent = text::ascent(FONT_SIZE);
    let mut cursor = text_top(node, content, rect.y);
    let mut header = Vec::new();
    for (n, (line, style)) in content.header.iter().enumerate() {
        // An expansion region's keyword sits in its top left corner (UML 2, §16.12); header
        // lines are drawn centred on their x, so the keyword's x is its middle.
        let x = if n == 0 && node.stereotype.is_some() && is_expansion_region(node.shape) {
            rect.x + PADDING + text::width(line, FONT_SIZE, *style) / 2.0
        } else {
            rect.x + rect.width / 2.0
        };
        header.push(TextLine { x, y: cursor + ascent, text: line.clone(), style: *style });
        cursor += line_h;
    }
    let mut compartments = Vec::new();
    for compartment in &content.compartments {
        cursor += PADDING / 2.0;
        let separator_y = cursor;
        cursor += PADDING / 2.0;
        let mut lines = Vec::new();
        for (line, style) in compartment {
            // A wrapped line's continuation starts indented (SVG collapses leading spaces).
            let text = line.trim_start();
            let indent = text::width(&line[..line.len() - text.len()], FONT_SIZE, Style::Regular);
            let (x, text) = (rect.x + PADDING + indent, text.to_string());
            lines.push(TextLine { x, y: cursor + ascent, text, style: *style });
            cursor += line_h;
        }
        if compartment.is_empty() {
            cursor += line_h;
        }
        compartments.push(SceneCompartment { separator_y, lines });
    }
    let anchors = port_anchors(node, content, Point { x: rect.x, y: rect.y });
    let ports = node
        .ports
        .iter()
        .zip(anchors)
        .map(|(port, anchor)| {
            let left = port_on_left(port);
            let x = if left { rect.x + PADDING + PORT_INSET } else { rect.x + rect.width - PADDING - PORT_INSET };
            let y = anchor.y - line_h * 0.45 + ascent * 0.85;
            let text = TextLine { x, y, text: port.label.clone(), style: Style::Regular };
            ScenePort { id: port.id.clone(), text, symbol_y: anchor.y, anchor, provider: port.provider, left }
        })
        .collect();
    let title = node
        .stereotype
        .iter()
        .map(|s| format!("«{s}»"))
        .chain([node.label.clone()])
        .chain(node.compartments.iter().flat_map(|c| c.lines.iter().cloned()))
        .chain(node.ports.iter().map(|p| p.label.clone()))
        .filter(|line| !line.is_empty())
        .collect::<Vec<String>>()
        .join("\n");
    let parent = node.parent.clone();
    SceneNode { id: node.id.clone(), shape: node.shape, rect, header, compartments, ports, title, parent }
}
