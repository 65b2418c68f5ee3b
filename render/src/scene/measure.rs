//! Measuring: how large each node is drawn (its header, compartments and port lines in the
//! bundled font), where its text starts, where its ports sit, and how large an edge label is.

use gudsl_model::graph::{GraphNode, GraphPort, NodeShape};

use super::Point;
use crate::text::{self, Style};

pub(crate) const FONT_SIZE: f64 = 12.0;
pub(crate) const PADDING: f64 = 8.0;
/// Font size of edge labels.
pub(crate) const LABEL_SIZE: f64 = FONT_SIZE * 0.85;
/// Font size of port lines.
pub(crate) const PORT_SIZE: f64 = FONT_SIZE * 0.85;
/// Lines of an action's body shown before the rest is collapsed to "… N more lines" (the
/// whole text is the node's `<title>`, a tooltip in a browser).
const MAX_BODY_LINES: usize = 12;
/// Longest line drawn, in characters: longer ones wrap.
const MAX_LINE_CHARS: usize = 60;
/// Indentation of a wrapped line's continuation.
const CONTINUATION: &str = "    ";
/// Edge labels (guards, arguments) wrap at spaces beyond this many characters per line.
const LABEL_LINE_CHARS: usize = 40;

/// A node's drawn content: header lines (stereotype, name) and compartments of lines, each in
/// its style.
pub(crate) struct Content {
    pub(crate) header: Vec<(String, Style)>,
    pub(crate) compartments: Vec<Vec<(String, Style)>>,
    pub(crate) width: f64,
    pub(crate) height: f64,
    /// The height of the area under the text that holds nested components (0: none).
    pub(crate) nested: f64,
}

impl Content {
    /// A shape without text (start, final, a bare diamond, a bar).
    fn bare(width: f64, height: f64) -> Content {
        Content { header: Vec::new(), compartments: Vec::new(), width, height, nested: 0.0 }
    }
}

/// Which border a port sits on: a processor (required interface, socket) on the left, where
/// data comes in; a provider (provided interface, lollipop) on the right, where it goes out.
pub(crate) fn port_on_left(port: &GraphPort) -> bool {
    port.provider == Some(false)
}

/// Each port's row: the left border's ports first, then the right border's, so that no two
/// labels share a row.
pub(crate) fn port_rows(node: &GraphNode) -> Vec<usize> {
    let left = node.ports.iter().filter(|p| port_on_left(p)).count();
    let (mut next_left, mut next_right) = (0, left);
    node.ports
        .iter()
        .map(|port| {
            let row = if port_on_left(port) { &mut next_left } else { &mut next_right };
            *row += 1;
            *row - 1
        })
        .collect()
}

/// Room between a port's square on the border and its label.
pub(crate) const PORT_INSET: f64 = 6.0;

/// An edge label as lines of at most `LABEL_LINE_CHARS` characters, broken at spaces (a word
/// longer than that gets a line of its own).
pub(crate) fn label_lines(label: &str) -> Vec<String> {
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
pub(crate) fn label_size(lines: &[String]) -> (f64, f64) {
    let width = lines.iter().map(|line| text::width(line, LABEL_SIZE, Style::Regular)).fold(0.0, f64::max);
    (width, text::line_height(LABEL_SIZE) * lines.len() as f64)
}

/// `line` in lines of at most `MAX_LINE_CHARS` characters, broken after a comma or else a space
/// where there is one in the line's later two thirds (else within a word); continuations are
/// indented. Nothing is cut.
pub(crate) fn wrap(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = line;
    loop {
        let prefix = if out.is_empty() { "" } else { CONTINUATION };
        let limit = MAX_LINE_CHARS - prefix.len();
        let Some((cut, _)) = rest.char_indices().nth(limit) else {
            out.push(format!("{prefix}{rest}"));
            return out;
        };
        let head = &rest[..cut];
        // After a comma (between parameters) if one is in the later two thirds, else after a
        // space there, else within the word.
        let after = |found: Option<usize>| found.map(|i| i + 1).filter(|&i| head[..i].chars().count() > limit / 3);
        let at = after(head.rfind(',')).or_else(|| after(head.rfind(' '))).unwrap_or(cut);
        out.push(format!("{prefix}{}", rest[..at].trim_end()));
        rest = rest[at..].trim_start();
        if rest.is_empty() {
            return out;
        }
    }
}

/// What a node shows and how large it is.
pub(crate) fn content(node: &GraphNode) -> Content {
    let line_h = text::line_height(FONT_SIZE);
    match node.shape {
        NodeShape::Start => return Content::bare(20.0, 20.0),
        NodeShape::Final => return Content::bare(24.0, 24.0),
        // A decision or merge the text leaves implicit: a bare diamond.
        NodeShape::Decision if node.label.is_empty() => {
            return Content::bare(26.0, 26.0);
        }
        NodeShape::Fork | NodeShape::Join => {
            return Content::bare(80.0, 8.0);
        }
        _ => {}
    }
    let mut header = Vec::new();
    if let Some(stereotype) = &node.stereotype {
        header.push((format!("«{stereotype}»"), Style::Regular));
    }
    let name_style = if node.is_abstract { Style::Oblique } else { Style::Bold };
    header.push((node.label.clone(), name_style));
    let mut compartments: Vec<Vec<(String, Style)>> = node
        .compartments
        .iter()
        .map(|c| {
            let style = |i: usize| if c.statics.get(i) == Some(&true) { Style::Underlined } else { Style::Regular };
            let mut lines: Vec<(String, Style)> =
                c.lines.iter().enumerate().flat_map(|(i, l)| wrap(l).into_iter().map(move |w| (w, style(i)))).collect();
            if matches!(
                node.shape,
                NodeShape::Action | NodeShape::Calc | NodeShape::CalcRange | NodeShape::Loop | NodeShape::LoopWindow
            ) && lines.len() > MAX_BODY_LINES
            {
                let hidden = lines.len() - MAX_BODY_LINES + 1;
                lines.truncate(MAX_BODY_LINES - 1);
                lines.push((format!("… {hidden} more lines"), Style::Regular));
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
        compartments.iter().flatten().map(|(l, style)| text::width(l, FONT_SIZE, *style)).fold(0.0, f64::max);
    let ports_width =
        node.ports.iter().map(|p| text::width(&p.label, PORT_SIZE, Style::Regular) + PORT_INSET).fold(0.0, f64::max);
    let mut width = widest_header.max(widest_line).max(ports_width) + 2.0 * PADDING;
    let mut height = text_height(header.len(), &compartments, 0);
    if node.shape == NodeShape::Decision {
        // A diamond holds its label in the middle half.
        width = width * 1.6 + 10.0;
        height = height * 1.6 + 10.0;
    }
    if node.shape == NodeShape::Component {
        // The component icon in the top right corner, and as much on the left: the centred
        // header stays clear of it.
        width += 48.0;
    }
    height += node.ports.len() as f64 * line_h * 0.9;
    Content { header, compartments, width: width.max(40.0), height: height.max(30.0), nested: 0.0 }
}

/// The height of a node's text: header lines, compartments (an empty one keeps one line) with
/// their separators, and the port lines.
fn text_height(header_lines: usize, compartments: &[Vec<(String, Style)>], ports: usize) -> f64 {
    let line_h = text::line_height(FONT_SIZE);
    let lines = header_lines + compartments.iter().map(|c| c.len().max(1)).sum::<usize>();
    lines as f64 * line_h + (1 + compartments.len()) as f64 * PADDING + ports as f64 * line_h * 0.9
}

/// Where a node's text starts: at the top of a box with compartments (a class resized taller
/// keeps its name on top), else its block centred vertically in a box whose top is `top` (above
/// the nested components it holds).
pub(crate) fn text_top(node: &GraphNode, content: &Content, top: f64) -> f64 {
    if !content.compartments.is_empty() {
        return top + PADDING / 2.0;
    }
    let block = text_height(content.header.len(), &content.compartments, node.ports.len());
    top + (content.height - content.nested - block).max(0.0) / 2.0 + PADDING / 2.0
}

/// How far outside its node's box a connection meets a port: just beyond its lollipop or
/// socket.
pub(crate) const PORT_REACH: f64 = 24.0;

/// Where connections meet each port of a node: just outside its socket on the left border or
/// its lollipop on the right one, in the port's row.
pub(crate) fn port_anchors(node: &GraphNode, content: &Content, at: Point) -> Vec<Point> {
    let line_h = text::line_height(FONT_SIZE);
    let top = port_rows_top(node, content, at.y);
    node.ports
        .iter()
        .zip(port_rows(node))
        .map(|(port, row)| {
            let x = if port_on_left(port) { at.x - PORT_REACH } else { at.x + content.width + PORT_REACH };
            Point { x, y: top + line_h * 0.45 + row as f64 * line_h * 0.9 }
        })
        .collect()
}

/// The top of a node's first row of ports: under its header and compartments.
pub(crate) fn port_rows_top(node: &GraphNode, content: &Content, top: f64) -> f64 {
    let line_h = text::line_height(FONT_SIZE);
    let mut cursor = text_top(node, content, top) + content.header.len() as f64 * line_h;
    for compartment in &content.compartments {
        cursor += PADDING + compartment.len().max(1) as f64 * line_h;
    }
    cursor
}
