//! Where long edges cross the ranks they pass: a long edge slanting from rank to rank keeps its
//! slant through each rank's band instead of standing upright in it (one straight line, not a
//! zigzag), as far as the band allows — at each of the band's top and bottom, the edges passing
//! keep their order and a small gap, and stay clear of the boxes and labels beside them. So no
//! edge meets a box and crossings stay as they were.

use super::fit::isotonic;
use super::place::Bands;
use super::proper::Proper;
use super::{Extent, Point};

/// Between two edges passing a band, at its top and at its bottom.
const EDGE_GAP: f64 = 6.0;

/// Between an edge passing a band and a box (or label) beside it.
const BOX_GAP: f64 = 8.0;

/// Per vertex, the x where its edge enters its band (at the top) and leaves it (at the
/// bottom): for a long edge's dummy that has no label beside it, on the line through its centre
/// from the vertex before and to the vertex after, as near as the band allows; for any other
/// vertex, its centre's.
pub(super) struct Passes {
    pub top: Vec<f64>,
    pub bottom: Vec<f64>,
}

impl Passes {
    pub(super) fn new(graph: &Proper, layers: &[Vec<usize>], x: &[f64], bands: &Bands, extent: &[Extent]) -> Passes {
        let plain = |v: usize| v >= graph.boxes && extent[v].left == 0.0 && extent[v].right == 0.0;
        let (mut top, mut bottom) = (x.to_vec(), x.to_vec());
        let centre = |v: usize| Point { x: x[v], y: bands.middle(graph.rank[v]) };
        let band = |v: usize| (bands.top[graph.rank[v]], bands.top[graph.rank[v]] + bands.height[graph.rank[v]]);
        for chain in graph.chains.iter().filter(|chain| chain.len() > 2) {
            let last = chain.len() - 1;
            for i in (1..last).filter(|&i| plain(chain[i])) {
                let v = chain[i];
                let before = if i == 1 { Point { x: x[chain[0]], y: band(chain[0]).1 } } else { centre(chain[i - 1]) };
                let after = if i + 1 == last {
                    Point { x: x[chain[last]], y: band(chain[last]).0 }
                } else {
                    centre(chain[i + 1])
                };
                let (upper, lower) = band(v);
                top[v] = on_line(centre(v), before, upper);
                bottom[v] = on_line(centre(v), after, lower);
            }
        }
        for layer in layers {
            settle(layer, &mut top, x, extent, &plain);
            settle(layer, &mut bottom, x, extent, &plain);
        }
        Passes { top, bottom }
    }
}

/// The x where the line through `a` and `b` meets the height `y` (`a`'s x on a level line).
fn on_line(a: Point, b: Point, y: f64) -> f64 {
    if (a.y - b.y).abs() < 1e-9 {
        a.x
    } else {
        a.x + (b.x - a.x) * (y - a.y) / (b.y - a.y)
    }
}

/// Moves the wanted x of each run of plain dummies in `layer` (between two other vertices)
/// as little as keeps them in order, `EDGE_GAP` apart and `BOX_GAP` clear of the vertices that
/// end the run. The dummies' own centres meet all that, so there is always room.
fn settle(layer: &[usize], want: &mut [f64], x: &[f64], extent: &[Extent], plain: &dyn Fn(usize) -> bool) {
    let mut start = 0;
    while start < layer.len() {
        if !plain(layer[start]) {
            start += 1;
            continue;
        }
        let end = (start..layer.len()).find(|&i| !plain(layer[i])).unwrap_or(layer.len());
        let lowest = start.checked_sub(1).map_or(f64::NEG_INFINITY, |i| x[layer[i]] + extent[layer[i]].right + BOX_GAP);
        let highest = layer.get(end).map_or(f64::INFINITY, |&u| x[u] - extent[u].left - BOX_GAP);
        let run = &layer[start..end];
        let span = EDGE_GAP * (run.len() - 1) as f64;
        let points: Vec<(f64, f64)> =
            run.iter().enumerate().map(|(k, &v)| (want[v] - EDGE_GAP * k as f64, 1.0)).collect();
        for (k, (&v, at)) in run.iter().zip(isotonic(&points)).enumerate() {
            want[v] = at.min(highest - span).max(lowest) + EDGE_GAP * k as f64;
        }
        start = end;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{LayoutNode, Spacing};

    /// A long edge from box 0 (rank 0) to box 1 (rank 4), and box 2 in rank 2 standing at `beside`.
    fn long_edge_past_a_box(beside: f64) -> (Proper, Vec<Vec<usize>>, Vec<f64>, Bands, Vec<Extent>) {
        let graph = Proper::new(&[], &[(0, 1, false)], &[0, 4, 2]);
        let nodes = [
            LayoutNode { width: 100.0, height: 40.0 },
            LayoutNode { width: 100.0, height: 40.0 },
            LayoutNode { width: 100.0, height: 80.0 },
        ];
        let extent = Extent::of_boxes(&nodes, graph.vertices());
        let mut layers = vec![Vec::new(); 5];
        for v in 0..graph.vertices() {
            layers[graph.rank[v]].push(v);
        }
        layers[2].sort_by_key(|&v| v == 2);
        let bands = Bands::new(&layers, &extent, Spacing::default(), &[]);
        // The edge's vertices on one straight line from (0, middle of rank 0) to (400, middle of rank 4).
        let (y0, y4) = (bands.middle(0), bands.middle(4));
        let mut x: Vec<f64> =
            (0..graph.vertices()).map(|v| 400.0 * (bands.middle(graph.rank[v]) - y0) / (y4 - y0)).collect();
        x[2] = beside;
        (graph, layers, x, bands, extent)
    }

    #[test]
    fn a_slanting_long_edge_passes_a_band_on_its_line() {
        let (graph, layers, x, bands, extent) = long_edge_past_a_box(1000.0);
        let pass = Passes::new(&graph, &layers, &x, &bands, &extent);
        let dummy = layers[2][0];
        let (c, top, bottom) = (x[dummy], bands.top[2], bands.top[2] + bands.height[2]);
        let slope = 400.0 / (bands.middle(4) - bands.middle(0));
        assert!((pass.top[dummy] - (c - slope * (bands.middle(2) - top))).abs() < 1e-6);
        assert!((pass.bottom[dummy] - (c + slope * (bottom - bands.middle(2)))).abs() < 1e-6);
        // The boxes' own x stay.
        assert_eq!((pass.top[2], pass.bottom[2]), (1000.0, 1000.0));
    }

    #[test]
    fn a_long_edge_keeps_clear_of_a_box_beside_it() {
        let (graph, layers, x, bands, extent) = long_edge_past_a_box(0.0);
        let dummy = layers[2][0];
        // The box stands just right of the edge's line (the layout's gap from it).
        let mut x = x;
        x[2] = x[dummy] + 20.0 + 50.0;
        let pass = Passes::new(&graph, &layers, &x, &bands, &extent);
        let box_left = x[2] - 50.0;
        assert!(pass.bottom[dummy] <= box_left - BOX_GAP + 1e-9, "{} vs {box_left}", pass.bottom[dummy]);
        assert!(pass.top[dummy] < x[dummy], "above the middle the line runs left of the centre");
    }
}
