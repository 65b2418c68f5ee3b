//! Edge polylines: each edge leaves its source straight down to the bottom of the source's rank
//! band, runs through its dummies, and enters its target straight from the top of the target's
//! band (so no edge cuts through a taller neighbour of the same rank); edges that share a box side
//! attach at their own points along it (or at their ports' places, where the input gives them).
//! A long edge passes each rank's band where `pass` puts it, or straight at its place in the
//! rank where the edges end at ports (for the scene's orthogonal router).

use std::collections::HashMap;

use super::pass::Passes;
use super::place::Bands;
use super::proper::Proper;
use super::{Extent, Point};

/// One polyline per oriented edge, in the input's direction, starting and ending on the boxes'
/// borders; `ports`: per input edge (or none), where its ends meet their boxes.
pub(super) fn polylines(
    graph: &Proper,
    edges: &[(usize, usize, bool)],
    layers: &[Vec<usize>],
    (x, bands, extent): (&[f64], &Bands, &[Extent]),
    ports: &[[Option<f64>; 2]],
) -> Vec<Vec<Point>> {
    let centre = |v: usize| Point { x: x[v], y: bands.middle(graph.rank[v]) };
    let pass = if ports.is_empty() {
        Passes::new(graph, layers, x, bands, extent)
    } else {
        Passes { top: x.to_vec(), bottom: x.to_vec() }
    };
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
    at_ports(&mut routed, graph, edges, (x, extent), ports);
    for (route, &(_, _, reversed)) in routed.iter_mut().zip(edges) {
        if reversed {
            route.reverse();
        }
        route.dedup_by(|a, b| (a.x - b.x).abs() < 1e-9 && (a.y - b.y).abs() < 1e-9);
    }
    routed
}

/// Between the ends of edges that meet one port: each leaves (or enters) it on a line of its
/// own, side by side in the order of where they run to, so that they neither touch nor cross.
const PORT_FAN: f64 = 3.0;
/// The most room the ends at one port take along its side.
pub(crate) const PORT_FAN_MOST: f64 = 9.0;

/// Moves the ends of edges that meet ports to the ports' places along their boxes' sides
/// (with their stubs), the ends at one port fanned out around its place. An edge laid out
/// reversed ends on the other sides of its boxes than its ports: it keeps its spread ends.
fn at_ports(
    routed: &mut [Vec<Point>],
    graph: &Proper,
    edges: &[(usize, usize, bool)],
    (x, extent): (&[f64], &[Extent]),
    ports: &[[Option<f64>; 2]],
) {
    // A port: its box, whether it holds edges' first ends, its place in hundredths.
    type Port = (usize, bool, i64);
    // Per port, its exact place and its ends: (edge, next vertex's x, the other end's port place).
    type Ends = (f64, Vec<(usize, f64, f64)>);
    let mut at: HashMap<Port, Ends> = HashMap::new();
    for (e, (chain, (&(_, _, reversed), ends))) in graph.chains.iter().zip(edges.iter().zip(ports)).enumerate() {
        let (first, last) = (chain[0], chain[chain.len() - 1]);
        if reversed || first == last || routed[e].len() < 4 {
            continue;
        }
        let mut meet = |v: usize, is_first: bool, offset: f64, next: usize, other: Option<f64>| {
            let port = (v, is_first, (offset * 100.0).round() as i64);
            at.entry(port).or_insert((offset, Vec::new())).1.push((e, x[next], other.unwrap_or(0.0)));
        };
        if let Some(offset) = ends[0] {
            meet(first, true, offset, chain[1], ends[1]);
        }
        if let Some(offset) = ends[1] {
            meet(last, false, offset, chain[chain.len() - 2], ends[0]);
        }
    }
    for ((v, is_first, _), (offset, mut ends)) in at {
        // Two ends running to one box (its ports, next rank): in the order of those ports.
        ends.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.2.total_cmp(&b.2)).then(a.0.cmp(&b.0)));
        let step = if ends.len() > 1 { PORT_FAN.min(PORT_FAN_MOST / (ends.len() - 1) as f64) } else { 0.0 };
        let middle = (ends.len() - 1) as f64 / 2.0;
        for (i, &(e, _, _)) in ends.iter().enumerate() {
            let along = x[v] - extent[v].left + offset + (i as f64 - middle) * step;
            let route = &mut routed[e];
            let n = route.len();
            let (end, stub) = if is_first { (0, 1) } else { (n - 1, n - 2) };
            (route[end].x, route[stub].x) = (along, along);
        }
    }
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
