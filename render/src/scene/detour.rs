//! A route around the boxes for an edge drawn anew among nodes kept where they were (the
//! editor's arranging): where the straight line between its boxes passes another box,
//! axis-parallel segments along the gaps between the boxes' rows and the columns beside
//! boxes — the shortest such route of three or five segments that passes no box.

use crate::geometry::{Point, Rect};
use crate::grid::Boxes;

/// Room kept between a row of boxes and a route along the gap beside it.
const GAP_ROOM: f64 = 4.0;

/// The boxes a route must keep out of, indexed for "what meets this segment", the gaps
/// between their rows (`gaps`) and the columns beside them.
pub(super) struct Obstacles<'a> {
    grid: Boxes,
    pub boxes: &'a [Rect],
    gaps: Vec<f64>,
    columns: Vec<f64>,
}

impl<'a> Obstacles<'a> {
    pub(super) fn new(boxes: &'a [Rect]) -> Obstacles<'a> {
        let columns = boxes.iter().flat_map(|r| [r.x - 2.0 * GAP_ROOM, r.x + r.width + 2.0 * GAP_ROOM]).collect();
        Obstacles { grid: Boxes::new(boxes.iter().copied()), boxes, gaps: gaps(boxes), columns }
    }

    /// Whether `route` passes through a box other than boxes `from` and `to` (its ends').
    pub(super) fn blocks(&self, route: &[Point], from: usize, to: usize) -> bool {
        route.windows(2).any(|s| self.grid.meet_segment(s[0], s[1], &[from, to]))
    }

    /// The shortest route around the other boxes from box `from` to box `to`, if there is one
    /// of these: out of `from` up or down into a gap between the rows of boxes, along it, and
    /// into `to` (three segments); or out into the gap beside `from`, along it to a column
    /// beside a box, along that to the gap beside `to`, and into it (five).
    pub(super) fn around(&self, from: usize, to: usize) -> Option<Vec<Point>> {
        let (a, b) = (self.boxes[from], self.boxes[to]);
        let gaps = &self.gaps;
        let beside = |r: Rect| {
            let above = gaps.iter().copied().filter(|&y| y < r.y).fold(f64::NAN, f64::max);
            let below = gaps.iter().copied().find(|&y| y > r.y + r.height);
            [Some(above).filter(|y| !y.is_nan()), below].into_iter().flatten().collect::<Vec<f64>>()
        };
        let xs = |r: Rect| [0.5, 0.25, 0.75].map(|f| r.x + r.width * f);
        let mut candidates: Vec<Vec<Point>> = Vec::new();
        for (x0, x1) in xs(a).into_iter().flat_map(|x0| xs(b).map(move |x1| (x0, x1))) {
            let end =
                |x: f64, r: Rect, y: f64| Point { x, y: if y > r.y + r.height / 2.0 { r.y + r.height } else { r.y } };
            for &y in gaps {
                candidates.push(vec![end(x0, a, y), Point { x: x0, y }, Point { x: x1, y }, end(x1, b, y)]);
            }
            for (y0, y1) in beside(a).into_iter().flat_map(|y0| beside(b).into_iter().map(move |y1| (y0, y1))) {
                for &x in &self.columns {
                    let (p, q) = (Point { x, y: y0 }, Point { x, y: y1 });
                    candidates.push(vec![
                        end(x0, a, y0),
                        Point { x: x0, y: y0 },
                        p,
                        q,
                        Point { x: x1, y: y1 },
                        end(x1, b, y1),
                    ]);
                }
            }
        }
        let length = |route: &Vec<Point>| {
            route.windows(2).map(|s| (s[1].x - s[0].x).abs() + (s[1].y - s[0].y).abs()).sum::<f64>()
        };
        candidates.sort_by(|p, q| length(p).total_cmp(&length(q)));
        candidates.into_iter().find(|route| !self.blocks(route, from, to))
    }
}

/// The middles of the horizontal gaps no box spans, and a line below all of them (not above:
/// the frame's heading is there), top down.
fn gaps(boxes: &[Rect]) -> Vec<f64> {
    let mut spans: Vec<(f64, f64)> = boxes.iter().map(|b| (b.y - GAP_ROOM, b.y + b.height + GAP_ROOM)).collect();
    spans.sort_by(|p, q| p.0.total_cmp(&q.0));
    let mut gaps = Vec::new();
    let mut reach = f64::NEG_INFINITY;
    for (start, end) in spans {
        if reach.is_finite() && start > reach {
            gaps.push((reach + start) / 2.0);
        }
        reach = reach.max(end);
    }
    if reach.is_finite() {
        gaps.push(reach + GAP_ROOM);
    }
    gaps
}
