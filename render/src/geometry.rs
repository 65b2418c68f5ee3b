//! Plane geometry the layout and the scene share: points, axis-parallel boxes, and whether
//! boxes overlap or a segment passes through a box.

/// A point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
}

/// An axis-parallel box: top-left corner and size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
}

impl Rect {
    /// The box grown by `by` on every side.
    pub(crate) fn grown(self, by: f64) -> Rect {
        Rect { x: self.x - by, y: self.y - by, width: self.width + 2.0 * by, height: self.height + 2.0 * by }
    }
}

/// Whether the boxes overlap (touching is not overlapping).
pub(crate) fn intersects(a: Rect, b: Rect) -> bool {
    a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height
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
/// An orthogonal route's corners: without repeated points and without points in the middle of
/// a straight stretch (nor where it would turn back on itself).
pub(crate) fn corners(route: Vec<Point>) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::with_capacity(route.len());
    for p in route {
        if out.last().is_some_and(|q| (q.x - p.x).abs() < 1e-9 && (q.y - p.y).abs() < 1e-9) {
            continue;
        }
        if let [.., a, b] = out[..] {
            let level = (a.y - b.y).abs() < 1e-9 && (b.y - p.y).abs() < 1e-9;
            let upright = (a.x - b.x).abs() < 1e-9 && (b.x - p.x).abs() < 1e-9;
            if level || upright {
                out.pop();
            }
        }
        out.push(p);
    }
    out
}
