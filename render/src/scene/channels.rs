//! Connections drawn along the fresh layout's routes, made orthogonal. The layout ran each
//! connection port to port through the ranks, its long edges straight through each rank at
//! their places between the boxes, in the order crossing minimisation gave them; here each
//! slant from one rank to the next becomes a vertical in the gap between them, on a track of its
//! own. The tracks of a gap are ordered so that two routes cross there only where their ends
//! change order (where any drawing must cross them). The routes at one port leave it (or enter
//! it) side by side, as the layout fanned them out, so no two routes touch.

use std::collections::HashMap;

use super::Point;
use crate::layout::PORT_FAN_MOST;

/// How far a gap's tracks may reach into the bands of the ranks beside it: no further than the
/// room a box with ports on that side keeps beside their symbols. (A box without ports there
/// keeps none: where it is its band's widest, a track there would meet it, and the check
/// against the boxes leaves that route to the router around them.)
const INTO_BANDS: f64 = 24.0;
/// How far from its port's anchor the layout may have fanned a route's end.
pub(super) const FANNED: f64 = PORT_FAN_MOST / 2.0 + 0.5;
/// Between two tracks of a gap, where the gap has room.
const TRACK: f64 = 8.0;
/// Tracks whose heights come nearer than this take places of their own (else they share one).
const APART: f64 = TRACK / 2.0;
/// The closest two tracks may run, and the most tracks a gap orders (the order takes cubic
/// time): a gap beyond either is left to the router around the boxes.
const CLOSEST: f64 = 2.0;
const MOST_TRACKS: usize = 400;

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

/// A track of a gap: the height where its route comes to it from the left, and the height
/// where it leaves it to the right.
#[derive(Clone, Copy)]
struct Track {
    from: f64,
    to: f64,
}

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
            Some(straightened(route))
        })
        .collect()
}

/// The layout's route with its ends at the ports' anchors (at the heights the layout fanned
/// them out to); none where it does not leave its source's port rightwards and enter its
/// target's from the left.
fn skeleton(c: &Followed) -> Option<Vec<Point>> {
    let (first, last) = (*c.route.first()?, *c.route.last()?);
    let meets = |end: Point, port: Point| (end.y - port.y).abs() <= FANNED;
    if c.route.len() < 2 || !meets(first, c.from) || !meets(last, c.to) || first.x < c.from.x || last.x > c.to.x {
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

/// Where each track of a gap runs: left to right in the order that crosses fewest routes
/// (`order`), tracks whose heights overlap side by side, the others sharing a place; none
/// where the gap holds more than `MOST_TRACKS` or they would run closer than `CLOSEST`.
fn places((left, right): Gap, mut tracks: Vec<(Slant, Track)>) -> Option<Vec<(Slant, f64)>> {
    if tracks.len() > MOST_TRACKS {
        return None;
    }
    // A start independent of the connections' order: by the heights the tracks span and come from.
    tracks.sort_by(|&(_, a), &(_, b)| {
        let (a, b) = ((span(a), a.from), (span(b), b.from));
        a.0 .0.total_cmp(&b.0 .0).then(a.0 .1.total_cmp(&b.0 .1)).then(a.1.total_cmp(&b.1))
    });
    let spans: Vec<(f64, f64)> = tracks.iter().map(|&(_, t)| span(t)).collect();
    let overlap = |i: usize, j: usize| spans[j].0 <= spans[i].1 + APART && spans[i].0 <= spans[j].1 + APART;
    let order = order(&tracks.iter().map(|&(_, t)| t).collect::<Vec<_>>(), &overlap);
    let mut slot = vec![0usize; tracks.len()];
    for (n, &i) in order.iter().enumerate() {
        slot[i] = order[..n].iter().filter(|&&j| overlap(i, j)).map(|&j| slot[j] + 1).max().unwrap_or(0);
    }
    let count = slot.iter().max().map_or(1, |m| m + 1) as f64;
    let (from, to) = (left as f64 / SCALE - INTO_BANDS, right as f64 / SCALE + INTO_BANDS);
    let step = TRACK.min((to - from) / (count + 1.0));
    if step < CLOSEST {
        return None;
    }
    let middle = (from + to) / 2.0;
    let place = |slot: usize| middle + (slot as f64 - (count - 1.0) / 2.0) * step;
    Some(tracks.into_iter().zip(slot).map(|((slant, _), slot)| (slant, place(slot))).collect())
}

/// The tracks' order left to right: of two tracks side by side, the order that crosses fewer
/// routes (`crossings`), as far as these preferences agree (where they run in a circle, Eades,
/// Lin and Smyth's greedy order for a small feedback arc set decides).
fn order(tracks: &[Track], overlap: &dyn Fn(usize, usize) -> bool) -> Vec<usize> {
    let n = tracks.len();
    // weight[i][j] > 0: i left of j crosses that many routes fewer than j left of i.
    let mut weight = vec![vec![0i64; n]; n];
    for i in 0..n {
        for j in (i + 1)..n {
            if overlap(i, j) {
                let saved = crossings(tracks[j], tracks[i]) - crossings(tracks[i], tracks[j]);
                (weight[i][j], weight[j][i]) = (saved, -saved);
            }
        }
    }
    let (mut left, mut right) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut placed = vec![false; n];
    for _ in 0..n {
        let open: Vec<usize> = (0..n).filter(|&i| !placed[i]).collect();
        // Whether an open track wants to be left of `i` (sign 1) or right of it (sign -1).
        let wanted = |i: usize, sign: i64| open.iter().any(|&j| weight[j][i] * sign > 0);
        let outweighs = |i: usize| open.iter().map(|&j| weight[i][j]).sum::<i64>();
        let (pick, leftmost) = match open.iter().find(|&&i| !wanted(i, 1)) {
            Some(&i) => (i, true),
            None => match open.iter().find(|&&i| !wanted(i, -1)) {
                Some(&i) => (i, false),
                None => (open.iter().copied().max_by_key(|&i| (outweighs(i), std::cmp::Reverse(i))).unwrap_or(0), true),
            },
        };
        placed[pick] = true;
        if leftmost {
            left.push(pick)
        } else {
            right.push(pick)
        }
    }
    left.extend(right.into_iter().rev());
    left
}

/// How many times two routes cross when track `a` runs left of track `b`: `b`'s route coming
/// from the left across `a`, and `a`'s leaving to the right across `b`.
fn crossings(a: Track, b: Track) -> i64 {
    // A route meeting the other track's end height counts too: there they would touch.
    let inside = |y: f64, (top, bottom): (f64, f64)| top <= y && y <= bottom;
    i64::from(inside(b.from, span(a))) + i64::from(inside(a.to, span(b)))
}

/// The heights a track spans, top to bottom.
fn span(track: Track) -> (f64, f64) {
    (track.from.min(track.to), track.from.max(track.to))
}

/// A gap's side as a key: its x in hundredths.
const SCALE: f64 = 100.0;
fn key(x: f64) -> i64 {
    (x * SCALE).round() as i64
}

/// The route without repeated points and without points in the middle of a straight stretch
/// (nor where it would turn back on itself: a gap's track may lie a little inside a rank's band,
/// before the point where the layout's route left the band).
fn straightened(route: Vec<Point>) -> Vec<Point> {
    let mut out: Vec<Point> = Vec::with_capacity(route.len());
    for p in route {
        if out.last().is_some_and(|q| (q.x - p.x).abs() < 1e-9 && (q.y - p.y).abs() < 1e-9) {
            continue;
        }
        if let [.., a, b] = out[..] {
            let along_x = (a.y - b.y).abs() < 1e-9 && (b.y - p.y).abs() < 1e-9;
            let along_y = (a.x - b.x).abs() < 1e-9 && (b.x - p.x).abs() < 1e-9;
            if along_x || along_y {
                out.pop();
            }
        }
        out.push(p);
    }
    out
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
        // Fifty routes nested in one gap, each crossing all the others: 88 pt hold them only
        // 1.7 pt apart.
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
        // Every track lies in the gap, or no further than the room beside the bands' boxes.
        for route in &routes {
            assert!(route[1..route.len() - 1].iter().all(|q| (100.0 - INTO_BANDS..=140.0 + INTO_BANDS).contains(&q.x)));
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
