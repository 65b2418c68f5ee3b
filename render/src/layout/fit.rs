//! A drawing too wide for its page fitted to it (`plan`, `narrow`): Brandes–Köpf keeps long
//! edges upright, and where they stand side by side across many ranks the drawing grows several
//! times wider than its widest rank needs. Narrowed, the Brandes–Köpf drawing is squeezed into
//! the width the page's aspect ratio allows (never less than its widest rank needs), then each
//! vertex drawn towards its neighbours (dot's edge weights: long edges pulled straightest) while
//! every rank keeps its order and its gaps — so crossings stay as they were and no edge runs
//! through a box; long edges slant (`pass`).

use super::proper::Proper;
use super::{Extent, Spacing};

/// How many times each rank is drawn towards its neighbours, down and up.
const SWEEPS: usize = 8;

/// How strongly a vertex keeps its place in the squeezed Brandes–Köpf drawing.
const ANCHOR: f64 = 0.25;

/// The pull of an edge by what it joins (dot's Ω): two boxes 1, a box and a long edge's
/// dummy 2, two dummies 8.
fn pull(graph: &Proper, u: usize, v: usize) -> f64 {
    match (u >= graph.boxes, v >= graph.boxes) {
        (true, true) => 8.0,
        (false, false) => 1.0,
        _ => 2.0,
    }
}

/// How a drawing too wide for its page is fitted to it: the width it is narrowed to, and by how
/// much its rank gaps are stretched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Fit {
    /// From the left margin to the right one.
    pub width: f64,
    /// The factor (1 to `MOST_STRETCH`) the gaps between ranks grow by.
    pub stretch: f64,
}

/// The most the gaps between ranks are stretched.
const MOST_STRETCH: f64 = 3.0;

/// How to fit a drawing of `layers` whose vertices stand at `x` and which is `height` tall
/// (margins included) with `gaps` of that between its ranks, or none if it fits its page: it
/// does not where it is wider than the page and more than `TOLERANCE` times the page's
/// aspect ratio. It is narrowed as the aspect ratio asks, but no narrower than its widest
/// rank; if that is still wider than the aspect ratio asks, the gaps between the ranks grow
/// to make up the height (up to `MOST_STRETCH` times, and no more than it was narrowed): shown
/// on the page, the drawing is no smaller for it, and its slanting edges and its end labels
/// get room between the ranks.
pub(super) fn plan(
    layers: &[Vec<usize>],
    extent: &[Extent],
    x: &[f64],
    separation: &dyn Fn(usize, usize) -> f64,
    spacing: Spacing,
    (height, gaps): (f64, f64),
) -> Option<Fit> {
    let page = spacing.page;
    let width = super::place::right_edge(x, extent) - spacing.margin;
    let whole = width + 2.0 * spacing.margin;
    if !page.too_wide(whole, height) {
        return None;
    }
    let least = layers.iter().map(|layer| least_width(layer, extent, separation)).fold(0.0, f64::max);
    let aim = (page.aspect() * height - 2.0 * spacing.margin).max(least);
    let wanted_height = (aim + 2.0 * spacing.margin) / page.aspect();
    // Narrowed, long edges slant: the more, the more room between the ranks they get.
    let most = (width / aim).min(MOST_STRETCH);
    let stretch = if gaps > 0.0 { (1.0 + (wanted_height - height) / gaps).clamp(1.0, most) } else { 1.0 };
    (aim < width).then_some(Fit { width: aim, stretch })
}

/// Narrows `x` (centre per vertex, the drawing's left edge at `spacing.margin`) to `width`
/// (`Fit::width`).
pub(super) fn narrow(
    graph: &Proper,
    layers: &[Vec<usize>],
    extent: &[Extent],
    x: &mut [f64],
    separation: &dyn Fn(usize, usize) -> f64,
    spacing: Spacing,
    width: f64,
) {
    let drawn = super::place::right_edge(x, extent) - spacing.margin;
    let left = spacing.margin;
    let scale = width / drawn;
    let anchor: Vec<f64> = x.iter().map(|&at| left + (at - left) * scale).collect();
    let ranks = Ranks { extent, separation, left, right: left + width };
    x.copy_from_slice(&anchor);
    for layer in layers {
        let wanted: Vec<(f64, f64)> = layer.iter().map(|&v| (anchor[v], 1.0)).collect();
        ranks.settle(layer, x, &wanted);
    }
    for _ in 0..SWEEPS {
        for layer in layers.iter().chain(layers.iter().rev()) {
            let desired = |v: usize| {
                let (mut sum, mut weight) = (anchor[v] * ANCHOR, ANCHOR);
                for &u in graph.up[v].iter().chain(&graph.down[v]) {
                    let w = pull(graph, u, v);
                    sum += w * x[u];
                    weight += w;
                }
                (sum / weight, weight)
            };
            let wanted: Vec<(f64, f64)> = layer.iter().map(|&v| desired(v)).collect();
            ranks.settle(layer, x, &wanted);
        }
    }
}

/// Moves `x` back to where the vertices that were kept sat before (`seats`, per vertex): every
/// rank settled nearest to those places (the others, of little weight, where they are, moved
/// as the kept ones moved in the median), in order, with their gaps, right of `left`.
pub(super) fn keep(
    layers: &[Vec<usize>],
    extent: &[Extent],
    x: &mut [f64],
    separation: &dyn Fn(usize, usize) -> f64,
    left: f64,
    seats: &[Option<super::Seat>],
) {
    let mut moved: Vec<f64> = (0..x.len()).filter_map(|v| Some(seats[v]?.x? - x[v])).collect();
    if moved.is_empty() {
        return;
    }
    moved.sort_by(f64::total_cmp);
    let shift = moved[moved.len() / 2];
    let ranks = Ranks { extent, separation, left, right: f64::INFINITY };
    for layer in layers {
        let wanted: Vec<(f64, f64)> = layer
            .iter()
            .map(|&v| match seats[v].and_then(|s| s.x) {
                Some(at) => (at, 1.0),
                None => (x[v] + shift, 0.01),
            })
            .collect();
        // Where every vertex can be where it wants, it is there exactly (a layout from its own
        // rows is the same to the last bit).
        // (Within a rounding error: placement leaves gaps that are a bit short in the last bits.)
        let room = |i: usize| wanted[i + 1].0 - wanted[i].0 >= separation(layer[i], layer[i + 1]) - 1e-6;
        let fits = layer.first().is_none_or(|&v| wanted[0].0 >= left + extent[v].left - 1e-6)
            && (0..layer.len().saturating_sub(1)).all(room);
        match fits {
            true => layer.iter().zip(&wanted).for_each(|(&v, &(at, _))| x[v] = at),
            false => ranks.settle(layer, x, &wanted),
        }
    }
}

/// The least width of a rank: its end vertices' outer halves and the gaps between neighbours.
fn least_width(layer: &[usize], extent: &[Extent], separation: &dyn Fn(usize, usize) -> f64) -> f64 {
    let (Some(&first), Some(&last)) = (layer.first(), layer.last()) else { return 0.0 };
    extent[first].left + layer.windows(2).map(|pair| separation(pair[0], pair[1])).sum::<f64>() + extent[last].right
}

/// The vertices' room and the strip `left..right` every vertex must stay in.
struct Ranks<'a> {
    extent: &'a [Extent],
    separation: &'a dyn Fn(usize, usize) -> f64,
    left: f64,
    right: f64,
}

impl Ranks<'_> {
    /// Places the vertices of `layer` nearest to where they want to be (`wanted`, per vertex
    /// of it: a position and how much it matters, by least squares) keeping their order, their
    /// gaps and the strip.
    fn settle(&self, layer: &[usize], x: &mut [f64], wanted: &[(f64, f64)]) {
        let (Some(&first), Some(&last)) = (layer.first(), layer.last()) else { return };
        // Less each vertex's offset from the first (its gaps), the positions only need to be
        // in order: an isotonic regression, clipped to the strip.
        let mut offset = Vec::with_capacity(layer.len());
        let mut at = 0.0;
        for (i, &v) in layer.iter().enumerate() {
            if i > 0 {
                at += (self.separation)(layer[i - 1], v);
            }
            offset.push(at);
        }
        let lowest = self.left + self.extent[first].left;
        let highest = self.right - self.extent[last].right - at;
        let points: Vec<(f64, f64)> = wanted.iter().zip(&offset).map(|(&(p, w), o)| (p - o, w)).collect();
        for ((&v, o), y) in layer.iter().zip(&offset).zip(isotonic(&points)) {
            x[v] = y.clamp(lowest, highest.max(lowest)) + o;
        }
    }
}

/// The non-decreasing sequence nearest to `points` (value, weight) by weighted least squares
/// (pool adjacent violators).
pub(super) fn isotonic(points: &[(f64, f64)]) -> Vec<f64> {
    // Pools: (weighted mean, weight, how many points).
    let mut pools: Vec<(f64, f64, usize)> = Vec::with_capacity(points.len());
    for &(value, weight) in points {
        let mut pool = (value, weight.max(f64::MIN_POSITIVE), 1);
        while let Some(&(mean, w, count)) = pools.last() {
            if mean < pool.0 {
                break;
            }
            pools.pop();
            let total = w + pool.1;
            pool = ((mean * w + pool.0 * pool.1) / total, total, count + pool.2);
        }
        pools.push(pool);
    }
    pools.iter().flat_map(|&(mean, _, count)| std::iter::repeat_n(mean, count)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{segment_meets_box, Rect};
    use crate::layout::tests::pseudo_random_edges;
    use crate::layout::{layered, Layout, LayoutInput, LayoutNode, Page, Point};

    /// A class diagram's shape (as `tests/render/bench_dot.py` makes them): an inheritance
    /// forest over about 60 % of `n` boxes and `n / 2` associations between random boxes.
    fn class_like(n: usize) -> LayoutInput {
        let draws = pseudo_random_edges(3, n, n).into_iter().enumerate().skip(1);
        let parents = draws.filter(|&(_, (_, coin))| coin % 5 < 3).map(|(v, (p, _))| (p % v, v));
        let edges: Vec<(usize, usize)> =
            parents.chain(pseudo_random_edges(5, n, n / 2)).filter(|(a, b)| a != b).collect();
        LayoutInput {
            nodes: (0..n).map(|i| LayoutNode { width: 110.0 + (i % 4) as f64 * 15.0, height: 60.0 }).collect(),
            edges,
            ..Default::default()
        }
    }

    /// Proper crossings between the edges' segments (not at shared ends).
    fn crossings(layout: &Layout) -> usize {
        let segments: Vec<(usize, Point, Point)> = (layout.edges.iter().enumerate())
            .flat_map(|(e, route)| route.windows(2).map(move |s| (e, s[0], s[1])))
            .collect();
        let side = |a: Point, b: Point, c: Point| ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)).signum();
        let mut count = 0;
        for (i, &(e, a, b)) in segments.iter().enumerate() {
            for &(f, c, d) in &segments[i + 1..] {
                if e != f && side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0 {
                    count += 1;
                }
            }
        }
        count
    }

    #[test]
    fn a_drawing_too_wide_is_narrowed_to_the_page_keeping_its_crossings() {
        let input = class_like(300);
        let wide = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert!(wide.width / wide.height > 3.0, "{} x {}", wide.width, wide.height);
        let fitted = layered(&input, Spacing::default());
        let aspect = fitted.width / fitted.height;
        assert!(aspect < 1.6 * 1.5, "{} x {}", fitted.width, fitted.height);
        assert!(fitted.width < wide.width / 2.0, "{} wide, was {}", fitted.width, wide.width);
        // The ranks keep their orders: the edges cross as often (give or take where a box's
        // edges leave it side by side).
        let (before, after) = (crossings(&wide), crossings(&fitted));
        assert!(after.abs_diff(before) * 50 <= before, "{before} crossings, narrowed {after}");
        // No box overlaps another or sticks out; no edge runs through a box.
        let rect = |v: usize| {
            let (p, n) = (fitted.positions[v], &input.nodes[v]);
            Rect { x: p.x, y: p.y, width: n.width, height: n.height }
        };
        for v in 0..input.nodes.len() {
            let r = rect(v);
            assert!(r.x >= 0.0 && r.x + r.width <= fitted.width && r.y + r.height <= fitted.height);
            for u in v + 1..input.nodes.len() {
                let o = rect(u);
                assert!(r.x + r.width <= o.x || o.x + o.width <= r.x || r.y + r.height <= o.y || o.y + o.height <= r.y);
            }
            for (e, route) in fitted.edges.iter().enumerate() {
                let (a, b) = input.edges[e];
                if a != v && b != v {
                    assert!(!route.windows(2).any(|s| segment_meets_box(s[0], s[1], r)), "edge {e} through box {v}");
                }
            }
        }
    }

    #[test]
    fn a_drawing_that_fits_or_is_only_as_wide_as_its_widest_rank_is_not_narrowed() {
        let input = class_like(20);
        let unbounded = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert_eq!(layered(&input, Spacing::default()), unbounded);
        // One rank of 40 boxes: nothing to narrow, and no rank gaps to stretch.
        let row = LayoutInput { nodes: vec![LayoutNode { width: 100.0, height: 40.0 }; 40], ..Default::default() };
        let single = LayoutInput { edges: (1..40).map(|v| (0, v)).collect(), ..row };
        let wide = layered(&single, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        let on_screen = layered(&single, Spacing::default());
        assert!(on_screen.width >= wide.width / 2.0 - 100.0, "{} vs {}", on_screen.width, wide.width);
    }

    #[test]
    fn isotonic_pools_what_is_out_of_order_by_weight() {
        assert_eq!(isotonic(&[(1.0, 1.0), (2.0, 1.0), (3.0, 1.0)]), vec![1.0, 2.0, 3.0]);
        assert_eq!(isotonic(&[(3.0, 1.0), (1.0, 1.0), (2.0, 1.0)]), vec![2.0, 2.0, 2.0]);
        assert_eq!(isotonic(&[(0.0, 1.0), (4.0, 3.0), (0.0, 1.0), (5.0, 1.0)]), vec![0.0, 3.0, 3.0, 5.0]);
    }
}
