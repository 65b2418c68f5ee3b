//! Placing edge labels the layout did not place (port-to-port connections): beside their edge,
//! clear of every box, every label placed before and every edge; and the geometry tests that
//! placement (and the layout's tests) rely on.

use super::{measure::label_size, Point, Rect};

pub(crate) fn intersects(a: Rect, b: Rect) -> bool {
    a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height
}

/// A box for `label` beside its edge, clear of every node, already placed label and edge (its
/// own included) if any candidate is (along each segment, on either side); else clear of nodes
/// and labels; else the middle of the edge.
pub(crate) fn place_label(
    route: &[Point],
    label: &str,
    obstacles: &[Rect],
    placed: &[Rect],
    routes: &[&[Point]],
) -> Rect {
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
    let clear = |b: Rect| {
        let padded = Rect { x: b.x - 2.0, y: b.y - 2.0, width: b.width + 4.0, height: b.height + 4.0 };
        b.x >= 0.0 && b.y >= 0.0 && !obstacles.iter().chain(placed).any(|o| intersects(padded, *o))
    };
    let boxes: Vec<Rect> = candidates.into_iter().map(|(x, y)| Rect { x, y, width: w, height: h }).collect();
    let off_edges = |b: &Rect| !routes.iter().any(|route| route.windows(2).any(|s| segment_meets_box(s[0], s[1], *b)));
    let clear_of_all = boxes.iter().copied().find(|b| clear(*b) && off_edges(b));
    clear_of_all.or_else(|| boxes.iter().copied().find(|b| clear(*b))).unwrap_or_else(|| {
        let mid = midpoint(route);
        Rect { x: mid.x + 4.0, y: mid.y - h / 2.0, width: w, height: h }
    })
}

/// Whether the segment from `a` to `b` passes through the box (Liang–Barsky clipping).
pub(crate) fn segment_meets_box(a: Point, b: Point, r: Rect) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [(-dx, a.x - r.x), (dx, r.x + r.width - a.x), (-dy, a.y - r.y), (dy, r.y + r.height - a.y)] {
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
