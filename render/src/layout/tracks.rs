//! The tracks of the gaps between ranks where connections that end at ports turn: which place
//! each slant's track takes in its gap (the order that crosses fewest routes, tracks whose
//! heights overlap side by side), and the room each gap needs for them. The layout sizes each
//! gap by it; the scene (`scene::channels`) runs the tracks there — one decision for both.

use super::place::Bands;
use super::proper::Proper;
use super::{Extent, Point};

/// Between two tracks of a gap, and between a gap's outer tracks and its sides.
pub(crate) const TRACK: f64 = 8.0;
/// Tracks whose heights come nearer than this take places of their own (else they share one).
const APART: f64 = TRACK / 2.0;
/// The most tracks a gap orders (the order takes cubic time): beyond, the gap's routes are left
/// to the scene's router around the boxes.
pub(crate) const MOST_TRACKS: usize = 400;

/// A track of a gap: the height where its route comes to it from the rank before, and the
/// height where it leaves it to the rank after.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Track {
    pub from: f64,
    pub to: f64,
}

/// Each track's place among the gap's places, counted from the rank before (tracks whose
/// heights do not overlap share one); independent of the tracks' order in `tracks`.
pub(crate) fn slots(tracks: &[Track]) -> Vec<usize> {
    // A start independent of the order given: by the heights the tracks span and come from.
    let mut sorted: Vec<usize> = (0..tracks.len()).collect();
    let key = |i: usize| (span(tracks[i]), tracks[i].from);
    sorted.sort_by(|&i, &j| {
        let (a, b) = (key(i), key(j));
        a.0 .0.total_cmp(&b.0 .0).then(a.0 .1.total_cmp(&b.0 .1)).then(a.1.total_cmp(&b.1))
    });
    let spans: Vec<(f64, f64)> = sorted.iter().map(|&i| span(tracks[i])).collect();
    let overlap = |i: usize, j: usize| spans[j].0 <= spans[i].1 + APART && spans[i].0 <= spans[j].1 + APART;
    let order = order(&sorted.iter().map(|&i| tracks[i]).collect::<Vec<_>>(), &overlap);
    let mut slot = vec![0usize; tracks.len()];
    for (n, &i) in order.iter().enumerate() {
        let below = order[..n].iter().filter(|&&j| overlap(i, j)).map(|&j| slot[sorted[j]] + 1).max();
        slot[sorted[i]] = below.unwrap_or(0);
    }
    slot
}

/// The room each gap between `bands` needs for the tracks of the edges that end at ports at
/// both ends (`ports`, per edge of `edges`) and run down the ranks, as the layout routes them
/// (`route::polylines`): a track's width either side of every place (none where no route slants
/// there, where more than `MOST_TRACKS` would, those go to the router, and without ports).
pub(super) fn room(
    graph: &Proper,
    edges: &[(usize, usize, bool)],
    layers: &[Vec<usize>],
    (x, bands, extent): (&[f64], &Bands, &[Extent]),
    ports: &[[Option<f64>; 2]],
) -> Vec<f64> {
    if ports.is_empty() {
        return Vec::new();
    }
    let routes = super::route::polylines(graph, edges, layers, (x, bands, extent), ports);
    let ported = |e: usize| !edges[e].2 && ports.get(e).is_some_and(|ends| ends.iter().all(Option::is_some));
    gap_room(&routes, &ported, bands)
}

/// The room each gap between `bands` needs for the tracks of `routes` (those `ported`).
fn gap_room(routes: &[Vec<Point>], ported: &dyn Fn(usize) -> bool, bands: &Bands) -> Vec<f64> {
    let ranks = bands.top.len();
    let mut gaps: Vec<Vec<Track>> = vec![Vec::new(); ranks.saturating_sub(1)];
    for (_, route) in routes.iter().enumerate().filter(|&(e, _)| ported(e)) {
        for pair in route.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let slants = (a.x - b.x).abs() >= 1e-6 && a.y < b.y;
            let rank = bands.top.partition_point(|&top| top <= a.y).saturating_sub(1);
            if slants && rank + 1 < ranks {
                gaps[rank].push(Track { from: a.x, to: b.x });
            }
        }
    }
    let room = |tracks: &Vec<Track>| {
        let places = match tracks.len() {
            0 => 0,
            n if n > MOST_TRACKS => 0,
            _ => slots(tracks).into_iter().max().map_or(0, |m| m + 1),
        };
        if places == 0 {
            0.0
        } else {
            (places + 1) as f64 * TRACK
        }
    };
    gaps.iter().map(room).collect()
}

/// The tracks' order from the rank before: of two tracks side by side, the order that crosses
/// fewer routes (`crossings`), as far as these preferences agree (where they run in a circle,
/// Eades, Lin and Smyth's greedy order for a small feedback arc set decides).
fn order(tracks: &[Track], overlap: &dyn Fn(usize, usize) -> bool) -> Vec<usize> {
    let n = tracks.len();
    // weight[i][j] > 0: i before j crosses that many routes fewer than j before i.
    let mut weight = vec![vec![0i64; n]; n];
    for i in 0..n {
        for j in (i + 1)..n {
            if overlap(i, j) {
                let saved = crossings(tracks[j], tracks[i]) - crossings(tracks[i], tracks[j]);
                (weight[i][j], weight[j][i]) = (saved, -saved);
            }
        }
    }
    let (mut first, mut last) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut placed = vec![false; n];
    for _ in 0..n {
        let open: Vec<usize> = (0..n).filter(|&i| !placed[i]).collect();
        // Whether an open track wants to be before `i` (sign 1) or after it (sign -1).
        let wanted = |i: usize, sign: i64| open.iter().any(|&j| weight[j][i] * sign > 0);
        let outweighs = |i: usize| open.iter().map(|&j| weight[i][j]).sum::<i64>();
        let (pick, at_first) = match open.iter().find(|&&i| !wanted(i, 1)) {
            Some(&i) => (i, true),
            None => match open.iter().find(|&&i| !wanted(i, -1)) {
                Some(&i) => (i, false),
                None => (open.iter().copied().max_by_key(|&i| (outweighs(i), std::cmp::Reverse(i))).unwrap_or(0), true),
            },
        };
        placed[pick] = true;
        if at_first {
            first.push(pick)
        } else {
            last.push(pick)
        }
    }
    first.extend(last.into_iter().rev());
    first
}

/// How many times two routes cross when track `a` runs before track `b`: `b`'s route coming
/// from the rank before across `a`, and `a`'s leaving to the rank after across `b`.
fn crossings(a: Track, b: Track) -> i64 {
    // A route meeting the other track's end height counts too: there they would touch.
    let inside = |y: f64, (top, bottom): (f64, f64)| top <= y && y <= bottom;
    i64::from(inside(b.from, span(a))) + i64::from(inside(a.to, span(b)))
}

/// The heights a track spans, least first.
fn span(track: Track) -> (f64, f64) {
    (track.from.min(track.to), track.from.max(track.to))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(x: f64, y: f64) -> Point {
        Point { x, y }
    }

    #[test]
    fn a_gap_is_given_a_track_s_width_around_each_of_its_places() {
        // Two ranks, bands 0..20 and 60..80; routes down from the first to the second.
        let bands = Bands { top: vec![0.0, 60.0], height: vec![20.0; 2], total_height: 80.0 };
        let down = |from: f64, to: f64| vec![p(from, 10.0), p(from, 20.0), p(to, 60.0), p(to, 70.0)];
        let all = |_: usize| true;
        // Straight down: no track.
        assert_eq!(gap_room(&[down(0.0, 0.0)], &all, &bands), [0.0]);
        // Two whose ends change order: side by side, three tracks' widths.
        let crossing = [down(0.0, 50.0), down(40.0, 10.0)];
        assert_eq!(gap_room(&crossing, &all, &bands), [3.0 * TRACK]);
        // Far apart in height they share a place; a route not ending at ports takes none.
        assert_eq!(gap_room(&[down(0.0, 10.0), down(40.0, 50.0)], &all, &bands), [2.0 * TRACK]);
        assert_eq!(gap_room(&crossing, &|e| e == 0, &bands), [2.0 * TRACK]);
    }

    #[test]
    fn a_track_s_place_does_not_depend_on_the_order_the_tracks_come_in() {
        let tracks: Vec<Track> =
            (0..12).map(|i| Track { from: (i * 7 % 12) as f64 * 10.0, to: (i * 5 % 12) as f64 * 10.0 }).collect();
        let slot = slots(&tracks);
        let reversed: Vec<Track> = tracks.iter().rev().copied().collect();
        let slot_reversed: Vec<usize> = slots(&reversed).into_iter().rev().collect();
        assert_eq!(slot, slot_reversed);
        assert!(slot.iter().any(|&s| s > 0));
    }
}
