//! Placing edge labels the layout did not place (port-to-port connections): beside their edge,
//! clear of every box, every label placed before and every edge; and the geometry tests that
//! placement (and the layout's tests) rely on.

use super::{measure::label_size, Point, Rect};

pub(crate) fn intersects(a: Rect, b: Rect) -> bool {
    a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height
}

/// A box for `label` beside its edge, clear of every node, already placed label and edge (its
/// own included) if any candidate is (along each segment, on either side); else clear of nodes,
/// labels and its own edge; else of nodes and labels; else the nearest place to the edge's
/// middle clear of nodes and labels; else the middle.
pub(crate) fn place_label(
    route: &[Point],
    label: &str,
    obstacles: &[Rect],
    placed: &[Rect],
    routes: &[&[Point]],
) -> Rect {
    let (w, h) = label_size(label);
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
    let clear = |b: Rect| {
        let padded = Rect { x: b.x - 2.0, y: b.y - 2.0, width: b.width + 4.0, height: b.height + 4.0 };
        b.x >= 0.0 && b.y >= 0.0 && !obstacles.iter().chain(placed).any(|o| intersects(padded, *o))
    };
    let boxes: Vec<Rect> = candidates.into_iter().map(|(x, y)| Rect { x, y, width: w, height: h }).collect();
    let off = |route: &[Point], b: &Rect| !route.windows(2).any(|s| segment_meets_box(s[0], s[1], *b));
    let off_edges = |b: &Rect| routes.iter().all(|route| off(route, b));
    let clear_of_all = boxes.iter().copied().find(|b| clear(*b) && off_edges(b));
    let off_its_edge = || boxes.iter().copied().find(|b| clear(*b) && off(route, b));
    let mid = midpoint(route);
    let at_middle = Rect { x: mid.x + 4.0, y: mid.y - h / 2.0, width: w, height: h };
    // Crowded: the nearest place around the middle clear of nodes and labels.
    let nearest_clear = || around(at_middle, 8.0, 1..40).map(|(_, spot)| spot).find(|b| clear(*b));
    clear_of_all
        .or_else(off_its_edge)
        .or_else(|| boxes.iter().copied().find(|b| clear(*b)))
        .or_else(nearest_clear)
        .unwrap_or(at_middle)
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
