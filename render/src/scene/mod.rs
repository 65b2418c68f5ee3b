//! The scene: a diagram measured and laid out, as plain data — every box, text line, port,
//! edge polyline, label and swimlane at its place (as usvg resolves an SVG into a render tree).
//! [`build`] makes it from a graph, stage by stage (`build.rs`): it sizes each node from its
//! measured text (`measure`), lays the graph out (`crate::layout`), routes connections port to
//! port, and places the labels (`labels`). The writers (`svg`, `json`) only draw or serialise it.

mod arrange;
mod build;
mod channels;
mod connections;
mod detour;
mod frame;
pub(crate) mod labels;
mod maze;
pub(crate) mod measure;
mod nesting;
pub(crate) mod notation;

pub use arrange::Hints;
pub use build::build;
pub use frame::Frame;

use gudsl_model::graph::{EdgeKind, NodeShape};

pub use crate::geometry::{Point, Rect};
use crate::pins::Rows;
use crate::text::{self, Style};
use measure::{port_anchors, port_on_left, text_top, Content, PORT_INSET, PORT_REACH};
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
    /// The rows of the fresh layout the scene was arranged from (`crate::pins::Rows`): what the
    /// next fresh layout of the diagram keeps.
    pub rows: Rows,
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

/// The room a node's port symbols take left and right of its box, and their tracks where the
/// router around the boxes runs them there (`tracks_beside`; else the layout makes room for
/// them in the gaps between its ranks).
fn port_reach(node: &gudsl_model::graph::GraphNode, tracks_beside: bool) -> (f64, f64) {
    let reach = if tracks_beside { PORT_REACH + connections::TRACKS } else { PORT_REACH };
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
