//! Placing edge labels the layout did not place: a middle label (of a port-to-port connection)
//! beside its edge, an end label (an association end's role and multiplicity) beside the end
//! of its edge; each clear of every box, every label placed before and every edge, and inside
//! the frame's body.

use crate::{
    geometry::segment_meets_box,
    grid::{Boxes, Segments},
};
use gudsl_model::graph::{EdgeKind, GraphEdge};

use super::{
    measure::{label_lines, label_size},
    Point, Rect,
};

/// The texts an edge carries, as lines: along it (a guard, arguments, a connection's name), and
/// at its ends as UML draws an association's ends (the source's multiplicity at the source; the
/// role name and the target's multiplicity at the target).
pub(crate) struct EdgeTexts {
    pub(crate) middle: Vec<String>,
    pub(crate) tail: Vec<String>,
    pub(crate) head: Vec<String>,
}

pub(crate) fn texts(edge: &GraphEdge) -> EdgeTexts {
    let written = |text: &Option<String>| text.iter().filter(|t| !t.is_empty()).cloned().collect::<Vec<String>>();
    match edge.kind {
        EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition => EdgeTexts {
            middle: Vec::new(),
            tail: written(&edge.source_label),
            head: written(&edge.label).into_iter().chain(written(&edge.target_label)).collect(),
        },
        _ => EdgeTexts {
            middle: edge.label.as_deref().filter(|l| !l.is_empty()).map(label_lines).unwrap_or_default(),
            tail: Vec::new(),
            head: Vec::new(),
        },
    }
}

/// Where an edge's labels went.
#[derive(Default)]
pub(crate) struct Placed {
    pub(crate) middle: Option<Rect>,
    pub(crate) tail: Option<Rect>,
    pub(crate) head: Option<Rect>,
}

impl Placed {
    pub(crate) fn all(&self) -> impl Iterator<Item = Rect> {
        [self.middle, self.tail, self.head].into_iter().flatten()
    }
}

/// Every edge's label boxes: a middle label where the layout reserved room for it, else placed
/// beside its edge; then the end labels where the layout reserved room for them if that is
/// clear, else beside their ends. Each is clear of the boxes, the labels placed before and
/// every edge where it can be, and right of and below `corner`; an edge's label may lie in the
/// boxes `inside` lists for it (by index: the nested components' parents that hold both its
/// ends).
pub(crate) fn place_all(
    texts: &[EdgeTexts],
    routes: &[Vec<Point>],
    laid_out: &[Option<Point>],
    laid_out_ends: &[[Option<Point>; 2]],
    boxes: &[Rect],
    inside: &[Vec<usize>],
    corner: Point,
) -> Vec<Placed> {
    let mut placed: Vec<Placed> = texts
        .iter()
        .zip(laid_out)
        .map(|(t, at)| {
            let (width, height) = label_size(&t.middle);
            let middle = at.filter(|_| !t.middle.is_empty()).map(|at| Rect { x: at.x, y: at.y, width, height });
            Placed { middle, ..Placed::default() }
        })
        .collect();
    let mut room = Room {
        obstacles: Boxes::new(boxes.iter().copied()),
        open: &[],
        placed: Boxes::new(placed.iter().flat_map(Placed::all)),
        routes: Segments::new(routes.iter().flat_map(|route| route.windows(2).map(|s| (s[0], s[1])))),
        corner,
    };
    // The end labels the layout made room for before any label is placed by searching.
    let ends = Ends { texts, routes, laid_out: laid_out_ends, inside };
    ends.place(true, &mut placed, &mut room);
    for (((t, route), at), inside) in texts.iter().zip(routes).zip(&mut placed).zip(inside) {
        if !t.middle.is_empty() && at.middle.is_none() {
            room.open = inside;
            at.middle = Some(place_label(route, label_size(&t.middle), &mut room));
        }
    }
    ends.place(false, &mut placed, &mut room);
    placed
}

/// The edges' end labels to place, and where the layout made room for them.
struct Ends<'a> {
    texts: &'a [EdgeTexts],
    routes: &'a [Vec<Point>],
    laid_out: &'a [[Option<Point>; 2]],
    inside: &'a [Vec<usize>],
}

impl<'a> Ends<'a> {
    /// Places the end labels the layout made room for (`reserved`), or the others.
    fn place(&self, reserved: bool, placed: &mut [Placed], room: &mut Room<'a>) {
        for (e, texts) in self.texts.iter().enumerate() {
            let [tail_at, head_at] = self.laid_out.get(e).copied().unwrap_or_default();
            for (at_target, laid_out) in [(false, tail_at), (true, head_at)] {
                let lines = if at_target { &texts.head } else { &texts.tail };
                if lines.is_empty() || laid_out.is_some() != reserved {
                    continue;
                }
                room.open = &self.inside[e];
                let at = Some(place_end_label(&self.routes[e], at_target, label_size(lines), laid_out, room));
                if at_target {
                    placed[e].head = at;
                } else {
                    placed[e].tail = at;
                }
            }
        }
    }
}

/// A box of size `(w, h)` for a middle label beside its edge: candidates along each segment, on
/// either side, chosen as `Room::choose` does (the edge's middle where none is clear).
fn place_label(route: &[Point], (w, h): (f64, f64), room: &mut Room) -> Rect {
    let mut candidates = Vec::new();
    for (fraction, gap) in
        [4.0, 16.0].into_iter().flat_map(|gap| [0.5, 0.3, 0.7, 0.15, 0.85, 0.4, 0.6].map(|f| (f, gap)))
    {
        for segment in route.windows(2) {
            let p = Point {
                x: segment[0].x + (segment[1].x - segment[0].x) * fraction,
                y: segment[0].y + (segment[1].y - segment[0].y) * fraction,
            };
            let beside = [(p.x + gap, p.y - h / 2.0), (p.x - gap - w, p.y - h / 2.0)];
            let over = [(p.x - w / 2.0, p.y - h - gap + 1.0), (p.x - w / 2.0, p.y + gap - 1.0)];
            // Beside a vertical segment, over or under a horizontal one: never across the line.
            let horizontal = (segment[1].x - segment[0].x).abs() > (segment[1].y - segment[0].y).abs();
            let (preferred, other) = if horizontal { (over, beside) } else { (beside, over) };
            // Off a slanted segment: the two corners at `p` that the line does not pass through.
            let corners = [
                (p.x + gap, p.y - h - gap),
                (p.x - gap - w, p.y + gap),
                (p.x - gap - w, p.y - h - gap),
                (p.x + gap, p.y + gap),
            ];
            candidates.extend(preferred);
            candidates.extend(other);
            candidates.extend(corners);
        }
    }
    let boxes: Vec<Rect> = candidates.into_iter().map(|(x, y)| Rect { x, y, width: w, height: h }).collect();
    let mid = midpoint(route);
    room.choose(&boxes, route, Rect { x: mid.x + 4.0, y: mid.y - h / 2.0, width: w, height: h })
}

/// A box of size `(w, h)` for the label at an end of `route` (its last point if `at_target`,
/// else its first): at `laid_out` if given and clear; else beside the edge's last (first)
/// segment, as near the end as it is clear of the end's node, of the other labels and of every
/// edge; on the side the end's segment leaves free first.
fn place_end_label(
    route: &[Point],
    at_target: bool,
    (w, h): (f64, f64),
    laid_out: Option<Point>,
    room: &mut Room,
) -> Rect {
    let points: Vec<Point> = if at_target { route.iter().rev().copied().collect() } else { route.to_vec() };
    let Some(&end) = points.first() else {
        return room.choose(&[], route, Rect { x: room.corner.x, y: room.corner.y, width: w, height: h });
    };
    let mut candidates: Vec<Rect> =
        laid_out.map(|at| Rect { x: at.x, y: at.y, width: w, height: h }).into_iter().collect();
    // Farther than 60 only where the edge is crowded near its end, and never past its middle.
    let half = route.windows(2).map(|s| (s[1].x - s[0].x).hypot(s[1].y - s[0].y)).sum::<f64>() / 2.0;
    let farther = [80.0, 100.0, 125.0, 150.0].into_iter().filter(|&away| away <= half);
    for away in [3.0f64, 8.0, 14.0, 22.0, 32.0, 44.0, 60.0].into_iter().chain(farther) {
        // Walk `away` from the end along the route: the point and the direction back to the end.
        let (mut left, mut at, mut towards_end) = (away, end, Point { x: 0.0, y: 1.0 });
        for segment in points.windows(2) {
            let (dx, dy) = (segment[1].x - segment[0].x, segment[1].y - segment[0].y);
            let length = dx.hypot(dy);
            if length < 1e-9 {
                continue;
            }
            towards_end = Point { x: -dx / length, y: -dy / length };
            let step = left.min(length);
            at = Point { x: segment[0].x + dx / length * step, y: segment[0].y + dy / length * step };
            left -= step;
            if left <= 0.0 {
                break;
            }
        }
        // The label's corner nearest the end touches the line `GAP` off it, on either side; it
        // reaches away from the end, so it never covers the end's node. Off a slanted line, the
        // two corners at the point that the line does not pass through (the second reaches
        // towards the end beside it; `Room::choose` keeps it off the node).
        const GAP: f64 = 3.0;
        let vertical = towards_end.y.abs() >= towards_end.x.abs();
        let slanted = towards_end.x.abs().min(towards_end.y.abs()) > 0.25;
        let corner = |right: bool, below: bool| {
            (if right { at.x + GAP } else { at.x - GAP - w }, if below { at.y + GAP } else { at.y - GAP - h })
        };
        let spots = if slanted {
            // The one reaching away from the end first.
            let (right, below) = (towards_end.x > 0.0, towards_end.y > 0.0);
            [corner(right, !below), corner(!right, below)]
        } else if vertical {
            let y = if towards_end.y > 0.0 { at.y - h } else { at.y };
            [(at.x + GAP, y), (at.x - GAP - w, y)]
        } else {
            let x = if towards_end.x > 0.0 { at.x - w } else { at.x };
            [(x, at.y - GAP - h), (x, at.y + GAP)]
        };
        candidates.extend(spots.map(|(x, y)| Rect { x, y, width: w, height: h }));
    }
    room.choose(&candidates, route, candidates[0])
}

/// What a label must keep clear of: the boxes, the labels placed before, every edge, and the
/// frame's heading (it stays right of and below `corner`).
struct Room<'a> {
    obstacles: Boxes,
    /// The obstacles the label being placed may lie in.
    open: &'a [usize],
    placed: Boxes,
    routes: Segments,
    corner: Point,
}

impl Room<'_> {
    /// The first of `candidates` clear of nodes, labels and every edge; else the nearest place
    /// around the first candidate clear of all that; else the first candidate clear of nodes,
    /// labels and its own edge; else of nodes and labels; else the nearest place around
    /// `fallback` clear of nodes and labels; else `fallback`. The chosen box counts as placed.
    fn choose(&mut self, candidates: &[Rect], route: &[Point], fallback: Rect) -> Rect {
        let clear = |b: &Rect| {
            b.x >= self.corner.x
                && b.y >= self.corner.y
                && !self.obstacles.overlap(b.grown(2.0), self.open)
                && !self.placed.overlap(b.grown(2.0), &[])
        };
        let off = |route: &[Point], b: &Rect| !route.windows(2).any(|s| segment_meets_box(s[0], s[1], *b));
        let off_edges = |b: &Rect| !self.routes.meet(*b);
        // Near the first candidate, clear of everything, where no candidate is.
        let nearby = || {
            let first = candidates.first()?;
            around(*first, 4.0, 1..16).map(|(_, spot)| spot).find(|b| clear(b) && off_edges(b))
        };
        let chosen = candidates
            .iter()
            .find(|b| clear(b) && off_edges(b))
            .copied()
            .or_else(nearby)
            .or_else(|| candidates.iter().find(|b| clear(b) && off(route, b)).copied())
            .or_else(|| candidates.iter().find(|b| clear(b)).copied())
            .or_else(|| around(fallback, 8.0, 1..40).map(|(_, spot)| spot).find(|b| clear(b)))
            .unwrap_or(fallback);
        self.placed.push(chosen);
        chosen
    }
}

/// `origin` moved along square rings `step` apart around it, ring by ring (`rings`), the
/// nearest first within a ring, each with its ring: where to look for free space.
pub(crate) fn around(origin: Rect, step: f64, rings: std::ops::Range<usize>) -> impl Iterator<Item = (usize, Rect)> {
    rings.flat_map(move |ring| {
        let r = ring as i64;
        let mut spots: Vec<Rect> = (-r..=r)
            .flat_map(|dx| (-r..=r).map(move |dy| (dx, dy)))
            .filter(|&(dx, dy)| dx.abs() == r || dy.abs() == r)
            .map(|(dx, dy)| Rect { x: origin.x + step * dx as f64, y: origin.y + step * dy as f64, ..origin })
            .collect();
        let away = |s: &Rect| (s.x - origin.x).hypot(s.y - origin.y);
        spots.sort_by(|a, b| away(a).total_cmp(&away(b)));
        spots.into_iter().map(move |spot| (ring, spot))
    })
}

fn midpoint(points: &[Point]) -> Point {
    if points.len() % 2 == 1 {
        return points[points.len() / 2];
    }
    let (a, b) = (points[points.len() / 2 - 1], points[points.len() / 2]);
    Point { x: (a.x + b.x) / 2.0, y: (a.y + b.y) / 2.0 }
}
