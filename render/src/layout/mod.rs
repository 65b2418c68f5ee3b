//! Layered (Sugiyama-style) layout of a directed graph of boxes, top to bottom: cycle breaking
//! (`rank`), ranks by network simplex (`simplex`), dummy vertices for long edges (`proper`), crossing
//! minimisation (`minimise`, with `order` and `sifting`), coordinates (`place`, `align`), edge polylines
//! (`route`) and small parts apart (`pack`). Edge labels take room as dot's do: with labels, ranks are doubled
//! and each labelled edge's label sits beside a dummy in a rank between its boxes' ranks. Parallel
//! edges with end labels are fanned apart with room for those labels (`bundle`).
//! Deterministic: the same input gives the same output.

mod align;
mod bundle;
mod fit;
mod minimise;
mod order;
mod pack;
mod page;
mod parts;
mod pass;
mod place;
mod proper;
mod rank;
mod route;
mod seeded;
mod sifting;
mod simplex;
mod squeeze;
pub(crate) mod tracks;
mod unzip;
mod wrap;

pub(crate) use bundle::parallel_edges;
pub(crate) use route::{self_loop, PORT_FAN_MOST};

pub use crate::geometry::Point;
pub use page::Page;
pub use seeded::{Entry, Remembered, RowEntry, Seat};

use minimise::{minimise_crossings, swept_crossings};
use place::Extent;
use proper::Proper;

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
    /// The edges are a flow read from its sources (control flow, dataflow): a cycle is drawn
    /// with the edge back that a depth-first search from the sources closes it with (a loop's
    /// last edge), as it reads. Otherwise several orientations are ranked (`rank::candidates`)
    /// and the one whose crossings come out fewest is drawn.
    pub flow: bool,
    /// Per edge (or none): the edge must point down where any choice allows it (a
    /// generalization, laid out parent first).
    pub firm: Vec<bool>,
    /// Per edge (or none): the size of the labels at its source's end and at its target's end
    /// (an association's multiplicities and role names). The layout makes room for them only
    /// where edges run in parallel (`bundle`); elsewhere they are placed afterwards.
    pub end_labels: Vec<[Option<(f64, f64)>; 2]>,
    /// Where the boxes and long edges sat in a layout before (`Layout::rows`). Where at least
    /// half of the boxes have a seat, the layout keeps their rows' direction and their order in
    /// every rank (`seeded`).
    pub remembered: Remembered,
    /// Per edge (or none): where its source's and its target's ends meet their boxes, measured
    /// along the box's side from its start (a port's place down a box drawn left to right). A
    /// layout given ports also runs every long edge straight through the ranks it passes, at
    /// its place in each, so an orthogonal router can follow it (`scene::channels`).
    pub ports: Vec<[Option<f64>; 2]>,
}

/// Spacing of the layout, and the page it is meant for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    /// Between boxes of one rank.
    pub node_gap: f64,
    /// Between ranks.
    pub rank_gap: f64,
    /// Around the drawing.
    pub margin: f64,
    /// A drawing that does not fit it, and whose aspect ratio is far from the page's, is
    /// reshaped towards the page's: wide ranks split (`unzip`), a tall drawing wrapped into
    /// columns (`wrap`).
    pub page: Page,
}

impl Default for Spacing {
    fn default() -> Self {
        Spacing { node_gap: 40.0, rank_gap: 60.0, margin: 20.0, page: Page::SCREEN }
    }
}

/// The result: each box's top-left corner, each edge's polyline (first and last points on the
/// boxes' borders), the top-left corner of each edge's label where the layout placed it (not
/// for self loops), the top-left corners of the end labels it made room for (at the edge's
/// source and at its target), and the drawing's size.
#[derive(Debug, Clone, PartialEq)]
pub struct Layout {
    pub positions: Vec<Point>,
    pub edges: Vec<Vec<Point>>,
    pub labels: Vec<Option<Point>>,
    pub end_labels: Vec<[Option<Point>; 2]>,
    pub width: f64,
    pub height: f64,
    /// What each rank that holds boxes holds, in order, top to bottom — boxes and the long edges
    /// passing (a part laid out apart, or nested, after the rest): what the next layout keeps
    /// (`LayoutInput::remembered`, by `Remembered::of_rows`).
    pub rows: Vec<Vec<RowEntry>>,
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
        self.end_labels.iter_mut().flatten().flatten().for_each(shift);
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
        flow: input.flow,
        firm: input.firm.clone(),
        end_labels: Vec::new(),
        remembered: input.remembered.clone(),
        ports: input.ports.clone(),
    };
    let mut layout = layered(&across, Spacing { page: spacing.page.turned(), ..spacing });
    let turn = |p: &mut Point| std::mem::swap(&mut p.x, &mut p.y);
    layout.positions.iter_mut().for_each(turn);
    layout.edges.iter_mut().flatten().for_each(turn);
    layout.labels.iter_mut().for_each(|l| *l = None);
    std::mem::swap(&mut layout.width, &mut layout.height);
    layout
}

/// Space between an edge and its label.
const LABEL_OFFSET: f64 = 4.0;

/// Lays out `input` top to bottom: the boxes joined by edges (or in swimlanes) in layers, the
/// boxes alone packed in rows under them (`pack`).
pub fn layered(input: &LayoutInput, spacing: Spacing) -> Layout {
    let (joined, apart) = pack::split(input);
    if apart.is_empty() {
        return layered_joined(input, spacing);
    }
    let (joined_input, joined_edges) = pack::sub_input(input, &joined);
    let inner = layered_joined(&joined_input, spacing);
    let m = input.edges.len();
    let mut layout = Layout {
        positions: vec![Point::default(); input.nodes.len()],
        edges: vec![Vec::new(); m],
        labels: vec![None; m],
        end_labels: vec![[None; 2]; m],
        width: inner.width,
        height: inner.height,
        rows: Vec::new(),
    };
    let joined_part = pack::Part { boxes: joined, edges: joined_edges, layout: inner };
    joined_part.put(&mut layout, Point { x: spacing.margin, y: spacing.margin }, spacing, false);
    // A part apart keeps its order inside, and the place it had, where that is still free.
    let parts: Vec<pack::Part> = apart
        .into_iter()
        .map(|boxes| {
            let (sub, edges) = pack::sub_input(input, &boxes);
            let sub = LayoutInput { remembered: sub.remembered.orders_only(), ..sub };
            pack::Part { layout: layered_joined(&sub, spacing), boxes, edges }
        })
        .collect();
    let had: Vec<Option<Point>> = parts.iter().map(|part| part.place_before(&input.remembered, spacing)).collect();
    pack::place_apart(layout, input, &parts, &had, spacing, !joined_part.boxes.is_empty())
}

/// Lays out `input` top to bottom, every box in the layers.
fn layered_joined(input: &LayoutInput, spacing: Spacing) -> Layout {
    let n = input.nodes.len();
    if n == 0 {
        let empty = 2.0 * spacing.margin;
        return Layout {
            positions: Vec::new(),
            edges: Vec::new(),
            labels: Vec::new(),
            end_labels: Vec::new(),
            width: empty,
            height: empty,
            rows: Vec::new(),
        };
    }
    let label_of = |e: usize| input.labels.get(e).copied().flatten();
    let labelled = (0..input.edges.len()).any(|e| label_of(e).is_some());
    let bundled = bundle::bundled(&input.edges, &input.end_labels);
    // The seats of a layout before, where they are worth keeping: ranks started from their rows,
    // the way to rank that keeps the rows' direction, and their orders.
    let seats = Some(&input.remembered).filter(|remembered| seeded::worth_keeping(remembered, n));
    let wanted = seats.map_or(Vec::new(), seeded::wanted_rows);
    let mut ways: Vec<(rank::Ranked, Proper, Vec<bool>)> =
        rank::candidates(n, &input.edges, input.flow, &input.firm, &wanted)
            .into_iter()
            .map(|mut ranked| {
                unzip::unzip(&mut ranked.rank, &ranked.edges, &input.nodes, &input.groups, labelled, spacing);
                if labelled {
                    ranked.rank.iter_mut().for_each(|r| *r *= 2);
                }
                let lane_ranks = bundle::insert_lane_ranks(&mut ranked.rank, &ranked.edges, &bundled, labelled);
                let graph = Proper::new(&input.groups, &ranked.edges, &ranked.rank);
                (ranked, graph, lane_ranks)
            })
            .collect();
    let chosen = choose_way(&ways, seats);
    let (rank::Ranked { edges, rank }, graph, lane_ranks) = ways.swap_remove(chosen);
    let mut extent = Extent::of_boxes(&input.nodes, graph.vertices());
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
    let end_room = bundle::Room::reserve(&graph, &edges, &bundled, &input.end_labels, &mut extent);
    let mut layers = graph.initial_layers(true, false);
    let width = |layers: &[Vec<usize>]| {
        let x = place::horizontal(&graph, layers, &extent, spacing);
        place::right_edge(&x, &extent)
    };
    minimise_crossings(&mut layers, &graph, &width);
    // Seats that the order minimised afresh does not keep order the ranks instead (where it does,
    // as for the layout the seats were read off, it is that layout's order).
    let places = seats.map(|remembered| remembered.of_vertices(&graph));
    let layers = match &places {
        Some(places) if !seeded::kept(&layers, places) => seeded::seeded_order(&graph, places),
        _ => layers,
    };
    let mut x = place::horizontal(&graph, &layers, &extent, spacing);
    let separation = |u: usize, v: usize| place::separation(&graph, &extent, spacing, u, v);
    let rank_gap = if labelled { spacing.rank_gap / 2.0 } else { spacing.rank_gap };
    // With labels every other rank is already half a gap from its neighbours.
    let inserted: &[bool] = if labelled { &[] } else { &lane_ranks };
    let mut bands = place::Bands::new(&layers, &extent, Spacing { rank_gap, ..spacing }, inserted);
    // Swimlanes are columns of their own: a drawing in lanes is neither narrowed nor wrapped.
    let in_lanes = input.groups.iter().any(Option::is_some);
    let fit = if in_lanes { None } else { fit::plan(&layers, &extent, &x, &separation, spacing, bands.size()) };
    if let Some(fit) = fit {
        bands = place::Bands::new(&layers, &extent, Spacing { rank_gap: rank_gap * fit.stretch, ..spacing }, inserted);
        fit::narrow(&graph, &layers, &extent, &mut x, &separation, spacing, fit.width);
    }
    let least = |v: usize| spacing.margin + extent[v].left;
    bundle::gather(&graph, &layers, &lane_ranks, &bundled, &mut x, &separation, &least);
    if let Some(places) = &places {
        fit::keep(&layers, &extent, &mut x, &separation, spacing.margin, places);
    }
    // Each gap as wide as the tracks the scene turns connections on there need; ranks kept where they were.
    let room = tracks::room(&graph, &edges, &layers, (&x, &bands, &extent), &input.ports);
    let kept = places.as_ref().map(|p| seeded::kept_bands(&input.remembered, &graph, p, &bands.height));
    bands.settle(&room, &kept.unwrap_or_default());
    let positions: Vec<Point> = (0..n)
        .map(|v| Point { x: x[v] - input.nodes[v].width / 2.0, y: bands.middle(rank[v]) - input.nodes[v].height / 2.0 })
        .collect();
    let labels = label_vertex
        .iter()
        .map(|v| v.map(|d| Point { x: x[d] + LABEL_OFFSET, y: bands.middle(graph.rank[d]) - extent[d].height / 2.0 }))
        .collect();
    let mut end_labels = vec![[None; 2]; edges.len()];
    for placed in &end_room.labels {
        let (top, height) = (bands.top[graph.rank[placed.dummy]], bands.height[graph.rank[placed.dummy]]);
        let y = if placed.at_top { top } else { top + height - placed.size.1 };
        end_labels[placed.edge][placed.end] = Some(Point { x: x[placed.dummy] + LABEL_OFFSET, y });
    }
    let routed = route::polylines(&graph, &edges, &layers, (&x, &bands, &extent), &input.ports);
    let width = place::right_edge(&x, &extent) + spacing.margin;
    let rows = seeded::rows(&layers, &graph, &x);
    let mut layout = Layout { positions, edges: routed, labels, end_labels, width, height: bands.total_height, rows };
    let kept = places.as_ref().map_or(Vec::new(), |p| seeded::kept_cuts(&input.remembered, &graph, &layers, p));
    let cuts = if in_lanes { Vec::new() } else { wrap::wrap(&mut layout, input, &bands, spacing, &kept) };
    seeded::mark(&mut layout.rows, &layers, &graph, (&bands.top, &bands.height), &cuts);
    layout
}

/// Which of the ways to rank the boxes to lay out: of those that keep the direction of the rows
/// the `seats` sat in best, the one whose order sweeps find the fewest crossings in (fewer ranks
/// are shorter but may crowd them), the first of equals. Sweeps only where there is a choice (a
/// flow has one way).
fn choose_way(ways: &[(rank::Ranked, Proper, Vec<bool>)], seats: Option<&Remembered>) -> usize {
    if ways.len() == 1 {
        return 0;
    }
    let against: Vec<usize> =
        ways.iter().map(|way| seats.map_or(0, |seats| seeded::disagreements(&way.0, seats))).collect();
    let fewest = against.iter().copied().min().unwrap_or(0);
    (0..ways.len())
        .filter(|&i| against[i] == fewest)
        .min_by_key(|&i| swept_crossings(&ways[i].1))
        .expect("one way to rank at least")
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::geometry::{segment_meets_box, Rect};

    /// `m` edges between random boxes of `n`, from `seed` (a linear congruential generator).
    pub(crate) fn pseudo_random_edges(seed: u64, n: usize, m: usize) -> Vec<(usize, usize)> {
        let mut state = seed * 7919 + 3;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 33) as usize) % n
        };
        (0..m).map(|_| (next(), next())).collect()
    }

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

    #[test]
    fn boxes_alone_are_packed_in_rows_not_one_long_row() {
        // Twelve unconnected boxes: a block of rows, about as wide as tall.
        let input = LayoutInput { nodes: boxes(12), ..Default::default() };
        let layout = layered(&input, Spacing::default());
        assert!(!overlaps(&layout, &input));
        let aspect = layout.width.max(layout.height) / layout.width.min(layout.height);
        assert!(aspect < 2.5, "{} x {}", layout.width, layout.height);
        // Beside a layered drawing they go under it, in input order, and the drawing keeps them.
        let input = LayoutInput { nodes: boxes(8), edges: vec![(0, 1), (1, 2), (0, 3)], ..Default::default() };
        let layout = layered(&input, Spacing::default());
        assert!(!overlaps(&layout, &input));
        let lowest_joined = (0..4).map(|v| layout.positions[v].y + input.nodes[v].height).fold(0.0, f64::max);
        assert!((4..8).all(|v| layout.positions[v].y > lowest_joined));
        assert!(layout.positions[4].x < layout.positions[5].x || layout.positions[4].y < layout.positions[5].y);
        assert!((0..8).all(|v| layout.positions[v].x + input.nodes[v].width <= layout.width));
        assert!((0..8).all(|v| layout.positions[v].y + input.nodes[v].height <= layout.height));
    }

    #[test]
    fn boxes_alone_fill_free_room_beside_a_rank_without_growing_the_drawing() {
        // A root over six children leaves room beside the root: two boxes alone go there, level
        // with it, at the drawing's sides, clear of every box and edge.
        let joined = LayoutInput { nodes: boxes(7), edges: (1..7).map(|v| (0, v)).collect(), ..Default::default() };
        let without = layered(&joined, Spacing::default());
        let input = LayoutInput { nodes: boxes(9), ..joined.clone() };
        let layout = layered(&input, Spacing::default());
        assert_eq!((layout.width, layout.height), (without.width, without.height));
        assert!(!overlaps(&layout, &input));
        for v in [7, 8] {
            assert_eq!(layout.positions[v].y, layout.positions[0].y);
            let (at, size) = (layout.positions[v], &input.nodes[v]);
            let r = Rect { x: at.x, y: at.y, width: size.width, height: size.height };
            assert!(!layout.edges.iter().any(|route| route.windows(2).any(|s| segment_meets_box(s[0], s[1], r))));
        }
        let right = |v: usize| layout.positions[v].x + input.nodes[v].width;
        let margin = Spacing::default().margin;
        assert_eq!(layout.positions[7].x.min(layout.positions[8].x), margin);
        assert_eq!(right(7).max(right(8)), layout.width - margin);
    }

    #[test]
    fn a_small_part_apart_fills_free_room_with_its_edge() {
        // 0 over 1..=6, 1 -> 7 -> 8: room right of 7 and 8, under the wide rank. The part 9 -> 10
        // goes there, laid out on its own, its edge between its boxes; the drawing does not grow.
        let mut edges: Vec<(usize, usize)> = (1..7).map(|v| (0, v)).collect();
        edges.extend([(1, 7), (7, 8)]);
        let joined = LayoutInput { nodes: boxes(9), edges: edges.clone(), ..Default::default() };
        let without = layered(&joined, Spacing::default());
        edges.push((9, 10));
        let input = LayoutInput { nodes: boxes(11), edges, ..Default::default() };
        let layout = layered(&input, Spacing::default());
        assert_eq!((layout.width, layout.height), (without.width, without.height));
        assert!(!overlaps(&layout, &input));
        assert!(layout.positions[9].y >= layout.positions[7].y && layout.positions[9].y < layout.positions[10].y);
        let route = &layout.edges[8];
        let (first, last) = (route[0], route[route.len() - 1]);
        assert_eq!(first.y, layout.positions[9].y + input.nodes[9].height);
        assert_eq!(last.y, layout.positions[10].y);
        for (e, route) in layout.edges.iter().enumerate() {
            let (a, b) = input.edges[e];
            for v in (0..11).filter(|&v| v != a && v != b) {
                let (at, size) = (layout.positions[v], &input.nodes[v]);
                let r = Rect { x: at.x, y: at.y, width: size.width, height: size.height };
                assert!(!route.windows(2).any(|s| segment_meets_box(s[0], s[1], r)), "edge {e} through box {v}");
            }
        }
    }

    #[test]
    fn network_simplex_ranks_keep_edges_short_and_pointing_down() {
        // 0 -> 1 -> 2 -> 3 and 4 -> 3: longest path puts 4 at the top (its edge three ranks
        // long); the least total length puts it just above 3.
        let edges = rank::orient(5, &[(0, 1), (1, 2), (2, 3), (4, 3)]);
        let rank = simplex::network_simplex(5, &edges, &rank::longest_path(5, &edges));
        assert_eq!(rank, vec![0, 1, 2, 3, 2]);
        // On a larger graph with cycles and parallel edges: every edge points down, and the total
        // length is no more than longest path's.
        let pairs: Vec<(usize, usize)> = (1..120)
            .map(|i| ((i * 7) % i, i))
            .chain((0..60).map(|i| ((i * 13 + 5) % 120, (i * 29 + 1) % 120)))
            .collect();
        let edges = rank::orient(120, &pairs);
        let start = rank::longest_path(120, &edges);
        let rank = simplex::network_simplex(120, &edges, &start);
        let length = |r: &[usize]| edges.iter().filter(|e| e.0 != e.1).map(|e| r[e.1] - r[e.0]).sum::<usize>();
        assert!(edges.iter().filter(|e| e.0 != e.1).all(|e| rank[e.1] > rank[e.0]));
        assert!(length(&rank) <= length(&start));
    }

    #[test]
    fn every_start_holds_each_vertex_once_even_with_parallel_edges() {
        let pairs = [(0, 1), (0, 1), (1, 2), (1, 2), (2, 0), (0, 3), (3, 2)];
        let edges = rank::orient(4, &pairs);
        let graph = Proper::new(&[], &edges, &rank::longest_path(4, &edges));
        for (breadth_first, undirected) in [(true, false), (false, false), (true, true), (false, true)] {
            let mut all: Vec<usize> = graph.initial_layers(breadth_first, undirected).concat();
            all.sort_unstable();
            assert_eq!(all, (0..graph.vertices()).collect::<Vec<_>>());
        }
    }
}
