//! Edge polylines: each edge leaves its source straight down to the bottom of the source's rank
//! band, runs through its dummies, and enters its target straight from the top of the target's
//! band (so no edge cuts through a taller neighbour of the same rank); edges that share a box side
//! attach at their own points along it. A long edge passes each rank's band where `pass` puts it.

use std::collections::HashMap;

use super::pass::Passes;
use super::place::Bands;
use super::proper::Proper;
use super::{Extent, Point};

/// One polyline per oriented edge, in the input's direction, starting and ending on the boxes'
/// borders.
pub(super) fn polylines(
    graph: &Proper,
    edges: &[(usize, usize, bool)],
    layers: &[Vec<usize>],
    x: &[f64],
    bands: &Bands,
    extent: &[Extent],
) -> Vec<Vec<Point>> {
    let centre = |v: usize| Point { x: x[v], y: bands.middle(graph.rank[v]) };
    let pass = Passes::new(graph, layers, x, bands, extent);
    let mut routed: Vec<Vec<Point>> = graph
        .chains
        .iter()
        .map(|chain| {
            if chain[0] == chain[chain.len() - 1] {
                let (c, e) = (centre(chain[0]), extent[chain[0]]);
                return self_loop(c.x + e.right, c.y, e.height);
            }
            let mut route = Vec::with_capacity(chain.len() * 2);
            let last = chain.len() - 1;
            for (i, &v) in chain.iter().enumerate() {
                let (c, h, r) = (centre(v), extent[v].height, graph.rank[v]);
                let (top, bottom) = (bands.top[r], bands.top[r] + bands.height[r]);
                if i == 0 {
                    route.push(Point { x: c.x, y: c.y + h / 2.0 });
                    route.push(Point { x: c.x, y: bottom });
                } else if i == last {
                    route.push(Point { x: c.x, y: top });
                    route.push(Point { x: c.x, y: c.y - h / 2.0 });
                } else {
                    route.push(Point { x: pass.top[v], y: top });
                    route.push(Point { x: pass.bottom[v], y: bottom });
                }
            }
            route
        })
        .collect();
    spread_attachments(&mut routed, graph, x, extent);
    for (route, &(_, _, reversed)) in routed.iter_mut().zip(edges) {
        if reversed {
            route.reverse();
        }
        route.dedup_by(|a, b| (a.x - b.x).abs() < 1e-9 && (a.y - b.y).abs() < 1e-9);
    }
    routed
}

/// A small loop on the right side of a box (its right border at `right`, its middle at
/// `middle`, `height` tall).
pub(crate) fn self_loop(right: f64, middle: f64, height: f64) -> Vec<Point> {
    vec![
        Point { x: right, y: middle - height / 4.0 },
        Point { x: right + 20.0, y: middle - height / 4.0 },
        Point { x: right + 20.0, y: middle + height / 4.0 },
        Point { x: right, y: middle + height / 4.0 },
    ]
}

/// Edges that leave (or enter) one side of a box get their own points along that side, in the
/// order of the vertices they run to in the neighbouring rank (so spreading adds no crossing),
/// instead of all sharing the side's centre. Routes still run from source to target here.
fn spread_attachments(routed: &mut [Vec<Point>], graph: &Proper, x: &[f64], extent: &[Extent]) {
    // (box, side is bottom) -> [(edge index, end is the route's first point, next vertex's x)]
    type Ends = Vec<(usize, bool, f64)>;
    let mut sides: HashMap<(usize, bool), Ends> = HashMap::new();
    for (e, chain) in graph.chains.iter().enumerate() {
        let last = chain.len() - 1;
        if chain[0] == chain[last] {
            continue;
        }
        sides.entry((chain[0], true)).or_default().push((e, true, x[chain[1]]));
        sides.entry((chain[last], false)).or_default().push((e, false, x[chain[last - 1]]));
    }
    let mut keys: Vec<(usize, bool)> = sides.keys().copied().collect();
    keys.sort_unstable();
    for key in keys {
        let mut ends = sides.remove(&key).unwrap_or_default();
        if ends.len() < 2 {
            continue;
        }
        ends.sort_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)));
        let w = (extent[key.0].left + extent[key.0].right) * 0.6;
        let count = ends.len() as f64;
        for (i, &(e, is_first, _)) in ends.iter().enumerate() {
            let route = &mut routed[e];
            let at = x[key.0] - w / 2.0 + w * (i as f64 + 0.5) / count;
            // Move the end point and its vertical stub together.
            let len = route.len();
            let (end, stub) = if is_first { (0, 1) } else { (len - 1, len - 2) };
            route[end].x = at;
            route[stub].x = at;
        }
    }
}
