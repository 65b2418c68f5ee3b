//! The diagram's frame, as UML 2 draws one: a rectangle around the whole diagram with a name
//! tab in its top left corner (`act Main`, `class Filtering`, `cmp ComponentExampleDiagram`).
//! An activity diagram's tab also carries its parameters and owner, and its variable section
//! (chapter 9.2.2.1) sits under the tab, above the nodes. An empty diagram says so inside its
//! frame instead of drawing nothing.

use gudsl_model::graph::{Graph, GraphKind};

use super::{measure::FONT_SIZE, Rect, TextLine};
use crate::text::{self, Style};

/// Space between the canvas edge and the frame.
pub(crate) const MARGIN: f64 = 8.0;
/// Space inside the frame around its text and the diagram.
const INSET: f64 = 8.0;
/// Width of the tab's cut corner.
const CUT: f64 = 10.0;
/// A parameter list wraps after this many characters.
const SIGNATURE_CHARS: usize = 70;
/// Variables are listed in columns of this many lines.
const COLUMN_LINES: usize = 8;
/// What an empty diagram says inside its frame.
const EMPTY_NOTE: &str = "empty diagram: nothing declared yet";
/// Height of an empty diagram's drawing area.
const EMPTY_HEIGHT: f64 = 50.0;

/// A diagram's frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub rect: Rect,
    /// The name tab; drawn with its bottom right corner cut.
    pub tab: Rect,
    /// The tab's lines: kind and name, then an activity's parameters and owner.
    pub heading: Vec<TextLine>,
    /// An activity's variable section: its box and lines (columns side by side).
    pub variables: Option<(Rect, Vec<TextLine>)>,
    /// What an empty diagram says in its frame.
    pub note: Option<TextLine>,
}

/// The frame's text, measured before the diagram is laid out: the layout goes below it.
pub(crate) struct Heading {
    tab_lines: Vec<(String, Style)>,
    tab: (f64, f64),
    columns: Vec<Vec<String>>,
    column_widths: Vec<f64>,
    variables: Option<(f64, f64)>,
    empty: bool,
    /// Room above the nodes for swimlane titles, and left of them for the lane's border.
    lane_titles: f64,
    lane_border: f64,
}

/// UML's keyword of a diagram kind in its frame's tab.
fn kind_keyword(kind: GraphKind) -> &'static str {
    match kind {
        GraphKind::Class => "class",
        GraphKind::Activity => "act",
        GraphKind::Component => "cmp",
        GraphKind::ComponentInstance => "inst",
    }
}

/// `(a, b, c)` broken after commas into lines of at most `SIGNATURE_CHARS` characters.
fn parameter_lines(parameters: &[String]) -> Vec<String> {
    let mut lines: Vec<String> = vec!["(".to_string()];
    for (i, parameter) in parameters.iter().enumerate() {
        let piece = if i + 1 == parameters.len() { format!("{parameter})") } else { format!("{parameter},") };
        let line = lines.last_mut().expect("one line at least");
        if line.len() > 1 && line.chars().count() + 1 + piece.chars().count() > SIGNATURE_CHARS {
            lines.push(format!("  {piece}"));
        } else {
            if line.len() > 1 {
                line.push(' ');
            }
            line.push_str(&piece);
        }
    }
    lines
}

impl Heading {
    pub(crate) fn measure(graph: &Graph) -> Heading {
        let line_h = text::line_height(FONT_SIZE);
        let mut tab_lines = vec![(format!("{} {}", kind_keyword(graph.kind), graph.id), Style::Bold)];
        if !graph.parameters.is_empty() {
            tab_lines.extend(parameter_lines(&graph.parameters).into_iter().map(|l| (l, Style::Regular)));
        }
        if let Some(owner) = &graph.owner {
            tab_lines.push((format!("owner {owner}"), Style::Regular));
        }
        let widest = tab_lines.iter().map(|(l, s)| text::width(l, FONT_SIZE, *s)).fold(0.0, f64::max);
        let tab = (widest + 2.0 * INSET + CUT, tab_lines.len() as f64 * line_h + INSET);
        let columns: Vec<Vec<String>> = graph.variables.chunks(COLUMN_LINES).map(<[String]>::to_vec).collect();
        let column_widths: Vec<f64> = columns
            .iter()
            .map(|c| c.iter().map(|l| text::width(l, FONT_SIZE, Style::Regular)).fold(0.0, f64::max))
            .collect();
        let variables = (!columns.is_empty()).then(|| {
            let width = column_widths.iter().sum::<f64>() + 3.0 * INSET * columns.len() as f64 + INSET;
            let lines = columns.first().map_or(0, Vec::len) + 1;
            (width, lines as f64 * line_h + INSET)
        });
        let lanes = !graph.groups.is_empty();
        let (lane_titles, lane_border) = if lanes { (line_h + 4.0, 12.0) } else { (0.0, 0.0) };
        let empty = graph.nodes.is_empty();
        Heading { tab_lines, tab, columns, column_widths, variables, empty, lane_titles, lane_border }
    }

    /// Where the frame's body starts, under the heading: swimlanes start there.
    pub(crate) fn body_top(&self) -> f64 {
        MARGIN + self.tab.1 + self.variables.map_or(0.0, |(_, h)| h + INSET) + INSET / 2.0
    }

    /// How far right and down of the canvas's corner the diagram's nodes start.
    pub(crate) fn body_offset(&self) -> (f64, f64) {
        (MARGIN + INSET + self.lane_border, self.body_top() + INSET / 2.0 + self.lane_titles)
    }

    /// The smallest canvas: the heading, and an empty diagram's note.
    pub(crate) fn min_size(&self) -> (f64, f64) {
        let (x, y) = self.body_offset();
        let widest = self.tab.0.max(self.variables.map_or(0.0, |(w, _)| w + INSET));
        let body = if self.empty {
            (text::width(EMPTY_NOTE, FONT_SIZE, Style::Oblique) + INSET, EMPTY_HEIGHT)
        } else {
            (0.0, 0.0)
        };
        ((MARGIN + widest).max(x + body.0) + INSET + MARGIN, y + body.1 + INSET + MARGIN)
    }

    /// The frame around a canvas of this size.
    pub(crate) fn place(&self, width: f64, height: f64) -> Frame {
        let line_h = text::line_height(FONT_SIZE);
        let ascent = text::ascent(FONT_SIZE);
        let tab = Rect { x: MARGIN, y: MARGIN, width: self.tab.0, height: self.tab.1 };
        let heading = self
            .tab_lines
            .iter()
            .enumerate()
            .map(|(i, (line, style))| TextLine {
                x: tab.x + INSET,
                y: tab.y + INSET / 2.0 + ascent + i as f64 * line_h,
                text: line.clone(),
                style: *style,
            })
            .collect();
        let variables = self.variables.map(|(w, h)| {
            let rect = Rect { x: MARGIN + INSET, y: tab.y + tab.height + INSET, width: w, height: h };
            let mut lines = vec![TextLine {
                x: rect.x + INSET,
                y: rect.y + INSET / 2.0 + ascent,
                text: "variables".into(),
                style: Style::Oblique,
            }];
            let mut x = rect.x + INSET;
            for (column, column_width) in self.columns.iter().zip(&self.column_widths) {
                for (i, line) in column.iter().enumerate() {
                    let y = rect.y + INSET / 2.0 + ascent + (i + 1) as f64 * line_h;
                    lines.push(TextLine { x, y, text: line.clone(), style: Style::Regular });
                }
                x += column_width + 3.0 * INSET;
            }
            (rect, lines)
        });
        let rect = Rect { x: MARGIN, y: MARGIN, width: width - 2.0 * MARGIN, height: height - 2.0 * MARGIN };
        let note = self.empty.then(|| {
            let (x, y) = self.body_offset();
            TextLine { x, y: y + EMPTY_HEIGHT / 2.0, text: EMPTY_NOTE.into(), style: Style::Oblique }
        });
        Frame { rect, tab, heading, variables, note }
    }
}
