//! SVG writer: draws a [`Scene`] in UML notation (class boxes with compartments, activity nodes
//! by kind, components with ports, instances, swimlanes), with edge heads by kind. It computes
//! no geometry: every position comes from the scene. Coordinates are written with two decimals,
//! so the output is byte-identical for identical input.

use std::{collections::HashSet, fmt::Write};

use gudsl_model::graph::{EdgeKind, Graph, NodeShape};

use crate::{
    scene::{
        self,
        measure::{FONT_SIZE, LABEL_SIZE, PORT_SIZE},
        Frame, Scene, SceneEdge, SceneNode, TextLine,
    },
    text::{Style, FONT_FAMILY},
};

/// Lays a graph out and draws it.
pub fn render(graph: &Graph) -> String {
    write(&scene::build(graph, scene::Hints::default()))
}

/// A number with at most two decimals, without trailing zeros.
pub(crate) fn f(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

pub(crate) fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

const MARKERS: &str = concat!(
    "<defs>",
    r#"<marker id="open" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="10" markerHeight="10" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10" fill="none" stroke="black"/></marker>"#,
    r#"<marker id="filled" viewBox="0 0 10 10" refX="10" refY="5" markerWidth="9" markerHeight="9" orient="auto-start-reverse"><path d="M0,0 L10,5 L0,10 z" fill="black"/></marker>"#,
    r#"<marker id="triangle" viewBox="0 0 12 12" refX="12" refY="6" markerWidth="12" markerHeight="12" orient="auto-start-reverse"><path d="M0,0 L12,6 L0,12 z" fill="white" stroke="black"/></marker>"#,
    r#"<marker id="diamond" viewBox="0 0 16 10" refX="0" refY="5" markerWidth="16" markerHeight="10" orient="auto"><path d="M0,5 L8,0 L16,5 L8,10 z" fill="white" stroke="black"/></marker>"#,
    r#"<marker id="diamond-filled" viewBox="0 0 16 10" refX="0" refY="5" markerWidth="16" markerHeight="10" orient="auto"><path d="M0,5 L8,0 L16,5 L8,10 z" fill="black"/></marker>"#,
    "</defs>\n"
);

/// The SVG document of a scene.
pub fn write(scene: &Scene) -> String {
    let mut out = String::new();
    let (w, h) = (f(scene.width), f(scene.height));
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{FONT_FAMILY}" font-size="{}">"#,
        f(FONT_SIZE)
    );
    let _ = writeln!(out, "<title>{}</title>", escape(&scene.id));
    out.push_str(MARKERS);
    let _ = writeln!(out, r#"<rect width="{w}" height="{h}" fill="white"/>"#);
    draw_frame(&mut out, &scene.frame);
    for lane in &scene.lanes {
        let _ = writeln!(
            out,
            r##"<g class="swimlane" data-id="{}"><rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="#888"/><text x="{}" y="{}" text-anchor="middle" font-weight="bold" fill="#555">{}</text></g>"##,
            escape(&lane.id),
            f(lane.rect.x),
            f(lane.rect.y),
            f(lane.rect.width),
            f(lane.rect.height),
            f(lane.title.x),
            f(lane.title.y),
            escape(&lane.title.text)
        );
    }
    // Nodes that hold others first (parents before children): the edges inside them on top.
    let parents: HashSet<&String> = scene.nodes.iter().filter_map(|n| n.parent.as_ref()).collect();
    let holds = |node: &SceneNode| parents.contains(&node.id);
    for node in scene.nodes.iter().filter(|n| holds(n)) {
        draw_node(&mut out, node);
    }
    for edge in &scene.edges {
        draw_edge(&mut out, edge);
    }
    for node in scene.nodes.iter().filter(|n| !holds(n)) {
        draw_node(&mut out, node);
    }
    out.push_str("</svg>\n");
    out
}

/// The frame: its rectangle, the name tab with its cut corner, the variable section and an
/// empty diagram's note.
fn draw_frame(out: &mut String, frame: &Frame) {
    let (r, t) = (frame.rect, frame.tab);
    let cut = 10.0_f64.min(t.height / 2.0);
    let _ = write!(
        out,
        r#"<g class="frame"><rect x="{}" y="{}" width="{}" height="{}" fill="none" stroke="black"/><path d="M{},{} H{} L{},{} V{}" fill="none" stroke="black"/>"#,
        f(r.x),
        f(r.y),
        f(r.width),
        f(r.height),
        f(t.x),
        f(t.y + t.height),
        f(t.x + t.width - cut),
        f(t.x + t.width),
        f(t.y + t.height - cut),
        f(t.y)
    );
    for line in &frame.heading {
        draw_text(out, line, "");
    }
    if let Some((rect, lines)) = &frame.variables {
        let _ = write!(
            out,
            r##"<rect class="variables" x="{}" y="{}" width="{}" height="{}" fill="#fafafa" stroke="#999"/>"##,
            f(rect.x),
            f(rect.y),
            f(rect.width),
            f(rect.height)
        );
        for line in lines {
            draw_text(out, line, "");
        }
    }
    if let Some(note) = &frame.note {
        draw_text(out, note, r##" fill="#777""##);
    }
    out.push_str("</g>\n");
}

/// A line of text starting at its point, in its style; `extra` adds attributes.
fn draw_text(out: &mut String, line: &TextLine, extra: &str) {
    let _ = write!(
        out,
        r#"<text x="{}" y="{}"{}{extra}>{}</text>"#,
        f(line.x),
        f(line.y),
        style_attribute(line.style),
        escape(&line.text)
    );
}

fn style_attribute(style: Style) -> &'static str {
    match style {
        Style::Bold => r#" font-weight="bold""#,
        Style::Oblique => r#" font-style="italic""#,
        Style::Underlined => r#" text-decoration="underline""#,
        Style::Regular => "",
    }
}

fn draw_edge(out: &mut String, edge: &SceneEdge) {
    let path: Vec<String> = edge.points.iter().map(|p| format!("{},{}", f(p.x), f(p.y))).collect();
    let (dash, start, end) = match edge.kind {
        EdgeKind::Generalization => ("", "", r#" marker-end="url(#triangle)""#),
        EdgeKind::Realization => (r#" stroke-dasharray="6,4""#, "", r#" marker-end="url(#triangle)""#),
        EdgeKind::Association => ("", "", r#" marker-end="url(#open)""#),
        EdgeKind::Aggregation => ("", r#" marker-start="url(#diamond)""#, ""),
        EdgeKind::Composition => ("", r#" marker-start="url(#diamond-filled)""#, ""),
        EdgeKind::Transition | EdgeKind::Connection | EdgeKind::Binding => ("", "", r#" marker-end="url(#filled)""#),
    };
    let _ = writeln!(
        out,
        r#"<polyline class="edge" data-id="{}" points="{}" fill="none" stroke="black"{dash}{start}{end}/>"#,
        escape(&edge.id),
        path.join(" ")
    );
    for (class, label) in
        [("edge-label", &edge.label), ("end-label", &edge.tail_label), ("end-label", &edge.head_label)]
    {
        let Some(label) = label else { continue };
        let lines: Vec<String> = label
            .lines
            .iter()
            .map(|(dy, line)| format!(r#"<tspan x="{}" dy="{}">{}</tspan>"#, f(label.rect.x), f(*dy), escape(line)))
            .collect();
        let _ = writeln!(
            out,
            r##"<text class="{class}" y="{}" font-size="{}" fill="#333">{}</text>"##,
            f(label.rect.y),
            f(LABEL_SIZE),
            lines.join("")
        );
    }
}

fn draw_node(out: &mut String, node: &SceneNode) {
    let (x, y, w, h) = (node.rect.x, node.rect.y, node.rect.width, node.rect.height);
    let _ = write!(out, r#"<g class="node" data-id="{}">"#, escape(&node.id));
    if !node.title.is_empty() {
        let _ = write!(out, "<title>{}</title>", escape(&node.title));
    }
    draw_shape(out, node.shape, x, y, w, h);
    for line in &node.header {
        let weight = style_attribute(line.style);
        let _ = write!(
            out,
            r#"<text x="{}" y="{}" text-anchor="middle"{weight}>{}</text>"#,
            f(line.x),
            f(line.y),
            escape(&line.text)
        );
    }
    let boxed = matches!(
        node.shape,
        NodeShape::Class | NodeShape::Interface | NodeShape::Enum | NodeShape::Attribute | NodeShape::Instance
    );
    for compartment in &node.compartments {
        if boxed {
            let y = f(compartment.separator_y);
            let _ = write!(out, r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}" stroke="black"/>"#, f(x), f(x + w));
        }
        for TextLine { x, y, text, style } in &compartment.lines {
            let style = style_attribute(*style);
            let _ = write!(out, r#"<text x="{}" y="{}"{style}>{}</text>"#, f(*x), f(*y), escape(text));
        }
    }
    for port in &node.ports {
        let anchor = if port.left { "" } else { r#" text-anchor="end""# };
        let _ = write!(
            out,
            r#"<text class="port" data-id="{}" x="{}" y="{}"{anchor} font-size="{}">{}</text>"#,
            escape(&port.id),
            f(port.text.x),
            f(port.text.y),
            f(PORT_SIZE),
            escape(&port.text.text)
        );
        let (border, outwards) = if port.left { (x, -1.0) } else { (x + w, 1.0) };
        draw_port_symbol(out, border, outwards, port.symbol_y, port.provider);
    }
    out.push_str("</g>\n");
}

/// A node's outline by kind.
fn draw_shape(out: &mut String, shape: NodeShape, x: f64, y: f64, w: f64, h: f64) {
    match shape {
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
        NodeShape::Action => {
            let _ = write!(
                out,
                r#"<rect x="{}" y="{}" width="{}" height="{}" rx="10" fill="white" stroke="black"/>"#,
                f(x),
                f(y),
                f(w),
                f(h)
            );
        }
        NodeShape::Calc | NodeShape::CalcRange | NodeShape::Loop | NodeShape::LoopWindow => {
            draw_expansion_region(out, shape, x, y, w, h)
        }
        _ => {
            let dash = if shape == NodeShape::External { r#" stroke-dasharray="4,3""# } else { "" };
            let _ = write!(
                out,
                r#"<rect x="{}" y="{}" width="{}" height="{}" fill="white" stroke="black"{dash}/>"#,
                f(x),
                f(y),
                f(w),
                f(h)
            );
            if shape == NodeShape::Component {
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
}

/// A loop or calc node as UML draws an expansion region: a dashed rounded box (tinted: blue
/// runs on the GPU, green loops) with an expansion node, a box of three cells, on its left
/// border where the iterated range (the work grid, the loop's values) comes in.
fn draw_expansion_region(out: &mut String, shape: NodeShape, x: f64, y: f64, w: f64, h: f64) {
    let fill = if matches!(shape, NodeShape::Calc | NodeShape::CalcRange) { "#eef4ff" } else { "#f2fbef" };
    let _ = write!(
        out,
        r#"<rect x="{}" y="{}" width="{}" height="{}" rx="10" fill="{fill}" stroke="black" stroke-dasharray="6,4"/>"#,
        f(x),
        f(y),
        f(w),
        f(h)
    );
    let (cell, top) = (8.0, y + h / 2.0 - 12.0);
    let _ = write!(
        out,
        r#"<rect class="expansion-node" x="{}" y="{}" width="{}" height="{}" fill="white" stroke="black"/>"#,
        f(x - cell / 2.0),
        f(top),
        f(cell),
        f(3.0 * cell)
    );
    for divider in [top + cell, top + 2.0 * cell] {
        let _ = write!(
            out,
            r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="black"/>"#,
            f(x - cell / 2.0),
            f(divider),
            f(x + cell / 2.0),
            f(divider)
        );
    }
}

/// UML port notation on a border at `bx`: a square on the boundary, then outside it (`outwards`
/// is 1 on the right border, -1 on the left) a lollipop (provided interface) or a socket
/// (required interface) opening away from the box.
fn draw_port_symbol(out: &mut String, bx: f64, outwards: f64, cy: f64, provider: Option<bool>) {
    let _ = write!(
        out,
        r#"<rect x="{}" y="{}" width="8" height="8" fill="white" stroke="black"/>"#,
        f(bx - 4.0),
        f(cy - 4.0)
    );
    let stem = format!(
        r#"<line x1="{}" y1="{}" x2="{}" y2="{}" stroke="black"/>"#,
        f(bx + 4.0 * outwards),
        f(cy),
        f(bx + 12.0 * outwards),
        f(cy)
    );
    match provider {
        Some(true) => {
            let _ = write!(
                out,
                r#"{stem}<circle cx="{}" cy="{}" r="5" fill="white" stroke="black"/>"#,
                f(bx + 17.0 * outwards),
                f(cy)
            );
        }
        Some(false) => {
            // A half circle around the end of the stem, open away from the box.
            let sweep = if outwards > 0.0 { 0 } else { 1 };
            let _ = write!(
                out,
                r#"{stem}<path d="M{},{} A6,6 0 0,{sweep} {},{}" fill="none" stroke="black"/>"#,
                f(bx + 18.0 * outwards),
                f(cy - 6.0),
                f(bx + 18.0 * outwards),
                f(cy + 6.0)
            );
        }
        None => {}
    }
}
