//! Orthogonal routes of connections and bindings, port to port: out of the source port away
//! from its box, along a vertical track, and into the target port from its side. Each port has
//! a track of its own beside its box, so connections into one port join on its track like the
//! branches of a tree, and no two connections of different ports run along one another (a
//! shared stretch of two routes reads as a box, not as two wires). A route that a box blocks
//! detours along the nearest free row between the boxes.

use super::{channels::FANNED, maze, Point, Rect};
use crate::geometry::corners;
use crate::grid::{span, Boxes, Cells};

/// A connection to route: its two port anchors and which way each port faces (1: the right
/// border, -1: the left), and the ids of the ports.
pub(super) struct Connection<'a> {
    pub from: Point,
    pub from_faces: f64,
    pub to: Point,
    pub to_faces: f64,
    pub from_port: &'a str,
    pub to_port: &'a str,
    /// The boxes it runs inside (its ends' parents, when components nest): not in its way.
    pub inside: Vec<usize>,
}

/// How far beyond a port's anchor its track starts, and the space between tracks.
const STUB: f64 = 12.0;
const TRACK: f64 = 8.0;
/// Space kept between a route and a box it passes.
const CLEARANCE: f64 = 6.0;
/// Tracks tried beside the first one before a route may share a stretch with another.
const SHIFTS: usize = 12;
/// The room a port's tracks take beside its symbol (the first few of them).
pub(super) const TRACKS: f64 = STUB + 3.0 * TRACK;

/// A segment of a route, with the ports of its connection.
#[derive(Clone, Copy)]
struct Placed<'a> {
    a: Point,
    b: Point,
    from_port: &'a str,
    to_port: &'a str,
}

/// Routes every connection among `boxes`: where `given` has a route for it that no box is in
/// the way of, that one (placed first), else the first clear route, in order.
pub(super) fn route<'a>(
    connections: &[Connection<'a>],
    boxes: &[Rect],
    given: Vec<Option<Vec<Point>>>,
) -> Vec<Vec<Point>> {
    let obstacles = Boxes::new(boxes.iter().copied());
    let mut placed: Cells<Placed> = Cells::new();
    let mut routes: Vec<Option<Vec<Point>>> = connections
        .iter()
        .zip(given.into_iter().chain(std::iter::repeat(None)))
        .map(|(c, route)| route.filter(|route| at_ports(c, route) && clear_of_boxes(c, route, &obstacles)))
        .collect();
    for (c, route) in connections.iter().zip(&routes) {
        if let Some(route) = route {
            place(&mut placed, c, route);
        }
    }
    for (c, route) in connections.iter().zip(&mut routes) {
        if route.is_none() {
            let found = best_route(c, boxes, &obstacles, &placed);
            place(&mut placed, c, &found);
            *route = Some(found);
        }
    }
    routes.into_iter().flatten().collect()
}

/// Puts `route`'s segments among those `placed`.
fn place<'a>(placed: &mut Cells<Placed<'a>>, c: &Connection<'a>, route: &[Point]) {
    for s in route.windows(2) {
        placed.insert(span(s[0], s[1]), Placed { a: s[0], b: s[1], from_port: c.from_port, to_port: c.to_port });
    }
}

/// Whether `route` starts at the connection's source port and ends at its target port (or
/// beside them, fanned out with others at the port): a route kept from the scene before may
/// not, where the ports moved along boxes that stayed.
fn at_ports(c: &Connection, route: &[Point]) -> bool {
    let meets = |end: Option<&Point>, port: Point| end.is_some_and(|p| p.x == port.x && (p.y - port.y).abs() <= FANNED);
    meets(route.first(), c.from) && meets(route.last(), c.to)
}

/// Whether no box is in the way of `route` (within `CLEARANCE`), but those it runs inside.
fn clear_of_boxes(c: &Connection, route: &[Point], obstacles: &Boxes) -> bool {
    route.windows(2).all(|s| {
        let segment = Rect {
            width: (s[0].x - s[1].x).abs().max(0.01),
            height: (s[0].y - s[1].y).abs().max(0.01),
            ..span(s[0], s[1])
        };
        !obstacles.overlap(segment.grown(CLEARANCE), &c.inside)
    })
}

/// The first clear route: on the ports' own tracks if it can, else on tracks further out; three
/// segments where the target is ahead, else five around the boxes.
fn best_route(c: &Connection, boxes: &[Rect], obstacles: &Boxes, placed: &Cells<Placed>) -> Vec<Point> {
    let alone = |route: &[Point]| {
        route.windows(2).all(|s| {
            !placed.any(span(s[0], s[1]).grown(2.0), |p| {
                // Branches of one tree (the same source or target port) may share a stretch.
                p.from_port != c.from_port && p.to_port != c.to_port && overlap(s[0], s[1], p.a, p.b)
            })
        })
    };
    let rows = rows(c, boxes);
    let mut fallback = None;
    for shift in 0..SHIFTS {
        let out = c.from.x + c.from_faces * (STUB + shift as f64 * TRACK);
        let into = c.to.x + c.to_faces * (STUB + shift as f64 * TRACK);
        for candidate in candidates(c, out, into, &rows) {
            if clear_of_boxes(c, &candidate, obstacles) {
                if alone(&candidate) {
                    return candidate;
                }
                fallback.get_or_insert(candidate);
            }
        }
    }
    fallback.or_else(|| searched(c, boxes, obstacles)).unwrap_or_else(|| around_everything(c, boxes))
}

/// A route searched through the free room between the boxes (`maze`), out of the source's stub
/// and into the target's.
fn searched(c: &Connection, boxes: &[Rect], obstacles: &Boxes) -> Option<Vec<Point>> {
    let out = Point { x: c.from.x + c.from_faces * STUB, y: c.from.y };
    let into = Point { x: c.to.x + c.to_faces * STUB, y: c.to.y };
    let found = maze::search((out, c.from_faces), (into, c.to_faces), boxes, obstacles, (CLEARANCE, &c.inside))?;
    Some(corners([vec![c.from], found, vec![c.to]].concat()))
}

/// The rows a route may run along between the boxes: the ports' own and those just above and
/// below each box, nearest the two ports first.
fn rows(c: &Connection, boxes: &[Rect]) -> Vec<f64> {
    let mut rows: Vec<f64> = vec![c.from.y, c.to.y];
    for b in boxes {
        rows.push(b.y - 2.0 * CLEARANCE);
        rows.push(b.y + b.height + 2.0 * CLEARANCE);
    }
    let cost = |y: f64| (y - c.from.y).abs() + (y - c.to.y).abs();
    rows.sort_by(|a, b| cost(*a).total_cmp(&cost(*b)).then(a.total_cmp(b)));
    rows.dedup();
    rows
}

/// Routes on the tracks at `out` (beside the source) and `into` (beside the target), made as
/// they are tried.
fn candidates<'r>(c: &'r Connection, out: f64, into: f64, rows: &'r [f64]) -> impl Iterator<Item = Vec<Point>> + 'r {
    let ahead = (into - out) * c.from_faces >= 0.0 && c.from_faces == -c.to_faces;
    // Along the target's track (connections into one port join there), or the source's.
    let straight = ahead.then(|| [three(c, into), three(c, out)]).into_iter().flatten();
    // Out, along a row between the boxes, and in.
    straight.chain(rows.iter().map(move |&y| five(c, out, y, into)))
}

fn three(c: &Connection, x: f64) -> Vec<Point> {
    let mut route = vec![c.from, Point { x, y: c.from.y }, Point { x, y: c.to.y }, c.to];
    route.dedup();
    route
}

fn five(c: &Connection, out: f64, y: f64, into: f64) -> Vec<Point> {
    let mut route = vec![
        c.from,
        Point { x: out, y: c.from.y },
        Point { x: out, y },
        Point { x: into, y },
        Point { x: into, y: c.to.y },
        c.to,
    ];
    route.dedup();
    route
}

/// The last resort: below every box.
fn around_everything(c: &Connection, boxes: &[Rect]) -> Vec<Point> {
    let bottom = boxes.iter().map(|b| b.y + b.height).fold(c.from.y.max(c.to.y), f64::max);
    let left = boxes.iter().map(|b| b.x).fold(c.from.x.min(c.to.x), f64::min) - STUB;
    let right = boxes.iter().map(|b| b.x + b.width).fold(c.from.x.max(c.to.x), f64::max) + STUB;
    let side = |faces: f64, x: f64| if faces > 0.0 { right.max(x + STUB) } else { left.min(x - STUB) };
    five(c, side(c.from_faces, c.from.x), bottom + 2.0 * CLEARANCE, side(c.to_faces, c.to.x))
}

/// Whether two axis-parallel segments run along one another (collinear within 2 pt, sharing
/// more than a point).
fn overlap(a0: Point, a1: Point, b0: Point, b1: Point) -> bool {
    let shared = |p0: f64, p1: f64, q0: f64, q1: f64| p0.max(p1).min(q0.max(q1)) - p0.min(p1).max(q0.min(q1)) > 1.0;
    let horizontal = |p: Point, q: Point| (p.y - q.y).abs() < 1e-9;
    match (horizontal(a0, a1), horizontal(b0, b1)) {
        (true, true) => (a0.y - b0.y).abs() < 2.0 && shared(a0.x, a1.x, b0.x, b1.x),
        (false, false) => (a0.x - b0.x).abs() < 2.0 && shared(a0.y, a1.y, b0.y, b1.y),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_route_is_taken_only_from_port_to_port() {
        let c = Connection {
            from: Point { x: 0.0, y: 0.0 },
            from_faces: 1.0,
            to: Point { x: 100.0, y: 30.0 },
            to_faces: -1.0,
            from_port: "A.out",
            to_port: "B.in",
            inside: Vec::new(),
        };
        let given = vec![Point { x: 0.0, y: 3.0 }, Point { x: 50.0, y: 3.0 }, Point { x: 50.0, y: 30.0 }, c.to];
        assert_eq!(route(std::slice::from_ref(&c), &[], vec![Some(given.clone())]), vec![given]);
        // Kept from a scene whose port sat 20 pt lower on a box that stayed: routed anew.
        let detached = vec![Point { x: 0.0, y: 20.0 }, Point { x: 50.0, y: 20.0 }, Point { x: 50.0, y: 30.0 }, c.to];
        let routed = route(std::slice::from_ref(&c), &[], vec![Some(detached)]);
        assert_eq!((routed[0][0], *routed[0].last().unwrap()), (c.from, c.to));
    }
}
