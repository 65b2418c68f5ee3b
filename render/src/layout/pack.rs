//! Boxes without edges: each, in input order, where it fits in the free room of the layered
//! drawing of the others (level with a rank's boxes, at the drawing's sides first), clear of its
//! boxes, edges and labels — as dot puts them into its ranks, but growing the drawing by
//! nothing. The rest are packed in rows under it, about as wide as the drawing (or, where there
//! is none or it is narrow, as wide as makes the packed boxes a block of about 3:2) — not one
//! long row across the top.

use super::{Layout, LayoutInput, Point, Spacing};
use crate::geometry::{intersects, segment_meets_box, Rect};

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
/// placeholders) with the boxes that are alone placed in its free room or in rows under it.
pub(super) fn place_alone(
    mut layout: Layout,
    input: &LayoutInput,
    alone: &[bool],
    spacing: Spacing,
    drawn: bool,
) -> Layout {
    let lonely: Vec<usize> = (0..input.nodes.len()).filter(|&v| alone[v]).collect();
    let rest = if drawn { into_free_room(&mut layout, input, alone, &lonely, spacing) } else { lonely };
    under(layout, input, rest, spacing, drawn)
}

/// Places each of `lonely` where it fits inside `layout`; returns those that fit nowhere.
fn into_free_room(
    layout: &mut Layout,
    input: &LayoutInput,
    alone: &[bool],
    lonely: &[usize],
    spacing: Spacing,
) -> Vec<usize> {
    let gap = spacing.node_gap;
    let rect =
        |v: usize, at: Point| Rect { x: at.x, y: at.y, width: input.nodes[v].width, height: input.nodes[v].height };
    let mut boxes: Vec<Rect> =
        (0..input.nodes.len()).filter(|&v| !alone[v]).map(|v| rect(v, layout.positions[v])).collect();
    let labels: Vec<Rect> = (layout.labels.iter().zip(&input.labels))
        .filter_map(|(at, size)| Some(((*at)?, (*size)?)))
        .map(|(at, (width, height))| Rect { x: at.x, y: at.y, width, height })
        .collect();
    let segments: Vec<(Point, Point)> =
        layout.edges.iter().flat_map(|route| route.windows(2).map(|s| (s[0], s[1]))).collect();
    let mut rows: Vec<f64> = boxes.iter().map(|b| b.y).collect();
    rows.sort_by(f64::total_cmp);
    rows.dedup_by(|a, b| (*a - *b).abs() < 0.5);
    let (left, right, bottom) = (spacing.margin, layout.width - spacing.margin, layout.height - spacing.margin);
    let mut rest = Vec::new();
    for &v in lonely {
        let (width, height) = (input.nodes[v].width, input.nodes[v].height);
        let clear = |r: Rect, boxes: &[Rect]| {
            let near = r.grown(gap / 2.0);
            r.x >= left
                && r.x + r.width <= right
                && r.y + r.height <= bottom
                && !boxes.iter().any(|b| intersects(r.grown(gap), *b))
                && !labels.iter().any(|l| intersects(near, *l))
                && !segments.iter().any(|&(a, b)| segment_meets_box(a, b, near))
        };
        // The drawing's sides in every row first, then the gaps inside a row, left to right.
        let sides = rows.iter().flat_map(|&y| [right - width, left].map(|x| Rect { x, y, width, height }));
        let inside = rows.iter().flat_map(|&y| {
            let band = |top: f64, bottom: f64| top < y + height + gap && bottom > y - gap;
            let mut xs: Vec<f64> =
                boxes.iter().filter(|b| band(b.y, b.y + b.height)).map(|b| b.x + b.width + gap).collect();
            xs.extend(
                (segments.iter().filter(|(a, b)| band(a.y.min(b.y), a.y.max(b.y))))
                    .map(|(a, b)| a.x.max(b.x) + gap / 2.0),
            );
            xs.sort_by(f64::total_cmp);
            xs.into_iter().map(move |x| Rect { x, y, width, height })
        });
        let spot = sides.chain(inside).find(|r| clear(*r, &boxes));
        match spot {
            Some(r) => {
                layout.positions[v] = Point { x: r.x, y: r.y };
                boxes.push(r);
            }
            None => rest.push(v),
        }
    }
    rest
}

/// `layout` with `lonely` placed in rows under it.
fn under(mut layout: Layout, input: &LayoutInput, lonely: Vec<usize>, spacing: Spacing, drawn: bool) -> Layout {
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
