//! The router's search where no route of a few segments is clear (`connections`): the shortest
//! orthogonal route with the fewest bends through the free room between the boxes — Dijkstra
//! over the grid of the lines a clearance beside each box's sides and the middles between them
//! (an orthogonal visibility graph, as libavoid and ELK's orthogonal router search), near the
//! two ports.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::{Point, Rect};
use crate::geometry::corners;
use crate::grid::Boxes;

/// What a bend costs, in points of length: a route a little longer is worth one bend less.
const BEND: f64 = 40.0;
/// How far around the two ports the search looks.
const AROUND: f64 = 400.0;

/// A route from `from` (leaving it level towards `leaving`: 1 right, -1 left) to `to` (to go on
/// level from there away from the side `entering` names: a bend there counts) that keeps
/// `clearance` from every box but those `inside` names: its corners, `from` and `to` among them;
/// none where the room near the two holds none.
pub(super) fn search(
    (from, leaving): (Point, f64),
    (to, entering): (Point, f64),
    boxes: &[Rect],
    obstacles: &Boxes,
    (clearance, inside): (f64, &[usize]),
) -> Option<Vec<Point>> {
    let window = Rect {
        x: from.x.min(to.x) - AROUND,
        y: from.y.min(to.y) - AROUND,
        width: (from.x - to.x).abs() + 2.0 * AROUND,
        height: (from.y - to.y).abs() + 2.0 * AROUND,
    };
    let near: Vec<&Rect> = boxes.iter().filter(|b| crate::geometry::intersects(**b, window)).collect();
    let beside = clearance + 1.0;
    let xs = lines([from.x, to.x], near.iter().flat_map(|b| [b.x - beside, b.x + b.width + beside]));
    let ys = lines([from.y, to.y], near.iter().flat_map(|b| [b.y - beside, b.y + b.height + beside]));
    let grid = Grid { xs, ys };
    let clear = |a: Point, b: Point| {
        let (x, y) = (a.x.min(b.x) - clearance + 0.01, a.y.min(b.y) - clearance + 0.01);
        let size = |d: f64| d.abs() + 2.0 * (clearance - 0.01);
        !obstacles.overlap(Rect { x, y, width: size(a.x - b.x), height: size(a.y - b.y) }, inside)
    };
    let (start, end) = (grid.index(from)?, grid.index(to)?);
    let (out, arrive) = (if leaving > 0.0 { RIGHT } else { LEFT }, if entering > 0.0 { LEFT } else { RIGHT });
    let path = grid.shortest((start, out), (end, arrive), &clear)?;
    Some(corners(path.into_iter().map(|i| grid.point(i)).collect()))
}

/// The grid's lines one way: `ends` and `sides`, sorted, and the middle between each two
/// neighbours.
fn lines(ends: [f64; 2], sides: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut at: Vec<f64> = ends.into_iter().chain(sides).collect();
    at.sort_by(f64::total_cmp);
    at.dedup_by(|a, b| (*a - *b).abs() < 0.5);
    let middles: Vec<f64> = at.windows(2).map(|w| (w[0] + w[1]) / 2.0).collect();
    at.extend(middles);
    at.sort_by(f64::total_cmp);
    at
}

/// Directions of travel: along x (right, left) and along y (down, up).
const RIGHT: usize = 0;
const LEFT: usize = 1;
const STEPS: [(i64, i64); 4] = [(1, 0), (-1, 0), (0, 1), (0, -1)];

struct Grid {
    xs: Vec<f64>,
    ys: Vec<f64>,
}

impl Grid {
    fn index(&self, p: Point) -> Option<(usize, usize)> {
        let find = |lines: &[f64], v: f64| lines.iter().position(|&l| (l - v).abs() < 0.5);
        Some((find(&self.xs, p.x)?, find(&self.ys, p.y)?))
    }

    fn point(&self, (i, j): (usize, usize)) -> Point {
        Point { x: self.xs[i], y: self.ys[j] }
    }

    /// The cheapest path of grid points from `start` (leaving towards `out`) to `end` (arriving
    /// towards `arrive`): length plus `BEND` a turn, over the steps `clear` allows.
    fn shortest(
        &self,
        (start, out): ((usize, usize), usize),
        (end, arrive): ((usize, usize), usize),
        clear: &dyn Fn(Point, Point) -> bool,
    ) -> Option<Vec<(usize, usize)>> {
        let (w, h) = (self.xs.len(), self.ys.len());
        let state = |(i, j): (usize, usize), d: usize| (j * w + i) * 4 + d;
        let mut cost = vec![f64::INFINITY; w * h * 4];
        let mut came: Vec<usize> = vec![usize::MAX; w * h * 4];
        let mut heap = BinaryHeap::new();
        let first = state(start, out);
        cost[first] = 0.0;
        heap.push((Reverse(0i64), first));
        while let Some((Reverse(key), s)) = heap.pop() {
            if key > (cost[s] * 100.0) as i64 {
                continue; // reached more cheaply since
            }
            let (cell, d) = (s / 4, s % 4);
            let at = (cell % w, cell / w);
            if at == end {
                let mut path = vec![at];
                let mut k = s;
                while came[k] != usize::MAX {
                    k = came[k];
                    path.push(((k / 4) % w, (k / 4) / w));
                }
                path.reverse();
                return Some(path);
            }
            for (turn, &(di, dj)) in STEPS.iter().enumerate() {
                let (i, j) = (at.0 as i64 + di, at.1 as i64 + dj);
                if turn ^ 1 == d || i < 0 || j < 0 || i >= w as i64 || j >= h as i64 {
                    continue; // no turning back
                }
                let next = (i as usize, j as usize);
                let (p, q) = (self.point(at), self.point(next));
                let bends = usize::from(turn != d) + usize::from(next == end && turn != arrive);
                let c = cost[s] + (p.x - q.x).abs() + (p.y - q.y).abs() + BEND * bends as f64;
                let n = state(next, turn);
                if c < cost[n] && clear(p, q) {
                    cost[n] = c;
                    came[n] = s;
                    heap.push((Reverse((c * 100.0) as i64), n));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point { x, y }
    }

    /// A route from a port at (0, 0) facing right to one at (312, 0) facing left, its stubs
    /// 12 pt long.
    fn route(boxes: &[Rect]) -> Option<Vec<Point>> {
        let obstacles = Boxes::new(boxes.iter().copied());
        let found = search((p(0.0, 0.0), 1.0), (p(300.0, 0.0), -1.0), boxes, &obstacles, (6.0, &[]))?;
        Some(corners([found, vec![p(312.0, 0.0)]].concat()))
    }

    #[test]
    fn a_route_goes_around_a_box_in_its_way_clear_of_it() {
        // A box across the straight line, reaching further down than up: around above it.
        let wall = Rect { x: 100.0, y: -40.0, width: 50.0, height: 120.0 };
        let found = route(&[wall]).unwrap();
        assert_eq!((found[0], *found.last().unwrap()), (p(0.0, 0.0), p(312.0, 0.0)));
        assert_eq!(found.len(), 6, "four bends: {found:?}");
        assert!(found.iter().all(|q| q.y <= 0.0), "above: {found:?}");
        for s in found.windows(2) {
            assert!(s[0].x == s[1].x || s[0].y == s[1].y, "{found:?}");
            assert!(!crate::geometry::segment_meets_box(s[0], s[1], wall.grown(6.0)), "{found:?}");
        }
        // Nothing in the way: straight.
        assert_eq!(route(&[]).unwrap(), [p(0.0, 0.0), p(312.0, 0.0)]);
    }

    #[test]
    fn a_port_walled_in_has_no_route() {
        let around = |x: f64, y: f64, width: f64, height: f64| Rect { x, y, width, height };
        let walls = [
            around(250.0, -60.0, 120.0, 20.0),
            around(250.0, 40.0, 120.0, 20.0),
            around(250.0, -60.0, 20.0, 120.0),
            around(350.0, -60.0, 20.0, 120.0),
        ];
        assert_eq!(route(&walls), None);
    }
}
