//! Small parts of the graph — boxes without edges, and connected parts of a few boxes apart
//! from the rest — each laid out on its own, then, in input order, put where it fits in the free
//! room of the layered drawing of the others (level with a rank's boxes, at the drawing's sides
//! first), clear of its boxes, edges and labels: as dot puts them into its ranks, but growing
//! the drawing by nothing. The rest are packed in rows under it, about as wide as the drawing
//! (or, where there is none or it is narrow, as wide as makes them a block of about 3:2) — not
//! one long row across the top.

use super::{parts::connected_parts, Entry, Layout, LayoutInput, Point, Remembered, RowEntry, Spacing};
use crate::geometry::Rect;
use crate::grid::{Boxes, Segments};

/// The most boxes of a part laid out apart.
const SMALL_PART: usize = 4;

/// Boxes joined by edges or in swimlanes, and the small parts apart from them (by box, in input
/// order): a part is small when it has at most `SMALL_PART` boxes, none in a swimlane, and is
/// not the largest part (unless that is one box alone too).
pub(super) fn split(input: &LayoutInput) -> (Vec<usize>, Vec<Vec<usize>>) {
    let n = input.nodes.len();
    let part = connected_parts(n, input.edges.iter().copied());
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n];
    for v in 0..n {
        members[part[v]].push(v);
    }
    let largest = (0..n).max_by_key(|&r| (members[r].len(), std::cmp::Reverse(r))).unwrap_or(0);
    let in_lane = |v: usize| input.groups.get(v).copied().flatten().is_some();
    let in_lanes = |r: usize| members[r].iter().any(|&v| in_lane(v));
    // The largest part is laid out in layers unless it is a box alone too.
    let layered = |r: usize| r == largest && (members[r].len() > 1 || in_lanes(r));
    let small = |r: usize| !layered(r) && members[r].len() <= SMALL_PART && !in_lanes(r);
    let apart: Vec<Vec<usize>> =
        (0..n).filter(|&r| !members[r].is_empty() && small(r)).map(|r| members[r].clone()).collect();
    let joined: Vec<usize> = (0..n).filter(|&v| !small(part[v])).collect();
    (joined, apart)
}

/// The part of `input` made of `boxes` (in that order) and the edges between them, and those
/// edges' indices in `input`.
pub(super) fn sub_input(input: &LayoutInput, boxes: &[usize]) -> (LayoutInput, Vec<usize>) {
    let mut index = vec![usize::MAX; input.nodes.len()];
    for (i, &v) in boxes.iter().enumerate() {
        index[v] = i;
    }
    let edges: Vec<usize> = (0..input.edges.len())
        .filter(|&e| index[input.edges[e].0] != usize::MAX && index[input.edges[e].1] != usize::MAX)
        .collect();
    let sub = LayoutInput {
        nodes: boxes.iter().map(|&v| input.nodes[v].clone()).collect(),
        edges: edges.iter().map(|&e| (index[input.edges[e].0], index[input.edges[e].1])).collect(),
        groups: boxes.iter().map(|&v| input.groups.get(v).copied().flatten()).collect(),
        labels: edges.iter().map(|&e| input.labels.get(e).copied().flatten()).collect(),
        flow: input.flow,
        firm: edges.iter().map(|&e| input.firm.get(e).copied().unwrap_or(false)).collect(),
        end_labels: edges.iter().map(|&e| input.end_labels.get(e).copied().unwrap_or_default()).collect(),
        remembered: input.remembered.part(boxes, &edges),
        ports: if input.ports.is_empty() {
            Vec::new()
        } else {
            edges.iter().map(|&e| input.ports.get(e).copied().unwrap_or_default()).collect()
        },
    };
    (sub, edges)
}

/// A part laid out on its own: its boxes, its edges (by input index), and its layout.
pub(super) struct Part {
    pub boxes: Vec<usize>,
    pub edges: Vec<usize>,
    pub layout: Layout,
}

impl Part {
    /// The part's drawing without its margin.
    fn size(&self, spacing: Spacing) -> (f64, f64) {
        (self.layout.width - 2.0 * spacing.margin, self.layout.height - 2.0 * spacing.margin)
    }

    /// Where the part's drawing had its top-left corner in the layout `remembered` (its first box
    /// with a place kept there), if it did.
    pub(super) fn place_before(&self, remembered: &Remembered, spacing: Spacing) -> Option<Point> {
        self.boxes.iter().enumerate().find_map(|(i, &v)| {
            let seat = remembered.boxes.get(v).copied().flatten()?;
            let (x, y) = (seat.x?, seat.y?);
            let centre = self.layout.rows.iter().flatten().find_map(|e| match e {
                (Entry::Box(j), Some(centre), _) if *j == i => Some(*centre),
                _ => None,
            })?;
            Some(Point { x: x - centre + spacing.margin, y: y - self.layout.positions[i].y + spacing.margin })
        })
    }

    /// Writes the part into `layout` with its drawing's top-left corner at `at`; its rows follow
    /// the layout's.
    pub(super) fn put(&self, layout: &mut Layout, at: Point, spacing: Spacing, apart: bool) {
        let (dx, dy) = (at.x - spacing.margin, at.y - spacing.margin);
        let moved = |p: Point| Point { x: p.x + dx, y: p.y + dy };
        for (i, &v) in self.boxes.iter().enumerate() {
            layout.positions[v] = moved(self.layout.positions[i]);
        }
        for (i, &e) in self.edges.iter().enumerate() {
            layout.edges[e] = self.layout.edges[i].iter().map(|&p| moved(p)).collect();
            layout.labels[e] = self.layout.labels[i].map(moved);
            layout.end_labels[e] = self.layout.end_labels[i].map(|at| at.map(moved));
        }
        // A box of a part apart is kept as drawn here: its centre and top, the part's place.
        let top = |i: usize| Some(self.layout.positions[i].y + dy).filter(|_| apart);
        let entry = |&(entry, x, y): &RowEntry| match entry {
            Entry::Box(i) => (Entry::Box(self.boxes[i]), x.map(|x| x + dx), top(i)),
            Entry::Edge(i) => (Entry::Edge(self.edges[i]), x.map(|x| x + dx), None),
            Entry::Band => (Entry::Band, x.map(|top| top + dy), y),
            Entry::Column => (Entry::Column, x, None),
        };
        // A part apart is laid out from its orders alone: where its bands and columns were is not kept.
        let kept = |e: &&RowEntry| !(apart && matches!(e.0, Entry::Band | Entry::Column));
        layout.rows.extend(self.layout.rows.iter().map(|row| row.iter().filter(kept).map(entry).collect()));
    }
}

/// `layout` (of the joined boxes, at their indices; the others' positions, edges and labels are
/// placeholders) with the small parts placed in its free room — each first where it `had` its
/// place before, if that is still free — or in rows under it.
pub(super) fn place_apart(
    mut layout: Layout,
    input: &LayoutInput,
    parts: &[Part],
    had: &[Option<Point>],
    spacing: Spacing,
    drawn: bool,
) -> Layout {
    let sizes: Vec<(f64, f64)> = parts.iter().map(|p| p.size(spacing)).collect();
    let mut spots =
        if drawn { into_free_room(&layout, input, parts, &sizes, had, spacing) } else { vec![None; parts.len()] };
    under(&mut layout, &sizes, &mut spots, spacing, drawn);
    for (part, spot) in parts.iter().zip(spots) {
        part.put(&mut layout, spot.expect("every part placed"), spacing, true);
    }
    layout
}

/// Where each part (of drawing size `sizes`) fits inside `layout` (of the joined boxes): the
/// top-left corner of its drawing, or none.
fn into_free_room(
    layout: &Layout,
    input: &LayoutInput,
    parts: &[Part],
    sizes: &[(f64, f64)],
    had: &[Option<Point>],
    spacing: Spacing,
) -> Vec<Option<Point>> {
    let gap = spacing.node_gap;
    let mut apart = vec![false; input.nodes.len()];
    parts.iter().flat_map(|p| &p.boxes).for_each(|&v| apart[v] = true);
    let rect =
        |v: usize, at: Point| Rect { x: at.x, y: at.y, width: input.nodes[v].width, height: input.nodes[v].height };
    let mut boxes: Vec<Rect> =
        (0..input.nodes.len()).filter(|&v| !apart[v]).map(|v| rect(v, layout.positions[v])).collect();
    // The parts' edges and labels are not in `layout` yet; their boxes are placeholders.
    let ends = layout.end_labels.iter().zip(&input.end_labels).flat_map(|(at, size)| at.iter().zip(size));
    let labels: Vec<Rect> = (layout.labels.iter().zip(&input.labels))
        .chain(ends)
        .filter_map(|(at, size)| Some(((*at)?, (*size)?)))
        .map(|(at, (width, height))| Rect { x: at.x, y: at.y, width, height })
        .collect();
    let segments: Vec<(Point, Point)> =
        layout.edges.iter().flat_map(|route| route.windows(2).map(|s| (s[0], s[1]))).collect();
    let mut rows: Vec<f64> = boxes.iter().map(|b| b.y).collect();
    rows.sort_by(f64::total_cmp);
    rows.dedup_by(|a, b| (*a - *b).abs() < 0.5);
    let (left, right, bottom) = (spacing.margin, layout.width - spacing.margin, layout.height - spacing.margin);
    let mut spots = Vec::with_capacity(parts.len());
    let (mut taken, labels_grid) = (Boxes::new(boxes.iter().copied()), Boxes::new(labels));
    let segments_grid = Segments::new(segments.iter().copied());
    // A part of the size of one that found no room finds none, until a part is placed (it takes
    // room, but also offers the place right of it).
    let mut failed: Vec<(f64, f64)> = Vec::new();
    for (&(width, height), had) in sizes.iter().zip(had) {
        let before = had.map(|at| Rect { x: at.x, y: at.y, width, height });
        if before.is_none() && failed.contains(&(width, height)) {
            spots.push(None);
            continue;
        }
        let clear = |r: Rect, taken: &Boxes| {
            let near = r.grown(gap / 2.0);
            r.x >= left
                && r.x + r.width <= right
                && r.y + r.height <= bottom
                && !taken.overlap(r.grown(gap), &[])
                && !labels_grid.overlap(near, &[])
                && !segments_grid.meet(near)
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
        let spot = before.into_iter().chain(sides).chain(inside).find(|r| clear(*r, &taken));
        match spot {
            Some(r) => {
                boxes.push(r);
                taken.push(r);
                failed.clear();
            }
            None => failed.push((width, height)),
        }
        spots.push(spot.map(|r| Point { x: r.x, y: r.y }));
    }
    spots
}

/// The parts (of drawing size `sizes`) without a spot yet placed in rows under `layout`, which
/// grows to hold them.
fn under(layout: &mut Layout, sizes: &[(f64, f64)], spots: &mut [Option<Point>], spacing: Spacing, drawn: bool) {
    let rest: Vec<usize> = (0..sizes.len()).filter(|&i| spots[i].is_none()).collect();
    if rest.is_empty() {
        return;
    }
    let area: f64 = rest.iter().map(|&i| (sizes[i].0 + spacing.node_gap) * (sizes[i].1 + spacing.node_gap)).sum();
    let widest = rest.iter().map(|&i| sizes[i].0).fold(0.0, f64::max);
    let drawing_width = if drawn { layout.width - 2.0 * spacing.margin } else { 0.0 };
    let row_width = drawing_width.max((area * 1.5).sqrt()).max(widest);
    let top = if drawn { layout.height } else { spacing.margin };
    let (mut x, mut y, mut row_height, mut right) = (spacing.margin, top, 0.0f64, 0.0f64);
    for i in rest {
        let (width, height) = sizes[i];
        if x > spacing.margin && x + width > spacing.margin + row_width {
            x = spacing.margin;
            y += row_height + spacing.node_gap;
            row_height = 0.0;
        }
        spots[i] = Some(Point { x, y });
        right = right.max(x + width);
        x += width + spacing.node_gap;
        row_height = row_height.max(height);
    }
    layout.width = if drawn { layout.width.max(right + spacing.margin) } else { right + spacing.margin };
    layout.height = y + row_height + spacing.margin;
}
