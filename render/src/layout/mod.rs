//! Layered (Sugiyama-style) layout of a directed graph of boxes, top to bottom: cycle breaking
//! and longest-path ranks (`rank`), dummy vertices for long edges (`proper`), crossing
//! minimisation (`order`, `sifting`), coordinates (`place`, `align`) and edge polylines
//! (`route`). Edge labels take room in the layout as dot's do: with labels, ranks are doubled
//! and each labelled edge's label sits beside a dummy in a rank between its boxes' ranks.
//! Deterministic: the same input gives the same output.

mod align;
mod order;
mod place;
mod proper;
mod rank;
mod route;
mod sifting;

pub(crate) use route::self_loop;

use order::Order;
use proper::Proper;
use sifting::GlobalOrder;

/// A box to place.
#[derive(Debug, Clone, PartialEq)]
pub struct LayoutNode {
    pub width: f64,
    pub height: f64,
}

/// The input: boxes and directed edges between them (by index), optionally a group (swimlane)
/// per box (groups are laid out as side-by-side columns, in group order) and the size
/// (width, height) of a label per edge.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LayoutInput {
    pub nodes: Vec<LayoutNode>,
    pub edges: Vec<(usize, usize)>,
    pub groups: Vec<Option<usize>>,
    pub labels: Vec<Option<(f64, f64)>>,
}

/// Spacing of the layout.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    /// Between boxes of one rank.
    pub node_gap: f64,
    /// Between ranks.
    pub rank_gap: f64,
    /// Around the drawing.
    pub margin: f64,
}

impl Default for Spacing {
    fn default() -> Self {
        Spacing { node_gap: 40.0, rank_gap: 60.0, margin: 20.0 }
    }
}

/// A point.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Point {
    pub x: f64,
    pub y: f64,
}

/// The result: each box's top-left corner, each edge's polyline (first and last points on the
/// boxes' borders), the top-left corner of each edge's label where the layout placed it (not
/// for self loops), and the drawing's size.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub positions: Vec<Point>,
    pub edges: Vec<Vec<Point>>,
    pub labels: Vec<Option<Point>>,
    pub width: f64,
    pub height: f64,
}

impl Layout {
    /// Moves the whole drawing right and down (its size grows by as much).
    pub fn translate(&mut self, dx: f64, dy: f64) {
        let shift = |p: &mut Point| {
            p.x += dx;
            p.y += dy;
        };
        self.positions.iter_mut().for_each(shift);
        self.edges.iter_mut().flatten().for_each(shift);
        self.labels.iter_mut().flatten().for_each(shift);
        self.width += dx;
        self.height += dy;
    }
}

/// Lays out `input` left to right: the layered layout of the boxes turned on their side, turned
/// back. Labels take no room in it (they are placed afterwards).
pub fn layered_left_to_right(input: &LayoutInput, spacing: Spacing) -> Layout {
    let across = LayoutInput {
        nodes: input.nodes.iter().map(|n| LayoutNode { width: n.height, height: n.width }).collect(),
        edges: input.edges.clone(),
        groups: input.groups.clone(),
        labels: vec![None; input.edges.len()],
    };
    let mut layout = layered(&across, spacing);
    let turn = |p: &mut Point| std::mem::swap(&mut p.x, &mut p.y);
    layout.positions.iter_mut().for_each(turn);
    layout.edges.iter_mut().flatten().for_each(turn);
    layout.labels.iter_mut().for_each(|l| *l = None);
    std::mem::swap(&mut layout.width, &mut layout.height);
    layout
}

/// Space between an edge and its label.
const LABEL_OFFSET: f64 = 4.0;

/// How much room a vertex takes left and right of its centre line, and its height.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Extent {
    pub left: f64,
    pub right: f64,
    pub height: f64,
}

/// Lays out `input` top to bottom.
pub fn layered(input: &LayoutInput, spacing: Spacing) -> Layout {
    let n = input.nodes.len();
    if n == 0 {
        let empty = 2.0 * spacing.margin;
        return Layout { positions: Vec::new(), edges: Vec::new(), labels: Vec::new(), width: empty, height: empty };
    }
    let label_of = |e: usize| input.labels.get(e).copied().flatten();
    let labelled = (0..input.edges.len()).any(|e| label_of(e).is_some());
    let edges = rank::orient(n, &input.edges);
    let mut rank = rank::longest_path(n, &edges);
    if labelled {
        rank.iter_mut().for_each(|r| *r *= 2);
    }
    let graph = proper::Proper::new(&input.groups, &edges, &rank);
    let mut extent: Vec<Extent> = input
        .nodes
        .iter()
        .map(|node| Extent { left: node.width / 2.0, right: node.width / 2.0, height: node.height })
        .collect();
    extent.resize(graph.vertices(), Extent::default());
    // A labelled edge's label goes right of the dummy nearest its middle in a between-rank.
    let label_vertex: Vec<Option<usize>> = (0..edges.len())
        .map(|e| {
            let (width, height) = label_of(e)?;
            let chain = &graph.chains[e];
            let middle = chain.len() / 2;
            let at = if middle % 2 == 1 { middle } else { middle - 1 };
            let dummy = *chain.get(at).filter(|_| chain.len() > 2)?;
            extent[dummy] = Extent { left: 0.0, right: LABEL_OFFSET + width, height };
            Some(dummy)
        })
        .collect();
    let mut layers = graph.initial_layers();
    minimise_crossings(&mut layers, &graph);
    let x = place::horizontal(&graph, &layers, &extent, spacing);
    let rank_gap = if labelled { spacing.rank_gap / 2.0 } else { spacing.rank_gap };
    let bands = place::Bands::new(&layers, &extent, Spacing { rank_gap, ..spacing });
    let positions: Vec<Point> = (0..n)
        .map(|v| Point { x: x[v] - input.nodes[v].width / 2.0, y: bands.middle(rank[v]) - input.nodes[v].height / 2.0 })
        .collect();
    let labels = label_vertex
        .iter()
        .map(|v| v.map(|d| Point { x: x[d] + LABEL_OFFSET, y: bands.middle(graph.rank[d]) - extent[d].height / 2.0 }))
        .collect();
    let routed = route::polylines(&graph, &edges, &x, &bands, &extent);
    let width = (0..graph.vertices()).map(|v| x[v] + extent[v].right).fold(0.0, f64::max) + spacing.margin;
    Layout { positions, edges: routed, labels, width, height: bands.total_height }
}

/// Reorders every rank of `layers` to reduce crossings: barycentre sweeps with transposition
/// from a breadth-first start, then global sifting of whole blocks; the order with the fewest
/// crossings wins.
fn minimise_crossings(layers: &mut [Vec<usize>], graph: &Proper) {
    for layer in layers.iter_mut() {
        layer.sort_by_key(|&v| graph.group[v]);
    }
    let mut order = Order::new(layers.to_vec(), graph.vertices());
    let mut best = order.layers.clone();
    let mut best_crossings = order.crossings(graph);
    // Barycentre sweeps, alternately down and up, each followed by transposition; stop once a
    // few sweeps in a row bring nothing.
    let mut fruitless = 0;
    for sweep in 0..24 {
        if best_crossings == 0 || fruitless == 3 {
            break;
        }
        order.barycentre_sweep(graph, sweep % 2 == 0);
        order.transpose(graph);
        let crossings = order.crossings(graph);
        if crossings < best_crossings {
            best_crossings = crossings;
            best.clone_from(&order.layers);
            fruitless = 0;
        } else {
            fruitless += 1;
        }
    }
    // Global sifting from there: long edges move as a whole, which sweeps cannot do.
    if best_crossings > 0 {
        let mut sifted = GlobalOrder::new(&Order::new(best.clone(), graph.vertices()), graph);
        let mut crossings = sifted.order.crossings(graph);
        for _ in 0..12 {
            sifted.sift_all(graph);
            let now = sifted.order.crossings(graph);
            if now >= crossings {
                break;
            }
            crossings = now;
        }
        let mut order = sifted.order;
        order.transpose(graph);
        if order.crossings(graph) < best_crossings {
            best = order.layers;
        }
    }
    layers.clone_from_slice(&best);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn boxes(n: usize) -> Vec<LayoutNode> {
        (0..n)
            .map(|i| LayoutNode { width: 60.0 + (i % 3) as f64 * 20.0, height: 30.0 + (i % 2) as f64 * 10.0 })
            .collect()
    }

    fn overlaps(layout: &Layout, input: &LayoutInput) -> bool {
        for a in 0..input.nodes.len() {
            for b in a + 1..input.nodes.len() {
                let (pa, pb) = (layout.positions[a], layout.positions[b]);
                let (na, nb) = (&input.nodes[a], &input.nodes[b]);
                if pa.x < pb.x + nb.width
                    && pb.x < pa.x + na.width
                    && pa.y < pb.y + nb.height
                    && pb.y < pa.y + na.height
                {
                    return true;
                }
            }
        }
        false
    }

    fn on_border(p: Point, at: Point, node: &LayoutNode) -> bool {
        let eps = 1e-6;
        let inside_x = p.x >= at.x - eps && p.x <= at.x + node.width + eps;
        let inside_y = p.y >= at.y - eps && p.y <= at.y + node.height + eps;
        let on_vertical = (p.x - at.x).abs() < eps || (p.x - at.x - node.width).abs() < eps;
        let on_horizontal = (p.y - at.y).abs() < eps || (p.y - at.y - node.height).abs() < eps;
        inside_x && inside_y && (on_vertical || on_horizontal)
    }

    #[test]
    fn tree_lays_out_without_overlaps_or_crossings() {
        let input = LayoutInput {
            nodes: boxes(7),
            edges: vec![(0, 1), (0, 2), (1, 3), (1, 4), (2, 5), (2, 6)],
            ..Default::default()
        };
        let layout = layered(&input, Spacing::default());
        assert!(!overlaps(&layout, &input));
        // Ranks go downwards.
        assert!(layout.positions[1].y > layout.positions[0].y && layout.positions[3].y > layout.positions[1].y);
        // Edges start and end on their boxes' borders.
        for (edge, route) in input.edges.iter().zip(&layout.edges) {
            assert!(on_border(route[0], layout.positions[edge.0], &input.nodes[edge.0]));
            assert!(on_border(*route.last().unwrap(), layout.positions[edge.1], &input.nodes[edge.1]));
        }
    }

    #[test]
    fn cycles_long_edges_and_self_loops() {
        // A loop back (3 -> 1), a long edge (0 -> 3) and a self loop (2 -> 2).
        let input = LayoutInput {
            nodes: boxes(5),
            edges: vec![(0, 1), (1, 2), (2, 3), (3, 1), (0, 3), (2, 2), (3, 4)],
            ..Default::default()
        };
        let layout = layered(&input, Spacing::default());
        assert!(!overlaps(&layout, &input));
        assert_eq!(layout.edges.len(), input.edges.len());
        // The long edge bends through a dummy: more than two points.
        assert!(layout.edges[4].len() > 2);
        // The back edge still points from 3 to 1.
        let back = &layout.edges[3];
        assert!(back[0].y > back.last().unwrap().y);
        assert!(layout.width > 0.0 && layout.height > 0.0);
    }

    #[test]
    fn ordering_removes_avoidable_crossings() {
        // K2,2 minus nothing crosses unless ordered well: 0->3, 1->2 with initial order 0,1 / 2,3.
        let input = LayoutInput { nodes: boxes(4), edges: vec![(0, 3), (1, 2)], ..Default::default() };
        let layout = layered(&input, Spacing::default());
        let (a, b) = (&layout.edges[0], &layout.edges[1]);
        // Straight, non-crossing: the source left of the other is also the target left of it.
        let left_source = a[0].x < b[0].x;
        let left_target = a.last().unwrap().x < b.last().unwrap().x;
        assert_eq!(left_source, left_target);
    }

    #[test]
    fn groups_become_disjoint_columns() {
        // Two lanes whose nodes alternate along one chain.
        let groups = vec![Some(0), Some(1), Some(0), Some(1), Some(0)];
        let input = LayoutInput {
            nodes: boxes(5),
            edges: vec![(0, 1), (1, 2), (2, 3), (3, 4)],
            groups: groups.clone(),
            ..Default::default()
        };
        let layout = layered(&input, Spacing::default());
        let span = |g: usize| {
            let members: Vec<usize> = (0..5).filter(|&v| groups[v] == Some(g)).collect();
            let left = members.iter().map(|&v| layout.positions[v].x).fold(f64::INFINITY, f64::min);
            let right =
                members.iter().map(|&v| layout.positions[v].x + input.nodes[v].width).fold(f64::NEG_INFINITY, f64::max);
            (left, right)
        };
        let (l0, r0) = span(0);
        let (l1, _) = span(1);
        assert!(r0 < l1, "lane 0 [{l0}, {r0}] must end before lane 1 starts at {l1}");
        assert!(!overlaps(&layout, &input));
    }

    #[test]
    fn deterministic_and_handles_empty_and_large_inputs() {
        assert_eq!(layered(&LayoutInput::default(), Spacing::default()).positions.len(), 0);
        let n = 200;
        let edges: Vec<(usize, usize)> =
            (1..n).map(|i| ((i * 7) % i, i)).chain((0..n / 4).map(|i| (i * 3 % n, (i * 11 + 5) % n))).collect();
        let input = LayoutInput { nodes: boxes(n), edges, ..Default::default() };
        let first = layered(&input, Spacing::default());
        let second = layered(&input, Spacing::default());
        assert_eq!(first, second);
        assert!(!overlaps(&first, &input));
    }

    #[test]
    fn labels_get_room_beside_their_edges() {
        // Three parallel labelled edges between two boxes and a labelled long edge.
        let edges = vec![(0, 1), (0, 1), (0, 1), (1, 2), (0, 2)];
        let labels = vec![Some((80.0, 14.0)), Some((60.0, 14.0)), Some((70.0, 28.0)), None, Some((50.0, 14.0))];
        let input = LayoutInput { nodes: boxes(3), edges: edges.clone(), labels, ..Default::default() };
        let layout = layered(&input, Spacing::default());
        assert!(!overlaps(&layout, &input));
        let label_box = |e: usize| {
            let at = layout.labels[e].expect("a labelled edge gets a place for its label");
            let (w, h) = input.labels[e].unwrap();
            (at.x, at.y, w, h)
        };
        assert_eq!(layout.labels[3], None);
        let meets = |a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)| {
            a.0 < b.0 + b.2 && b.0 < a.0 + a.2 && a.1 < b.1 + b.3 && b.1 < a.1 + a.3
        };
        for e in [0, 1, 2, 4] {
            let label = label_box(e);
            for (v, p) in layout.positions.iter().enumerate() {
                assert!(!meets(label, (p.x, p.y, input.nodes[v].width, input.nodes[v].height)), "label {e} on box {v}");
            }
            for f in [0, 1, 2, 4].into_iter().filter(|&f| f > e) {
                assert!(!meets(label, label_box(f)), "labels {e} and {f} overlap");
            }
            // No edge passes through a label (the polylines are vertical where labels are).
            for route in &layout.edges {
                for s in route.windows(2) {
                    let (x0, x1) = (s[0].x.min(s[1].x), s[0].x.max(s[1].x));
                    let (y0, y1) = (s[0].y.min(s[1].y), s[0].y.max(s[1].y));
                    let thin = (x0, y0, (x1 - x0).max(1e-6), (y1 - y0).max(1e-6));
                    assert!(!meets(label, thin), "an edge crosses label {e}");
                }
            }
        }
    }
}
