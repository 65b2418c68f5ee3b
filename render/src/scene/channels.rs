//! Connections drawn along the fresh layout's routes, made orthogonal. The layout ran each
//! connection port to port through the ranks, its long edges straight through each rank at
//! their places between the boxes, in the order crossing minimisation gave them; here each
//! slant from one rank to the next becomes a vertical in the gap between them, on a track of its
//! own. The tracks of a gap are ordered so that two routes cross there only where their ends
//! change order (where any drawing must cross them). The routes at one port leave it (or enter
//! it) side by side, as the layout fanned them out, so no two routes touch.

use std::collections::HashMap;

use super::Point;
use crate::geometry::corners;
use crate::layout::tracks::{slots, Track, MOST_TRACKS, TRACK};
use crate::layout::PORT_FAN_MOST;

/// How far from its port's anchor the layout may have fanned a route's end.
pub(super) const FANNED: f64 = PORT_FAN_MOST / 2.0 + 0.5;
/// The closest two tracks may run (where the layout gave a gap less room than its tracks take):
/// a gap whose tracks would run closer is left to the router around the boxes.
const CLOSEST: f64 = 2.0;

/// A connection the layout routed: its ports' anchors and the layout's route, from the side of
/// the source's box to the side of the target's, meeting each at its port's height.
pub(super) struct Followed<'a> {
    pub from: Point,
    pub to: Point,
    pub route: &'a [Point],
}

/// A gap between two ranks: its sides' x, in hundredths.
type Gap = (i64, i64);
/// A slant of a route: the connection's index and the segment's.
type Slant = (usize, usize);

/// Per connection, its orthogonal route; none where the layout's route does not run from its
/// source's port to its target's (an edge the layout reversed to break a cycle).
pub(super) fn follow(connections: &[Followed]) -> Vec<Option<Vec<Point>>> {
    let skeletons: Vec<Option<Vec<Point>>> = connections.iter().map(skeleton).collect();
    // Per gap (by its two sides' x), its tracks, each of one slant (by connection and segment).
    let mut gaps: HashMap<Gap, Vec<(Slant, Track)>> = HashMap::new();
    for (k, (c, skeleton)) in connections.iter().zip(&skeletons).enumerate() {
        let Some(points) = skeleton else { continue };
        for (s, pair) in points.windows(2).enumerate() {
            let (a, b) = (pair[0], pair[1]);
            if !slants(a, b) {
                continue;
            }
            // The gap between the layout's ranks (the skeleton's ends are on the ports, inside them).
            let (left, right) = (c.route[s].x, c.route[s + 1].x);
            let gap = (key(left.min(right)), key(left.max(right)));
            let (from, to) = if a.x < b.x { (a.y, b.y) } else { (b.y, a.y) };
            gaps.entry(gap).or_default().push(((k, s), Track { from, to }));
        }
    }
    // A gap with too many tracks leaves its routes to the router around the boxes.
    let places: HashMap<Slant, f64> =
        gaps.into_iter().filter_map(|(gap, tracks)| places(gap, tracks)).flatten().collect();
    skeletons
        .into_iter()
        .enumerate()
        .map(|(k, skeleton)| {
            let points = skeleton?;
            let mut route = vec![points[0]];
            for (s, pair) in points.windows(2).enumerate() {
                if slants(pair[0], pair[1]) {
                    let x = *places.get(&(k, s))?;
                    route.push(Point { x, y: pair[0].y });
                    route.push(Point { x, y: pair[1].y });
                }
                route.push(pair[1]);
            }
            // A gap's track may lie a little inside a rank's band, before the point where the
            // layout's route left it: the route would turn back on itself there.
            Some(corners(route))
        })
        .collect()
}

/// The layout's route with its ends at the ports' anchors (at the heights the layout fanned
/// them out to); none where it does not leave its source's port rightwards and enter its
/// target's from the left.
fn skeleton(c: &Followed) -> Option<Vec<Point>> {
    let (first, last) = (*c.route.first()?, *c.route.last()?);
    let meets = |end: Point, port: Point| (end.y - port.y).abs() <= FANNED;
    let (outside, ahead) = (first.x < c.from.x - 1e-6, last.x > c.to.x + 1e-6);
    if c.route.len() < 2 || !meets(first, c.from) || !meets(last, c.to) || outside || ahead {
        return None;
    }
    let mut points = c.route.to_vec();
    let n = points.len();
    (points[0].x, points[n - 1].x) = (c.from.x, c.to.x);
    // An end the layout did not fan out is on the anchor, to the last bit.
    snap(points.iter_mut(), c.from.y);
    snap(points.iter_mut().rev(), c.to.y);
    Some(points)
}

/// Moves the first level stretch of `points` to `height` if it is within rounding of it.
fn snap<'p>(mut points: impl Iterator<Item = &'p mut Point>, height: f64) {
    let Some(first) = points.next() else { return };
    let level = first.y;
    if (level - height).abs() < 1e-6 {
        first.y = height;
        points.take_while(|p| (p.y - level).abs() < 1e-6).for_each(|p| p.y = height);
    }
}

/// Whether a segment of the layout's route slants (neither level nor upright already, as
/// around a wrapped drawing's columns): it needs a track.
fn slants(a: Point, b: Point) -> bool {
    (a.y - b.y).abs() >= 1e-6 && (a.x - b.x).abs() >= 1e-6
}

/// Where each track of a gap runs: left to right in the order that crosses fewest routes,
/// tracks whose heights overlap side by side, the others sharing a place (`tracks::slots`), a
/// track's width apart and from the gap's sides; closer where the gap is narrower than that,
/// but none where they would run closer than `CLOSEST` or the gap holds more than `MOST_TRACKS`.
fn places((left, right): Gap, tracks: Vec<(Slant, Track)>) -> Option<Vec<(Slant, f64)>> {
    if tracks.len() > MOST_TRACKS {
        return None;
    }
    let slot = slots(&tracks.iter().map(|&(_, t)| t).collect::<Vec<_>>());
    let count = slot.iter().max().map_or(1, |m| m + 1) as f64;
    let (from, to) = (left as f64 / SCALE, right as f64 / SCALE);
    let step = TRACK.min((to - from) / (count + 1.0));
    if step < CLOSEST {
        return None;
    }
    let middle = (from + to) / 2.0;
    let place = |slot: usize| middle + (slot as f64 - (count - 1.0) / 2.0) * step;
    Some(tracks.into_iter().zip(slot).map(|((slant, _), slot)| (slant, place(slot))).collect())
}

/// A gap's side as a key: its x in hundredths.
const SCALE: f64 = 100.0;
fn key(x: f64) -> i64 {
    (x * SCALE).round() as i64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tests_bindings::meetings;

    fn p(x: f64, y: f64) -> Point {
        Point { x, y }
    }

    /// A connection from a port at `from` (x 80) to one at `to` (x 160), as the layout routed
    /// it between ranks whose bands end at x 100 and start again at x 140: level in the bands,
    /// slanting across the gap between.
    fn across_one_gap(from: f64, to: f64) -> Vec<Point> {
        vec![p(100.0, from), p(140.0, to)]
    }

    fn followed<'a>(routes: &'a [Vec<Point>]) -> Vec<Followed<'a>> {
        routes
            .iter()
            .map(|route| Followed { from: p(80.0, route[0].y), to: p(160.0, route[route.len() - 1].y), route })
            .collect()
    }

    /// Each connection's route, every one of them followed.
    fn routed(layout: &[Vec<Point>]) -> Vec<Vec<Point>> {
        follow(&followed(layout)).into_iter().map(Option::unwrap).collect()
    }

    fn orthogonal(route: &[Point]) -> bool {
        route.windows(2).all(|s| s[0].x == s[1].x || s[0].y == s[1].y)
    }

    #[test]
    fn routes_whose_ends_keep_their_order_do_not_cross() {
        // Both going down, the second starting and ending lower: on tracks in the wrong order
        // (the first left) each would cross the other's track.
        let layout = [across_one_gap(0.0, 50.0), across_one_gap(20.0, 70.0)];
        let routes = routed(&layout);
        assert!(routes.iter().all(|r| orthogonal(r)), "{routes:?}");
        assert_eq!(meetings(&routes[0], &routes[1]), (0, 0), "{routes:?}");
        // The lower one turns first (its track left of the other's).
        assert!(routes[1][1].x < routes[0][1].x, "{routes:?}");
        // Going up, the mirror image.
        let layout = [across_one_gap(50.0, 0.0), across_one_gap(70.0, 20.0)];
        let routes = routed(&layout);
        assert_eq!(meetings(&routes[0], &routes[1]), (0, 0), "{routes:?}");
    }

    #[test]
    fn a_route_ending_where_another_starts_does_not_touch_it() {
        let layout = [across_one_gap(10.0, 20.0), across_one_gap(20.0, 30.0)];
        let routes = routed(&layout);
        assert_eq!(meetings(&routes[0], &routes[1]), (0, 0), "{routes:?}");
    }

    #[test]
    fn a_gap_with_more_tracks_than_fit_is_left_to_the_router() {
        // Fifty routes nested in one gap, each crossing all the others: 40 pt hold them only
        // 0.8 pt apart.
        let layout: Vec<Vec<Point>> = (0..50).map(|i| across_one_gap(i as f64, 100.0 - i as f64)).collect();
        assert!(follow(&followed(&layout)).iter().all(Option::is_none));
        // Ten fit.
        let layout: Vec<Vec<Point>> = (0..10).map(|i| across_one_gap(i as f64, 100.0 - i as f64)).collect();
        assert!(follow(&followed(&layout)).iter().all(Option::is_some));
    }

    #[test]
    fn routes_whose_ends_change_order_cross_once() {
        let layout = [across_one_gap(0.0, 60.0), across_one_gap(20.0, 40.0)];
        let routes = routed(&layout);
        assert_eq!(meetings(&routes[0], &routes[1]), (1, 0), "{routes:?}");
    }

    #[test]
    fn routes_fanned_out_at_one_port_neither_touch_nor_cross() {
        // Four routes leaving one port 3 pt apart (as the layout fans them: in the order of
        // their targets), to targets far above, above, level and below.
        let layout = [
            across_one_gap(46.0, 0.0),
            across_one_gap(49.0, 30.0),
            across_one_gap(52.0, 52.0),
            across_one_gap(55.0, 100.0),
        ];
        let routes = routed(&layout);
        for i in 0..4 {
            for j in (i + 1)..4 {
                assert_eq!(meetings(&routes[i], &routes[j]), (0, 0), "{i} and {j}: {routes:?}");
            }
        }
        // Every track lies in the gap.
        for route in &routes {
            assert!(route[1..route.len() - 1].iter().all(|q| (100.0..=140.0).contains(&q.x)));
        }
    }

    #[test]
    fn a_route_through_ranks_turns_in_the_gaps_and_keeps_its_places_in_the_ranks() {
        // Across two gaps, level through the rank between them (a long edge's dummy at 30).
        let layout = [vec![p(100.0, 0.0), p(140.0, 30.0), p(240.0, 30.0), p(280.0, 60.0)]];
        let connections = [Followed { from: p(80.0, 0.0), to: p(300.0, 60.0), route: &layout[0] }];
        let route = follow(&connections).remove(0).unwrap();
        assert!(orthogonal(&route), "{route:?}");
        assert_eq!((route[0], *route.last().unwrap()), (p(80.0, 0.0), p(300.0, 60.0)));
        let level_at_30: Vec<&[Point]> = route.windows(2).filter(|s| s[0].y == 30.0 && s[1].y == 30.0).collect();
        assert!(level_at_30.iter().any(|s| s[0].x <= 140.0 && s[1].x >= 240.0), "{route:?}");
        let turns: Vec<f64> = route.windows(2).filter(|s| s[0].x == s[1].x).map(|s| s[0].x).collect();
        assert_eq!(turns.len(), 2, "{route:?}");
        assert!((76.0..=164.0).contains(&turns[0]) && (216.0..=304.0).contains(&turns[1]), "{route:?}");
    }

    #[test]
    fn a_route_the_layout_did_not_run_from_port_to_port_is_left_to_the_router() {
        // Laid out reversed (a cycle's edge back): it leaves the source's box on the left.
        let layout = [vec![p(60.0, 0.0), p(20.0, 30.0)]];
        let connections = [Followed { from: p(80.0, 0.0), to: p(160.0, 30.0), route: &layout[0] }];
        assert_eq!(follow(&connections), vec![None]);
        // Its end far from the port (more than a fan's room).
        let layout = [across_one_gap(0.0, 30.0)];
        let connections = [Followed { from: p(80.0, 10.0), to: p(160.0, 30.0), route: &layout[0] }];
        assert_eq!(follow(&connections), vec![None]);
    }
}
