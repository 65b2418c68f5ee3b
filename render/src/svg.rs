//! Diagram → SVG: sizes every node from its measured text, lays the graph out, and draws it in
//! UML notation (class boxes with compartments, activity nodes by kind, components with ports,
//! instances), with edge heads by kind. Deterministic: coordinates are written with two decimals.

use std::{collections::HashMap, fmt::Write};

use gudsl_model::graph::{EdgeKind, Graph, GraphNode, NodeShape};

use crate::{
    layout::{layered, Layout, LayoutInput, LayoutNode, Point, Spacing},
    text::{self, Style, FONT_FAMILY},
};

const FONT_SIZE: f64 = 12.0;
const PADDING: f64 = 8.0;
/// Lines of an action's body shown before it is collapsed to "…".
const MAX_BODY_LINES: usize = 6;
/// Longest body line shown, in characters.
const MAX_LINE_CHARS: usize = 60;
/// Edge labels (guards, arguments) wrap at spaces beyond this many characters per line.
const LABEL_LINE_CHARS: usize = 40;
/// Font size of edge labels.
const LABEL_SIZE: f64 = FONT_SIZE * 0.85;

/// A node's drawn content: header lines (stereotype, name) and compartments of lines.
struct Content {
    header: Vec<(String, Style)>,
    compartments: Vec<Vec<String>>,
    width: f64,
    height: f64,
}

/// A port's line: its notation symbol (provider lollipop ○, processor socket ◐) and label.
fn port_text(port: &gudsl_model::graph::GraphPort) -> String {
    let symbol = match port.provider {
        Some(true) => "○",
        Some(false) => "◐",
        None => "□",
    };
    format!("{symbol} {}", port.label)
}

/// An edge label as lines of at most `LABEL_LINE_CHARS` characters, broken at spaces (a word
/// longer than that gets a line of its own).
fn label_lines(label: &str) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in label.split(' ') {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= LABEL_LINE_CHARS => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The width and height of an edge label as drawn.
fn label_size(label: &str) -> (f64, f64) {
    let lines = label_lines(label);
    let width = lines.iter().map(|line| text::width(line, LABEL_SIZE, Style::Regular)).fold(0.0, f64::max);
    (width, text::line_height(LABEL_SIZE) * lines.len() as f64)
}

fn shorten(line: &str) -> String {
    if line.chars().count() > MAX_LINE_CHARS {
        format!("{}…", line.chars().take(MAX_LINE_CHARS - 1).collect::<String>())
    } else {
        line.to_string()
    }
}

fn content(node: &GraphNode) -> Content {
    let line_h = text::line_height(FONT_SIZE);
    match node.shape {
        NodeShape::Start => return Content { header: Vec::new(), compartments: Vec::new(), width: 20.0, height: 20.0 },
        NodeShape::Final => return Content { header: Vec::new(), compartments: Vec::new(), width: 24.0, height: 24.0 },
        NodeShape::Fork | NodeShape::Join => {
            return Content { header: Vec::new(), compartments: Vec::new(), width: 80.0, height: 8.0 };
        }
        _ => {}
    }
    let mut header = Vec::new();
    if let Some(stereotype) = &node.stereotype {
        header.push((format!("«{stereotype}»"), Style::Regular));
    }
    let name_style = if node.is_abstract { Style::Oblique } else { Style::Bold };
    header.push((node.label.clone(), name_style));
    let mut compartments: Vec<Vec<String>> = node
        .compartments
        .iter()
        .map(|c| {
            let mut lines: Vec<String> = c.lines.iter().map(|l| shorten(l)).collect();
            if matches!(
                node.shape,
                NodeShape::Action | NodeShape::Calc | NodeShape::CalcRange | NodeShape::Loop | NodeShape::LoopWindow
            ) && lines.len() > MAX_BODY_LINES
            {
                let hidden = lines.len() - MAX_BODY_LINES + 1;
                lines.truncate(MAX_BODY_LINES - 1);
                lines.push(format!("… {hidden} more"));
            }
            lines
        })
        .collect();
    if matches!(node.shape, NodeShape::Class | NodeShape::Interface | NodeShape::Enum | NodeShape::Attribute)
        && compartments.is_empty()
    {
        compartments.push(Vec::new());
    }
    let widest_header = header.iter().map(|(t, s)| text::width(t, FONT_SIZE, *s)).fold(0.0, f64::max);
    let widest_line =
        compartments.iter().flatten().map(|l| text::width(l, FONT_SIZE, Style::Regular)).fold(0.0, f64::max);
    let ports_width =
        node.ports.iter().map(|p| text::width(&port_text(p), FONT_SIZE * 0.85, Style::Regular)).fold(0.0, f64::max);
    let mut width = widest_header.max(widest_line).max(ports_width) + 2.0 * PADDING;
    let mut height = text_height(header.len(), &compartments, 0);
    if node.shape == NodeShape::Decision {
        // A diamond holds its label in the middle half.
        width = width * 1.6 + 10.0;
        height = height * 1.6 + 10.0;
    }
    if node.shape == NodeShape::Component {
        width += 24.0; // the component icon
    }
    height += node.ports.len() as f64 * line_h * 0.9;
    Content { header, compartments, width: width.max(40.0), height: height.max(30.0) }
}

/// The height of a node's text: header lines, compartments (an empty one keeps one line) with
/// their separators, and the port lines.
fn text_height(header_lines: usize, compartments: &[Vec<String>], ports: usize) -> f64 {
    let line_h = text::line_height(FONT_SIZE);
    let lines = header_lines + compartments.iter().map(|c| c.len().max(1)).sum::<usize>();
    lines as f64 * line_h + (1 + compartments.len()) as f64 * PADDING + ports as f64 * line_h * 0.9
}

/// Where a node's text starts: its block centred vertically in a box whose top is `top`.
fn text_top(node: &GraphNode, content: &Content, top: f64) -> f64 {
    let block = text_height(content.header.len(), &content.compartments, node.ports.len());
    top + (content.height - block).max(0.0) / 2.0 + PADDING / 2.0
}

/// Where connections meet each port of a node: just outside its lollipop or socket on the
/// right border (the rows `draw_node` writes them in).
fn port_anchors(node: &GraphNode, content: &Content, at: Point) -> Vec<Point> {
    let line_h = text::line_height(FONT_SIZE);
    let mut cursor = text_top(node, content, at.y) + content.header.len() as f64 * line_h;
    for compartment in &content.compartments {
        cursor += PADDING + compartment.len().max(1) as f64 * line_h;
    }
    (0..node.ports.len())
        .map(|i| Point { x: at.x + content.width + 24.0, y: cursor + line_h * 0.45 + i as f64 * line_h * 0.9 })
        .collect()
}

/// A graph arranged for drawing: node contents, the layout, and the edges it routed.
struct Arranged<'g> {
    contents: Vec<Content>,
    layout: Layout,
    edges: Vec<&'g gudsl_model::graph::GraphEdge>,
    /// Each edge's label box (x, y, width, height), placed clear of the boxes and other labels.
    labels: Vec<Option<(f64, f64, f64, f64)>>,
}

fn arrange(graph: &Graph) -> Arranged<'_> {
    let contents: Vec<Content> = graph.nodes.iter().map(content).collect();
    // An edge end is a node's id, or a port's: the node's id, a dot and more.
    let by_id: HashMap<&str, usize> = graph.nodes.iter().enumerate().map(|(i, n)| (n.id.as_str(), i)).collect();
    let index_of = |id: &str| {
        let prefixes = id.match_indices('.').map(|(dot, _)| &id[..dot]).rev();
        std::iter::once(id).chain(prefixes).find_map(|prefix| by_id.get(prefix).copied())
    };
    let mut edges = Vec::new();
    let mut input = LayoutInput {
        nodes: contents.iter().map(|c| LayoutNode { width: c.width, height: c.height }).collect(),
        edges: Vec::new(),
        groups: graph
            .nodes
            .iter()
            .map(|n| n.group.as_ref().and_then(|g| graph.groups.iter().position(|group| &group.id == g)))
            .collect(),
        labels: Vec::new(),
    };
    let is_port = |id: &str| graph.nodes.iter().any(|n| n.ports.iter().any(|p| p.id == id));
    for edge in &graph.edges {
        if let (Some(a), Some(b)) = (index_of(&edge.source), index_of(&edge.target)) {
            // Generalization and realization point upwards in UML: lay them out parent first.
            let (from, to) = match edge.kind {
                EdgeKind::Generalization | EdgeKind::Realization => (b, a),
                _ => (a, b),
            };
            input.edges.push((from, to));
            // The layout makes room for the labels of the edges it routes (not port to port).
            let routed_by_layout = !(is_port(&edge.source) && is_port(&edge.target));
            input.labels.push(edge.label.as_deref().filter(|_| routed_by_layout).map(label_size));
            edges.push(edge);
        }
    }
    let mut layout = layered(&input, Spacing::default());
    for (route, edge) in layout.edges.iter_mut().zip(&edges) {
        if matches!(edge.kind, EdgeKind::Generalization | EdgeKind::Realization) {
            route.reverse(); // drawn from the child to the parent
        }
    }
    // Connections and bindings run between ports: out of the source port to a vertical lane
    // right of every box, then into the target port.
    let anchor_of = |id: &str| {
        graph.nodes.iter().zip(&contents).zip(&layout.positions).find_map(|((node, content), at)| {
            node.ports.iter().position(|p| p.id == id).map(|i| port_anchors(node, content, *at)[i])
        })
    };
    let right_of_boxes = layout.positions.iter().zip(&contents).map(|(p, c)| p.x + c.width).fold(0.0, f64::max) + 40.0;
    let spans: Vec<(f64, f64)> = layout.positions.iter().zip(&contents).map(|(p, c)| (p.y, p.y + c.height)).collect();
    // The gap below (or above) every box that shares `y`'s band: clear of all boxes there.
    let below = |y: f64| spans.iter().filter(|(t, b)| *t <= y && y <= *b).map(|(_, b)| *b).fold(y, f64::max) + 16.0;
    let above = |y: f64| spans.iter().filter(|(t, b)| *t <= y && y <= *b).map(|(t, _)| *t).fold(y, f64::min) - 16.0;
    let mut lane = 0.0;
    for (route, edge) in layout.edges.iter_mut().zip(&edges) {
        if let (Some(from), Some(to)) = (anchor_of(&edge.source), anchor_of(&edge.target)) {
            let x = right_of_boxes + lane;
            lane += 14.0;
            // Out of the port, into the gap between the rows, along it to the lane, and back
            // in the same way to the target port: no segment crosses a box.
            let (out_y, in_y) =
                if to.y >= from.y { (below(from.y), above(to.y)) } else { (above(from.y), below(to.y)) };
            let (fx, tx) = (from.x + 8.0, to.x + 8.0);
            *route = vec![
                from,
                Point { x: fx, y: from.y },
                Point { x: fx, y: out_y },
                Point { x, y: out_y },
                Point { x, y: in_y },
                Point { x: tx, y: in_y },
                Point { x: tx, y: to.y },
                to,
            ];
        }
    }
    layout.width = layout.width.max(right_of_boxes + lane + 20.0);
    let obstacles: Vec<(f64, f64, f64, f64)> =
        layout.positions.iter().zip(&contents).map(|(p, c)| (p.x, p.y, c.width, c.height)).collect();
    let mut placed: Vec<(f64, f64, f64, f64)> = Vec::new();
    let mut labels = Vec::with_capacity(edges.len());
    let routes: Vec<&[Point]> = layout.edges.iter().map(Vec::as_slice).collect();
    for ((edge, route), laid_out) in edges.iter().zip(&layout.edges).zip(&layout.labels) {
        let label = edge.label.as_ref().map(|label| {
            let chosen = match laid_out {
                Some(at) => {
                    let (w, h) = label_size(label);
                    (at.x, at.y, w, h)
                }
                None => place_label(route, label, &obstacles, &placed, &routes),
            };
            placed.push(chosen);
            chosen
        });
        labels.push(label);
    }
    Arranged { contents, layout, edges, labels }
}

fn intersects(a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> bool {
    a.0 < b.0 + b.2 && b.0 < a.0 + a.2 && a.1 < b.1 + b.3 && b.1 < a.1 + a.3
}

/// A box for `label` beside its edge, clear of every node, already placed label and edge (its
/// own included) if any candidate is (along each segment, on either side); else clear of nodes
/// and labels; else the middle of the edge.
fn place_label(
    route: &[Point],
    label: &str,
    obstacles: &[(f64, f64, f64, f64)],
    placed: &[(f64, f64, f64, f64)],
    routes: &[&[Point]],
) -> (f64, f64, f64, f64) {
    let (w, h) = label_size(label);
    let mut candidates = Vec::new();
    for fraction in [0.5, 0.3, 0.7, 0.15, 0.85] {
        for segment in route.windows(2) {
            let p = Point {
                x: segment[0].x + (segment[1].x - segment[0].x) * fraction,
                y: segment[0].y + (segment[1].y - segment[0].y) * fraction,
            };
            let beside = [(p.x + 4.0, p.y - h / 2.0), (p.x - 4.0 - w, p.y - h / 2.0)];
            let over = [(p.x - w / 2.0, p.y - h - 3.0), (p.x - w / 2.0, p.y + 3.0)];
            // Beside a vertical segment, over or under a horizontal one: never across the line.
            let horizontal = (segment[1].x - segment[0].x).abs() > (segment[1].y - segment[0].y).abs();
            let (preferred, other) = if horizontal { (over, beside) } else { (beside, over) };
            // Off a slanted segment: the two corners at `p` that the line does not pass through.
            let corners = [
                (p.x + 4.0, p.y - h - 4.0),
                (p.x - 4.0 - w, p.y + 4.0),
                (p.x - 4.0 - w, p.y - h - 4.0),
                (p.x + 4.0, p.y + 4.0),
            ];
            candidates.extend(preferred);
            candidates.extend(other);
            candidates.extend(corners);
        }
    }
    let clear = |b: (f64, f64, f64, f64)| {
        let padded = (b.0 - 2.0, b.1 - 2.0, b.2 + 4.0, b.3 + 4.0);
        b.0 >= 0.0 && b.1 >= 0.0 && !obstacles.iter().chain(placed).any(|o| intersects(padded, *o))
    };
    let boxes: Vec<(f64, f64, f64, f64)> = candidates.into_iter().map(|(x, y)| (x, y, w, h)).collect();
    let off_edges = |b: &(f64, f64, f64, f64)| {
        !routes.iter().any(|route| route.windows(2).any(|s| segment_meets_box(s[0], s[1], *b)))
    };
    let clear_of_all = boxes.iter().copied().find(|b| clear(*b) && off_edges(b));
    clear_of_all.or_else(|| boxes.iter().copied().find(|b| clear(*b))).unwrap_or_else(|| {
        let mid = midpoint(route);
        (mid.x + 4.0, mid.y - h / 2.0, w, h)
    })
}

/// Renders a diagram graph as an SVG document.
pub fn render(graph: &Graph) -> String {
    let arranged = arrange(graph);
    write_svg(graph, &arranged)
}

/// The computed geometry as the neutral JSON of `research/layout_metrics.py`: node boxes, edge
/// polylines and label boxes (x, y = top-left), so layouts can be scored like dot's.
pub fn layout_json(graph: &Graph) -> String {
    let arranged = arrange(graph);
    let json_str = |s: &str| format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""));
    let mut nodes = Vec::new();
    for ((node, content), at) in graph.nodes.iter().zip(&arranged.contents).zip(&arranged.layout.positions) {
        nodes.push(format!(
            r#"{{"id":{},"x":{},"y":{},"w":{},"h":{}}}"#,
            json_str(&node.id),
            f(at.x),
            f(at.y),
            f(content.width),
            f(content.height)
        ));
    }
    let mut edges = Vec::new();
    let mut labels = Vec::new();
    for (i, (edge, points)) in arranged.edges.iter().zip(&arranged.layout.edges).enumerate() {
        let pts: Vec<String> = points.iter().map(|p| format!("[{},{}]", f(p.x), f(p.y))).collect();
        edges.push(format!(
            r#"{{"src":{},"dst":{},"points":[{}]}}"#,
            json_str(&edge.source),
            json_str(&edge.target),
            pts.join(",")
        ));
        if let Some((x, y, w, h)) = arranged.labels[i] {
            labels.push(format!(r#"{{"edge":{i},"kind":"mid","x":{},"y":{},"w":{},"h":{}}}"#, f(x), f(y), f(w), f(h)));
        }
    }
    format!("{{\"nodes\":[{}],\"edges\":[{}],\"labels\":[{}]}}\n", nodes.join(","), edges.join(","), labels.join(","))
}

fn f(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

fn write_svg(graph: &Graph, arranged: &Arranged) -> String {
    let (contents, layout, edges) = (&arranged.contents, &arranged.layout, &arranged.edges);
    let mut out = String::new();
    // The drawing grows to hold edge labels that reach past the boxes.
    let w = arranged.labels.iter().flatten().map(|l| l.0 + l.2 + 8.0).fold(layout.width, f64::max);
    let h = arranged.labels.iter().flatten().map(|l| l.1 + l.3 + 8.0).fold(layout.height, f64::max);
    let w = graph
        .groups
        .iter()
        .map(|g| {
            text::width(&g.label, FONT_SIZE, Style::Bold)
                + g.owner.as_ref().map_or(0.0, |o| text::width(&format!(" : {o}"), FONT_SIZE, Style::Bold))
        })
        .fold(w, |w, title| w.max(title + 40.0));
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}" height="{}" viewBox="0 0 {} {}" font-family="{FONT_FAMILY}" font-size="{}">"#,
        f(w),
        f(h),
        f(w),
        f(h),
        f(FONT_SIZE)
    );
    let _ = writeln!(out, "<title>{}</title>", escape(&graph.id));
    out.push_str(concat!(
        "<defs>",
        r#"<marker id="open" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="10" markerHeight="10" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10" fill="none" stroke="black"/></marker>"#,
        r#"<marker id="filled" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="9" markerHeight="9" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="black"/></marker>"#,
        r#"<marker id="triangle" viewBox="0 0 12 12" refX="12" refY="6" markerWidth="12" markerHeight="12" orient="auto-start-reverse"><path d="M0,0 L12,6 L0,12 z" fill="white" stroke="black"/></marker>"#,
        r#"<marker id="diamond" viewBox="0 0 16 10" refX="0" refY="5" markerWidth="16" markerHeight="10" orient="auto"><path d="M0,5 L8,0 L16,5 L8,10 z" fill="white" stroke="black"/></marker>"#,
        r#"<marker id="diamond-filled" viewBox="0 0 16 10" refX="0" refY="5" markerWidth="16" markerHeight="10" orient="auto"><path d="M0,5 L8,0 L16,5 L8,10 z" fill="black"/></marker>"#,
        "</defs>\n"
    ));
    let _ = writeln!(out, r#"<rect width="{}" height="{}" fill="white"/>"#, f(w), f(h));
    // Swimlanes: partitions around their nodes' column, titled with the lane and its owner.
    for group in &graph.groups {
        let members: Vec<(Point, &Content)> = graph
            .nodes
            .iter()
            .zip(contents)
            .zip(&layout.positions)
            .filter(|((n, _), _)| n.group.as_ref() == Some(&group.id))
            .map(|((_, c), p)| (*p, c))
            .collect();
        if members.is_empty() {
            continue;
        }
        let mut left = members.iter().map(|(p, _)| p.x).fold(f64::INFINITY, f64::min) - 14.0;
        let mut right = members.iter().map(|(p, c)| p.x + c.width).fold(f64::NEG_INFINITY, f64::max) + 14.0;
        let title = match &group.owner {
            Some(owner) => format!("{} : {owner}", group.label),
            None => group.label.clone(),
        };
        // The partition is at least as wide as its title.
        let missing = text::width(&title, FONT_SIZE, Style::Bold) + 16.0 - (right - left);
        if missing > 0.0 {
            left -= missing / 2.0;
            right += missing / 2.0;
        }
        left = left.max(1.0);
        right = right.min(w - 1.0);
        let _ = writeln!(
            out,
            r##"<g class="swimlane" data-id="{}"><rect x="{}" y="2" width="{}" height="{}" fill="none" stroke="#888"/><text x="{}" y="{}" text-anchor="middle" font-weight="bold" fill="#555">{}</text></g>"##,
            escape(&group.id),
            f(left),
            f(right - left),
            f(h - 4.0),
            f((left + right) / 2.0),
            f(2.0 + text::ascent(FONT_SIZE) + 2.0),
            escape(&title)
        );
    }
    for (i, edge) in edges.iter().enumerate() {
        let Some(points) = layout.edges.get(i) else { continue };
        let path: Vec<String> = points.iter().map(|p| format!("{},{}", f(p.x), f(p.y))).collect();
        let (dash, start, end) = match edge.kind {
            EdgeKind::Generalization => ("", "", r#" marker-end="url(#triangle)""#),
            EdgeKind::Realization => (r#" stroke-dasharray="6,4""#, "", r#" marker-end="url(#triangle)""#),
            EdgeKind::Association => ("", "", r#" marker-end="url(#open)""#),
            EdgeKind::Aggregation => ("", r#" marker-start="url(#diamond)""#, ""),
            EdgeKind::Composition => ("", r#" marker-start="url(#diamond-filled)""#, ""),
            EdgeKind::Transition | EdgeKind::Connection | EdgeKind::Binding => {
                ("", "", r#" marker-end="url(#filled)""#)
            }
        };
        let _ = writeln!(
            out,
            r#"<polyline class="edge" data-id="{}" points="{}" fill="none" stroke="black"{dash}{start}{end}/>"#,
            escape(&edge.id),
            path.join(" ")
        );
        // Multiplicities beside each end of an association (source end, then target end).
        for (multiplicity, end, next) in [
            (&edge.source_label, points.first(), points.get(1)),
            (&edge.target_label, points.last(), points.len().checked_sub(2).and_then(|i| points.get(i))),
        ] {
            if let (Some(text_value), Some(end), Some(next)) =
                (multiplicity.as_ref().filter(|m| !m.is_empty()), end, next)
            {
                let (dx, dy) = (next.x - end.x, next.y - end.y);
                let len = (dx * dx + dy * dy).sqrt().max(1e-9);
                // Beside the edge, on the side it turns away to (right of a straight one).
                let leftwards = dx < -0.5;
                let side = if leftwards { -6.0 } else { 6.0 };
                let (px, py) = (end.x + dx / len * 14.0 + side, end.y + dy / len * 14.0);
                let anchor = if leftwards { r#" text-anchor="end""# } else { "" };
                let _ = writeln!(
                    out,
                    r##"<text class="multiplicity" x="{}" y="{}"{anchor} font-size="{}" fill="#333">{}</text>"##,
                    f(px),
                    f(py + text::ascent(FONT_SIZE * 0.8) / 2.0),
                    f(FONT_SIZE * 0.8),
                    escape(text_value)
                );
            }
        }
        if let (Some(label), Some((x, y, _, _))) = (&edge.label, arranged.labels[i]) {
            let lines: Vec<String> = label_lines(label)
                .iter()
                .enumerate()
                .map(|(n, line)| {
                    let dy = if n == 0 { text::ascent(LABEL_SIZE) } else { text::line_height(LABEL_SIZE) };
                    format!(r#"<tspan x="{}" dy="{}">{}</tspan>"#, f(x), f(dy), escape(line))
                })
                .collect();
            let _ = writeln!(
                out,
                r##"<text class="edge-label" y="{}" font-size="{}" fill="#333">{}</text>"##,
                f(y),
                f(LABEL_SIZE),
                lines.join("")
            );
        }
    }
    for ((node, content), position) in graph.nodes.iter().zip(contents).zip(&layout.positions) {
        draw_node(&mut out, node, content, *position);
    }
    out.push_str("</svg>\n");
    out
}

/// Whether the segment from `a` to `b` passes through the box `(x, y, width, height)`
/// (Liang–Barsky clipping).
fn segment_meets_box(a: Point, b: Point, (x, y, w, h): (f64, f64, f64, f64)) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.x - x), (dx, x + w - a.x), (-dy, a.y - y), (dy, y + h - a.y)] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    t0 <= t1
}

fn midpoint(points: &[Point]) -> Point {
    if points.len() % 2 == 1 {
        return points[points.len() / 2];
    }
    let (a, b) = (points[points.len() / 2 - 1], points[points.len() / 2]);
    Point { x: (a.x + b.x) / 2.0, y: (a.y + b.y) / 2.0 }
}

fn draw_node(out: &mut String, node: &GraphNode, content: &Content, at: Point) {
    let (x, y, w, h) = (at.x, at.y, content.width, content.height);
    let id = escape(&node.id);
    let _ = write!(out, r#"<g class="node" data-id="{id}">"#);
    match node.shape {
        NodeShape::Start => {
            let _ = write!(
                out,
                r#"<circle cx="{}" cy="{}" r="{}" fill="black"/>"#,
                f(x + w / 2.0),
                f(y + h / 2.0),
                f(w / 2.0)
            );
        }
        NodeShape::Final => {
            let (cx, cy) = (f(x + w / 2.0), f(y + h / 2.0));
            let _ = write!(
                out,
                r#"<circle cx="{cx}" cy="{cy}" r="{}" fill="white" stroke="black"/><circle cx="{cx}" cy="{cy}" r="{}" fill="black"/>"#,
                f(w / 2.0),
                f(w / 2.0 - 5.0)
            );
        }
        NodeShape::Fork | NodeShape::Join => {
            let _ = write!(out, r#"<rect x="{}" y="{}" width="{}" height="{}" fill="black"/>"#, f(x), f(y), f(w), f(h));
        }
        NodeShape::Decision => {
            let _ = write!(
                out,
                r#"<polygon points="{},{} {},{} {},{} {},{}" fill="white" stroke="black"/>"#,
                f(x + w / 2.0),
                f(y),
                f(x + w),
                f(y + h / 2.0),
                f(x + w / 2.0),
                f(y + h),
                f(x),
                f(y + h / 2.0)
            );
        }
        NodeShape::Action | NodeShape::Calc | NodeShape::CalcRange | NodeShape::Loop | NodeShape::LoopWindow => {
            let fill = match node.shape {
                NodeShape::Calc | NodeShape::CalcRange => "#eef4ff",
                NodeShape::Loop | NodeShape::LoopWindow => "#f2fbef",
                _ => "white",
            };
            let _ = write!(
                out,
                r#"<rect x="{}" y="{}" width="{}" height="{}" rx="10" fill="{fill}" stroke="black"/>"#,
                f(x),
                f(y),
                f(w),
                f(h)
            );
        }
        _ => {
            let dash = if node.shape == NodeShape::External { r#" stroke-dasharray="4,3""# } else { "" };
            let _ = write!(
                out,
                r#"<rect x="{}" y="{}" width="{}" height="{}" fill="white" stroke="black"{dash}/>"#,
                f(x),
                f(y),
                f(w),
                f(h)
            );
            if node.shape == NodeShape::Component {
                // The UML component icon in the top right corner.
                let (ix, iy) = (x + w - 20.0, y + 6.0);
                let _ = write!(
                    out,
                    r#"<rect x="{}" y="{}" width="12" height="14" fill="white" stroke="black"/><rect x="{}" y="{}" width="6" height="3" fill="white" stroke="black"/><rect x="{}" y="{}" width="6" height="3" fill="white" stroke="black"/>"#,
                    f(ix),
                    f(iy),
                    f(ix - 3.0),
                    f(iy + 3.0),
                    f(ix - 3.0),
                    f(iy + 8.0)
                );
            }
        }
    }
    // Text: header centred, compartments left-aligned under separators.
    let line_h = text::line_height(FONT_SIZE);
    let ascent = text::ascent(FONT_SIZE);
    let mut cursor = text_top(node, content, y);
    for (line, style) in &content.header {
        let weight = match style {
            Style::Bold => r#" font-weight="bold""#,
            Style::Oblique => r#" font-style="italic""#,
            Style::Regular => "",
        };
        let _ = write!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle"{weight}>{}</text>"#,
            f(x + w / 2.0),
            f(cursor + ascent),
            escape(line)
        );
        cursor += line_h;
    }
    let boxed = matches!(
        node.shape,
        NodeShape::Class | NodeShape::Interface | NodeShape::Enum | NodeShape::Attribute | NodeShape::Instance
    );
    for compartment in &content.compartments {
        cursor += PADDING / 2.0;
        if boxed {
            let _ = write!(
                out,
                r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="black"/>"#,
                f(x),
                f(cursor),
                f(x + w),
                f(cursor)
            );
        }
        cursor += PADDING / 2.0;
        for line in compartment {
            let _ = write!(out, r#"<text x="{}" y="{}">{}</text>"#, f(x + PADDING), f(cursor + ascent), escape(line));
            cursor += line_h;
        }
        if compartment.is_empty() {
            cursor += line_h;
        }
    }
    for port in &node.ports {
        let _ = write!(
            out,
            r#"<text class="port" data-id="{}" x="{}" y="{}" font-size="{}">{}</text>"#,
            escape(&port.id),
            f(x + PADDING),
            f(cursor + ascent * 0.85),
            f(FONT_SIZE * 0.85),
            escape(&port_text(port))
        );
        // UML port notation on the right border: a square on the boundary, then a lollipop
        // (provided interface) or a socket (required interface).
        let cy = cursor + line_h * 0.45;
        let bx = x + w;
        let _ = write!(
            out,
            r#"<rect x="{}" y="{}" width="8" height="8" fill="white" stroke="black"/>"#,
            f(bx - 4.0),
            f(cy - 4.0)
        );
        match port.provider {
            Some(true) => {
                let _ = write!(
                    out,
                    r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="black"/><circle cx="{}" cy="{}" r="5" fill="white" stroke="black"/>"#,
                    f(bx + 4.0),
                    f(cy),
                    f(bx + 12.0),
                    f(cy),
                    f(bx + 17.0),
                    f(cy)
                );
            }
            Some(false) => {
                let _ = write!(
                    out,
                    r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="black"/><path d="M{},{} A6,6 0 0,0 {},{}" fill="none" stroke="black"/>"#,
                    f(bx + 4.0),
                    f(cy),
                    f(bx + 12.0),
                    f(cy),
                    f(bx + 18.0),
                    f(cy - 6.0),
                    f(bx + 18.0),
                    f(cy + 6.0)
                );
            }
            None => {}
        }
        cursor += line_h * 0.9;
    }
    out.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use gudsl_model::AnalysisHost;

    use super::*;

    fn sample_graphs() -> Vec<Graph> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
        let mut files = Vec::new();
        for dir in ["seed", "framework"] {
            let mut entries: Vec<_> = std::fs::read_dir(root.join(dir)).unwrap().flatten().map(|e| e.path()).collect();
            entries.sort();
            for path in entries.into_iter().filter(|p| p.extension().is_some_and(|e| e == "gudsl")) {
                files.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
            }
        }
        let (host, files) = AnalysisHost::with_files(files);
        let analysis = host.analysis();
        files.iter().flat_map(|&f| analysis.graphs(f).unwrap().to_vec()).collect()
    }

    #[test]
    fn every_sample_diagram_renders_deterministically() {
        let graphs = sample_graphs();
        assert!(graphs.len() > 40);
        for graph in &graphs {
            let svg = render(graph);
            assert!(svg.starts_with("<svg ") && svg.ends_with("</svg>\n"), "{}", graph.id);
            assert_eq!(svg, render(graph), "{}: not deterministic", graph.id);
            assert_eq!(svg.matches("<g class=\"node\"").count(), graph.nodes.len(), "{}", graph.id);
            assert!(!svg.contains("NaN") && !svg.contains("inf"), "{}", graph.id);
        }
    }

    #[test]
    fn every_sample_svg_rasterizes_with_resvg() {
        for graph in sample_graphs().iter() {
            let png = crate::png::to_png(&render(graph), 1.0).unwrap_or_else(|e| panic!("{}: {e}", graph.id));
            assert!(png.starts_with(b"\x89PNG"), "{}", graph.id);
        }
        for graph in sample_graphs() {
            crate::png::parse(&render(&graph)).unwrap_or_else(|e| panic!("{}: {e}", graph.id));
        }
    }

    #[test]
    fn layout_json_is_the_metrics_script_format() {
        for graph in sample_graphs().iter().take(8) {
            let json = layout_json(graph);
            assert!(json.starts_with("{\"nodes\":[{\"id\":"), "{json}");
            assert!(json.contains("\"edges\":[") && json.contains("\"labels\":["));
            assert_eq!(json.matches("\"w\":").count() - json.matches("\"kind\":\"mid\"").count(), graph.nodes.len());
        }
    }

    /// Geometry of every sample diagram: boxes do not overlap, no label covers a box, and every
    /// edge starts and ends on the border of its boxes.
    #[test]
    fn sample_geometry_is_clean() {
        for graph in sample_graphs() {
            let arranged = arrange(&graph);
            let boxes: Vec<(f64, f64, f64, f64)> = arranged
                .layout
                .positions
                .iter()
                .zip(&arranged.contents)
                .map(|(p, c)| (p.x, p.y, c.width, c.height))
                .collect();
            for a in 0..boxes.len() {
                for b in a + 1..boxes.len() {
                    assert!(
                        !intersects(boxes[a], boxes[b]),
                        "{}: {} overlaps {}",
                        graph.id,
                        graph.nodes[a].id,
                        graph.nodes[b].id
                    );
                }
            }
            for (label, edge) in arranged.labels.iter().zip(&arranged.edges) {
                if let Some(label) = label {
                    for (route, other) in arranged.layout.edges.iter().zip(&arranged.edges) {
                        let crossed = route.windows(2).any(|s| segment_meets_box(s[0], s[1], *label));
                        assert!(!crossed, "{}: label of {} is crossed by {}", graph.id, edge.id, other.id);
                    }
                    for (i, b) in boxes.iter().enumerate() {
                        assert!(
                            !intersects(*label, *b),
                            "{}: label of {} covers {}",
                            graph.id,
                            edge.id,
                            graph.nodes[i].id
                        );
                    }
                }
            }
            let index_of =
                |id: &str| graph.nodes.iter().position(|n| id == n.id || id.starts_with(&format!("{}.", n.id)));
            for (edge, route) in arranged.edges.iter().zip(&arranged.layout.edges) {
                let (Some(s), Some(t)) = (index_of(&edge.source), index_of(&edge.target)) else { continue };
                if s == t {
                    continue;
                }
                // Port-to-port edges end at the ports' anchors, right of the boxes.
                let port_anchor = |node: usize, id: &str| {
                    graph.nodes[node].ports.iter().position(|p| p.id == id).map(|i| {
                        port_anchors(&graph.nodes[node], &arranged.contents[node], arranged.layout.positions[node])[i]
                    })
                };
                if let (Some(a), Some(b)) = (port_anchor(s, &edge.source), port_anchor(t, &edge.target)) {
                    assert_eq!(route[0], a, "{}: {} does not start at its port", graph.id, edge.id);
                    assert_eq!(*route.last().unwrap(), b, "{}: {} does not end at its port", graph.id, edge.id);
                    // Axis-parallel segments: none may pass through a box.
                    for segment in route.windows(2) {
                        let (x0, x1) = (segment[0].x.min(segment[1].x), segment[0].x.max(segment[1].x));
                        let (y0, y1) = (segment[0].y.min(segment[1].y), segment[0].y.max(segment[1].y));
                        for (i, bx) in boxes.iter().enumerate() {
                            let hit = x0 < bx.0 + bx.2
                                && bx.0 < x1.max(x0 + 0.01)
                                && y0 < bx.1 + bx.3
                                && bx.1 < y1.max(y0 + 0.01);
                            assert!(!hit, "{}: {} passes through {}", graph.id, edge.id, graph.nodes[i].id);
                        }
                    }
                    continue;
                }
                let on_border = |p: Point, b: (f64, f64, f64, f64)| {
                    let e = 0.01;
                    let inside = p.x >= b.0 - e && p.x <= b.0 + b.2 + e && p.y >= b.1 - e && p.y <= b.1 + b.3 + e;
                    let edge_x = (p.x - b.0).abs() < e || (p.x - b.0 - b.2).abs() < e;
                    let edge_y = (p.y - b.1).abs() < e || (p.y - b.1 - b.3).abs() < e;
                    inside && (edge_x || edge_y)
                };
                assert!(on_border(route[0], boxes[s]), "{}: {} does not start on its box", graph.id, edge.id);
                assert!(
                    on_border(*route.last().unwrap(), boxes[t]),
                    "{}: {} does not end on its box",
                    graph.id,
                    edge.id
                );
            }
        }
    }

    #[test]
    fn text_fits_its_box() {
        for graph in sample_graphs() {
            for node in &graph.nodes {
                let c = content(node);
                for (line, style) in &c.header {
                    assert!(
                        text::width(line, FONT_SIZE, *style) + 2.0 * PADDING <= c.width + 1e-6,
                        "{}: {line}",
                        node.id
                    );
                }
                for line in c.compartments.iter().flatten() {
                    assert!(
                        text::width(line, FONT_SIZE, Style::Regular) + 2.0 * PADDING <= c.width + 1e-6,
                        "{}: {line}",
                        node.id
                    );
                }
                for port in &node.ports {
                    let line = port_text(port);
                    assert!(
                        text::width(&line, FONT_SIZE * 0.85, Style::Regular) + 2.0 * PADDING <= c.width + 1e-6,
                        "{}: {line}",
                        node.id
                    );
                }
            }
        }
    }
}
