//! Boxes without edges packed in rows under the layered drawing of the others, in input order,
//! the rows about as wide as the drawing (or, where there is none or it is narrow, as wide as
//! makes the packed boxes a block of about 3:2) — not one long row across the top.

use super::{Layout, LayoutInput, Point, Spacing};

/// Whether box `v` is alone: no edge touches it and it is in no swimlane.
pub(super) fn alone(input: &LayoutInput) -> Vec<bool> {
    let mut alone: Vec<bool> =
        (0..input.nodes.len()).map(|v| input.groups.get(v).copied().flatten().is_none()).collect();
    for &(a, b) in &input.edges {
        alone[a] = false;
        alone[b] = false;
    }
    alone
}

/// `layout` (of the boxes that are not alone, at their indices; the others' positions are
/// placeholders) with the boxes that are alone placed in rows under it.
pub(super) fn under(mut layout: Layout, input: &LayoutInput, alone: &[bool], spacing: Spacing, drawn: bool) -> Layout {
    let lonely: Vec<usize> = (0..input.nodes.len()).filter(|&v| alone[v]).collect();
    if lonely.is_empty() {
        return layout;
    }
    let area: f64 = lonely
        .iter()
        .map(|&v| (input.nodes[v].width + spacing.node_gap) * (input.nodes[v].height + spacing.node_gap))
        .sum();
    let widest = lonely.iter().map(|&v| input.nodes[v].width).fold(0.0, f64::max);
    let drawing_width = if drawn { layout.width - 2.0 * spacing.margin } else { 0.0 };
    let row_width = drawing_width.max((area * 1.5).sqrt()).max(widest);
    let top = if drawn { layout.height } else { spacing.margin };
    let (mut x, mut y, mut row_height, mut right) = (spacing.margin, top, 0.0f64, 0.0f64);
    for v in lonely {
        let node = &input.nodes[v];
        if x > spacing.margin && x + node.width > spacing.margin + row_width {
            x = spacing.margin;
            y += row_height + spacing.node_gap;
            row_height = 0.0;
        }
        layout.positions[v] = Point { x, y };
        right = right.max(x + node.width);
        x += node.width + spacing.node_gap;
        row_height = row_height.max(node.height);
    }
    layout.width = if drawn { layout.width.max(right + spacing.margin) } else { right + spacing.margin };
    layout.height = y + row_height + spacing.margin;
    layout
}
