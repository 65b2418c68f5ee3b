//! Orders kept from a layout before: each box's seat (its row among the ranks that hold boxes,
//! and its place in that row) is read off a drawing and orders the next one. The boxes seated
//! before keep their relative order in every rank; new boxes and the dummies of long edges are
//! put, block by block, where they cross the fewest (global sifting of those blocks alone, then
//! sweeps around the seated boxes). A fresh layout after an edit then keeps what the edit left
//! alone; where crossing minimisation afresh keeps the seats' order anyway (as for the layout
//! they were read off), its order stands.

use super::{minimise::sweeps, order::Order, proper::Proper, rank::Ranked, sifting::GlobalOrder};

/// Where a box, or one of a long edge's dummies, sat in a layout: its row (the ranks that hold
/// boxes, counted from the top) and its place in the row as a share of it (the middle of its
/// slot: (column + ½) / entries).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seat {
    pub row: usize,
    pub at: f64,
    /// Its centre across the ranks, where it was kept.
    pub x: Option<f64>,
    /// Its top, for a box of a part laid out apart.
    pub y: Option<f64>,
}

/// An entry of a row, where it was drawn: its centre across the ranks and, for a box of a part
/// laid out apart, its top (with the centre, that part's place).
pub type RowEntry = (Entry, Option<f64>, Option<f64>);

/// What a row holds: a box, or a long edge passing through it (one of its dummies), by index;
/// or, last in a row, a mark: where the row's band started along the ranks and how far it
/// reached (`Band`, its `x` and `y`),
/// and that a wrapped drawing's column started there (`Column`, its `x`: how many ranks without
/// boxes before the row the column started).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Entry {
    Box(usize),
    Edge(usize),
    Band,
    Column,
}

/// Where the boxes and long edges of a graph sat in a layout before.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Remembered {
    /// Per box (or none).
    pub boxes: Vec<Option<Seat>>,
    /// Per edge: its dummies' seats in the rows it passed, top to bottom.
    pub edges: Vec<Vec<Seat>>,
    /// Where a wrapped drawing's columns after the first started: at a row, so many ranks
    /// without boxes before it.
    pub columns: Vec<(usize, usize)>,
    /// Where rows' bands started along the ranks, and how far they reached.
    pub bands: Vec<(usize, f64, Option<f64>)>,
}

impl Remembered {
    /// The seats in `rows` of a graph of `boxes` boxes and `edges` edges (entries beyond are
    /// left out).
    pub fn of_rows(rows: &[Vec<RowEntry>], boxes: usize, edges: usize) -> Remembered {
        let mut remembered = Remembered {
            boxes: vec![None; boxes],
            edges: vec![Vec::new(); edges],
            columns: Vec::new(),
            bands: Vec::new(),
        };
        for (row, entries) in rows.iter().enumerate() {
            let (marks, seated): (Vec<&RowEntry>, Vec<&RowEntry>) =
                entries.iter().partition(|e| matches!(e.0, Entry::Column | Entry::Band));
            for (column, &&(entry, x, y)) in seated.iter().enumerate() {
                let seat = Seat { row, at: (column as f64 + 0.5) / seated.len() as f64, x, y };
                match entry {
                    Entry::Box(v) if v < boxes => remembered.boxes[v] = Some(seat),
                    Entry::Edge(e) if e < edges => remembered.edges[e].push(seat),
                    _ => {}
                }
            }
            if let Some(&&(_, before, _)) = marks.iter().find(|e| e.0 == Entry::Column) {
                // Saturating: a sidecar is untrusted, the count is clamped where it is used.
                remembered.columns.push((row, before.map_or(0, |b| b.max(0.0) as usize)));
            }
            if let Some(&&(_, Some(top), height)) = marks.iter().find(|e| e.0 == Entry::Band) {
                remembered.bands.push((row, top, height));
            }
        }
        remembered
    }

    /// The same seats without where they were drawn: orders only.
    pub(super) fn orders_only(mut self) -> Remembered {
        let forget = |seat: &mut Seat| (seat.x, seat.y) = (None, None);
        self.boxes.iter_mut().flatten().for_each(forget);
        self.edges.iter_mut().flatten().for_each(forget);
        self.columns.clear();
        self.bands.clear();
        self
    }

    /// The seats of the part made of `boxes` and `edges` (indices here), in that order.
    pub(crate) fn part(&self, boxes: &[usize], edges: &[usize]) -> Remembered {
        Remembered {
            boxes: boxes.iter().map(|&v| self.boxes.get(v).copied().flatten()).collect(),
            edges: edges.iter().map(|&e| self.edges.get(e).cloned().unwrap_or_default()).collect(),
            columns: self.columns.clone(),
            bands: self.bands.clone(),
        }
    }

    /// The seat of each vertex of `graph` that sits in its rank's row (none for the others): a
    /// box's own, a dummy its edge's in that row. A rank's row is the one most of its seated
    /// boxes sat in; a box that sat in another (its rank changed) is placed anew, as is a long
    /// edge that did not pass the row.
    pub(super) fn of_vertices(&self, graph: &Proper) -> Vec<Option<Seat>> {
        let row_of = self.row_of_ranks(graph);
        let in_row = |v: usize, seat: &Seat| row_of[graph.rank[v]] == Some(seat.row);
        let mut places: Vec<Option<Seat>> =
            (0..graph.vertices()).map(|v| self.box_seat(v).filter(|s| in_row(v, s))).collect();
        for (e, chain) in graph.chains.iter().enumerate() {
            let seats = self.edges.get(e).map_or(&[][..], Vec::as_slice);
            for &v in chain.iter().filter(|&&v| v >= graph.boxes) {
                places[v] = seats.iter().find(|s| in_row(v, s)).copied();
            }
        }
        places
    }

    /// Per rank of `graph`: the row most of its seated boxes sat in (the first of equals).
    fn row_of_ranks(&self, graph: &Proper) -> Vec<Option<usize>> {
        let mut counts: Vec<std::collections::BTreeMap<usize, usize>> = vec![Default::default(); graph.ranks()];
        for v in 0..graph.boxes {
            if let Some(seat) = self.box_seat(v) {
                *counts[graph.rank[v]].entry(seat.row).or_default() += 1;
            }
        }
        let most = |count: &std::collections::BTreeMap<usize, usize>| {
            count.iter().max_by_key(|&(&row, &n)| (n, std::cmp::Reverse(row))).map(|(&row, _)| row)
        };
        counts.iter().map(most).collect()
    }

    fn box_seat(&self, v: usize) -> Option<Seat> {
        self.boxes.get(v).copied().flatten()
    }
}

/// What each rank of `layers` that holds boxes holds, in order: the rows a layout leaves to the
/// next.
pub(super) fn rows(layers: &[Vec<usize>], graph: &Proper, x: &[f64]) -> Vec<Vec<RowEntry>> {
    let mut edge_of = vec![usize::MAX; graph.vertices()];
    for (e, chain) in graph.chains.iter().enumerate() {
        chain.iter().filter(|&&v| v >= graph.boxes).for_each(|&v| edge_of[v] = e);
    }
    let entry = |v: usize| if v < graph.boxes { Entry::Box(v) } else { Entry::Edge(edge_of[v]) };
    layers
        .iter()
        .filter(|layer| layer.iter().any(|&v| v < graph.boxes))
        .map(|layer| layer.iter().map(|&v| (entry(v), Some(x[v]), None)).collect())
        .collect()
}

/// Per row of the layout `places` (the vertices' seats) were read off, the rank of `graph` its
/// seated boxes are in now.
fn rank_of_row(graph: &Proper, places: &[Option<Seat>]) -> std::collections::HashMap<usize, usize> {
    let seated = places.iter().enumerate().take(graph.boxes);
    seated.filter_map(|(v, seat)| Some((seat.as_ref()?.row, graph.rank[v]))).collect()
}

/// The first rank of each column after the first of the wrapped layout `remembered` was read
/// off, as its rows fall in `layers` now (`places`: the vertices' seats): a column that started
/// at a row starts at that row's rank, or so many ranks before it as it did, none of them holding
/// boxes. Strictly increasing; empty where the layout before was not wrapped.
pub(super) fn kept_cuts(
    remembered: &Remembered,
    graph: &Proper,
    layers: &[Vec<usize>],
    places: &[Option<Seat>],
) -> Vec<usize> {
    let rank_of_row = rank_of_row(graph, places);
    let holds_box = |r: usize| layers[r].iter().any(|&v| v < graph.boxes);
    let mut cuts: Vec<usize> = Vec::new();
    for &(row, before) in &remembered.columns {
        let Some(&rank) = rank_of_row.get(&row) else { continue };
        let mut first = rank;
        while first > 0 && rank - first < before && !holds_box(first - 1) {
            first -= 1;
        }
        if first > cuts.last().copied().unwrap_or(0) {
            cuts.push(first);
        }
    }
    cuts
}

/// Per rank of `graph` (its band `height` along the ranks now), where its band starts for its
/// middle to be where it was in the layout `remembered` was read off (`places`: the vertices'
/// seats), if its row's band was kept.
pub(super) fn kept_bands(
    remembered: &Remembered,
    graph: &Proper,
    places: &[Option<Seat>],
    height: &[f64],
) -> Vec<Option<f64>> {
    let rank_of_row = rank_of_row(graph, places);
    let mut kept = vec![None; graph.ranks()];
    for &(row, top, was) in &remembered.bands {
        if let Some(&rank) = rank_of_row.get(&row) {
            kept[rank] = Some(top + (was.unwrap_or(height[rank]) - height[rank]) / 2.0);
        }
    }
    kept
}

/// Marks in `rows` (of `layers`, as `rows` writes them) where each row's band starts and how
/// far it reaches (`bands`: per rank, its top and height), and where each of the columns that
/// start at the ranks `cuts` starts: last in the first row at or after it, with the ranks before it.
pub(super) fn mark(
    rows: &mut [Vec<RowEntry>],
    layers: &[Vec<usize>],
    graph: &Proper,
    bands: (&[f64], &[f64]),
    cuts: &[usize],
) {
    let box_ranks: Vec<usize> = (0..layers.len()).filter(|&r| layers[r].iter().any(|&v| v < graph.boxes)).collect();
    for (entries, &rank) in rows.iter_mut().zip(&box_ranks) {
        entries.push((Entry::Band, Some(bands.0[rank]), Some(bands.1[rank])));
    }
    for &first in cuts {
        let row = box_ranks.partition_point(|&r| r < first);
        if let (Some(entries), Some(&rank)) = (rows.get_mut(row), box_ranks.get(row)) {
            entries.push((Entry::Column, Some((rank - first) as f64), None));
        }
    }
}

/// Whether `remembered` is worth keeping for a graph of `boxes` boxes: at least half of them had
/// a seat (else the layout before was of another graph, and the order starts afresh).
pub(super) fn worth_keeping(remembered: &Remembered, boxes: usize) -> bool {
    boxes > 0 && 2 * remembered.boxes.iter().take(boxes).flatten().count() >= boxes
}

/// Per box: the row it sat in (a start for ranking it).
pub(super) fn wanted_rows(remembered: &Remembered) -> Vec<Option<usize>> {
    remembered.boxes.iter().map(|seat| seat.map(|s| s.row)).collect()
}

/// Whether `layers` keep the seated vertices (`places`, per vertex) in the order of their
/// places in every rank.
pub(super) fn kept(layers: &[Vec<usize>], places: &[Option<Seat>]) -> bool {
    layers.iter().all(|layer| {
        let seated: Vec<f64> = layer.iter().filter_map(|&v| places[v].map(|s| s.at)).collect();
        seated.windows(2).all(|pair| pair[0] < pair[1])
    })
}

/// How many of `ranked`'s edges between seated boxes in different rows point the other way
/// than those rows (or join boxes now in one rank): a way of ranking that keeps the rows
/// before has none.
pub(super) fn disagreements(ranked: &Ranked, remembered: &Remembered) -> usize {
    let seat = |v: usize| remembered.box_seat(v);
    ranked
        .edges
        .iter()
        .filter(|&&(a, b, _)| match (seat(a), seat(b)) {
            (Some(sa), Some(sb)) if sa.row != sb.row => {
                (sa.row < sb.row) != (ranked.rank[a] < ranked.rank[b]) || ranked.rank[a] == ranked.rank[b]
            }
            _ => false,
        })
        .count()
}

/// At most this many passes of sifting the blocks none of whose vertices was seated.
const PASSES: usize = 4;

/// The order of every rank of `graph` from the seated vertices' `places`: those keep their
/// order; every other block (a new box, a new long edge's dummies) first goes where its seated
/// neighbours put it and is sifted to where it crosses the fewest until a pass brings nothing;
/// then median sweeps and transposition around the seated vertices.
pub(super) fn seeded_order(graph: &Proper, places: &[Option<Seat>]) -> Vec<Vec<usize>> {
    let place = initial_places(graph, places);
    let mut layers = vec![Vec::new(); graph.ranks()];
    for v in 0..graph.vertices() {
        layers[graph.rank[v]].push(v);
    }
    for layer in &mut layers {
        layer.sort_by(|&a, &b| graph.group[a].cmp(&graph.group[b]).then(place[a].total_cmp(&place[b])).then(a.cmp(&b)));
    }
    let seated: Vec<bool> = places.iter().map(Option::is_some).collect();
    let sifted = sift_free(&layers, graph, places);
    sweeps(sifted.unwrap_or(layers), graph, &seated).0
}

/// `layers` with the blocks none of whose vertices is seated sifted to where they cross the
/// fewest, until a pass brings nothing; none where the one order of blocks that sifting needs
/// would not keep the seated vertices' order (a long edge seated in some ranks).
fn sift_free(layers: &[Vec<usize>], graph: &Proper, places: &[Option<Seat>]) -> Option<Vec<Vec<usize>>> {
    let mut global = GlobalOrder::new(&Order::new(layers.to_vec(), graph.vertices()), graph);
    if !kept(&global.order.layers, places) {
        return None;
    }
    let free: Vec<usize> =
        (0..graph.blocks.len()).filter(|&b| graph.blocks[b].iter().all(|&v| places[v].is_none())).collect();
    let mut crossings = global.order.crossings(graph);
    for _ in 0..PASSES {
        if crossings == 0 {
            break;
        }
        // Sifting moves one block past others: the order of the rest, the seated too, stays.
        free.iter().for_each(|&b| global.sift(b, graph));
        let after = global.order.crossings(graph);
        if after >= crossings {
            break;
        }
        crossings = after;
    }
    Some(global.order.layers)
}

/// A first place (0 left … 1 right) for every vertex: a seated one its seat's; a new box the
/// mean of its seated neighbours' (the middle without any); a dummy not seated evenly between
/// the nearest places along its edge.
fn initial_places(graph: &Proper, seats: &[Option<Seat>]) -> Vec<f64> {
    let places: Vec<Option<f64>> = seats.iter().map(|s| s.map(|s| s.at)).collect();
    let mut sum = vec![(0.0, 0usize); graph.boxes];
    for chain in &graph.chains {
        let (a, b) = (chain[0], chain[chain.len() - 1]);
        if let (Some(at), None) = (places[a], places[b]) {
            sum[b] = (sum[b].0 + at, sum[b].1 + 1);
        }
        if let (None, Some(at)) = (places[a], places[b]) {
            sum[a] = (sum[a].0 + at, sum[a].1 + 1);
        }
    }
    let mut place: Vec<f64> = (0..graph.vertices())
        .map(|v| match (places[v], v < graph.boxes) {
            (Some(at), _) => at,
            (None, true) if sum[v].1 > 0 => sum[v].0 / sum[v].1 as f64,
            _ => 0.5,
        })
        .collect();
    for chain in &graph.chains {
        // The chain's ends are boxes: both have a place.
        let known: Vec<usize> =
            (0..chain.len()).filter(|&k| k == 0 || k == chain.len() - 1 || places[chain[k]].is_some()).collect();
        for pair in known.windows(2) {
            let (i, j) = (pair[0], pair[1]);
            let (from, to) = (place[chain[i]], place[chain[j]]);
            for k in i + 1..j {
                place[chain[k]] = from + (to - from) * (k - i) as f64 / (j - i) as f64;
            }
        }
    }
    place
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::order::tests::proper;

    /// The seats of every vertex in `layers`' rows.
    fn places(layers: &[Vec<usize>], graph: &Proper) -> Vec<Option<Seat>> {
        let x = vec![0.0; graph.vertices()];
        Remembered::of_rows(&rows(layers, graph, &x), graph.boxes, graph.chains.len()).of_vertices(graph)
    }

    #[test]
    fn a_layout_seated_by_its_own_rows_keeps_them() {
        let edges = crate::layout::tests::pseudo_random_edges(5, 30, 45);
        let graph = proper(30, &edges, &[]);
        let first = seeded_order(&graph, &places(&graph.initial_layers(true, false), &graph));
        assert!(kept(&first, &places(&first, &graph)));
        let x = vec![0.0; graph.vertices()];
        assert_eq!(rows(&seeded_order(&graph, &places(&first, &graph)), &graph, &x), rows(&first, &graph, &x));
    }

    #[test]
    fn seated_boxes_keep_their_order_and_new_blocks_are_sifted_in() {
        let edges = crate::layout::tests::pseudo_random_edges(9, 24, 30);
        let graph = proper(24, &edges, &[]);
        // Every rank's boxes seated right to left, the dummies not at all: the boxes keep that.
        let start = graph.initial_layers(true, false);
        let reversed: Vec<Vec<usize>> = start.iter().map(|layer| layer.iter().rev().copied().collect()).collect();
        let mut seats = places(&reversed, &graph);
        seats[graph.boxes..].iter_mut().for_each(|seat| *seat = None);
        let order = seeded_order(&graph, &seats);
        assert!(kept(&order, &seats));
        let boxes_only = |layers: &[Vec<usize>]| -> Vec<Vec<usize>> {
            layers.iter().map(|l| l.iter().copied().filter(|&v| v < 24).collect()).collect()
        };
        assert_eq!(boxes_only(&order), boxes_only(&reversed));
        // The dummies found their places: fewer crossings than where they were first put.
        let place = initial_places(&graph, &seats);
        let mut unsifted = reversed.clone();
        unsifted.iter_mut().for_each(|l| l.sort_by(|&a, &b| place[a].total_cmp(&place[b]).then(a.cmp(&b))));
        let crossings = |layers: Vec<Vec<usize>>| Order::new(layers, graph.vertices()).crossings(&graph);
        assert!(crossings(order) < crossings(unsifted));
    }

    #[test]
    fn the_columns_a_wrapped_layout_started_are_read_back_where_they_started() {
        // A chain of four boxes with an empty rank (only a long edge's dummy) before the third.
        let edges = [(0, 1, false), (1, 2, false), (2, 3, false), (0, 4, false)];
        let graph = Proper::new(&[], &edges, &[0, 1, 3, 4, 4]);
        let layers = graph.initial_layers(true, false);
        let x = vec![0.0; graph.vertices()];
        let unmarked = rows(&layers, &graph, &x);
        let mut marked = unmarked.clone();
        // Columns starting at the empty rank (before the third row) and at the last rank.
        let tops: Vec<f64> = (0..5).map(|r| r as f64 * 100.0).collect();
        mark(&mut marked, &layers, &graph, (&tops, &[20.0; 5]), &[2, 4]);
        assert_eq!(marked[2].last(), Some(&(Entry::Column, Some(1.0), None)));
        let remembered = Remembered::of_rows(&marked, graph.boxes, graph.chains.len());
        let places = remembered.of_vertices(&graph);
        assert_eq!(kept_cuts(&remembered, &graph, &layers, &places), [2, 4]);
        // Each row's band where it was (none for the empty rank); the last, 10 taller now, around
        // the same middle.
        let height = [20.0, 20.0, 20.0, 20.0, 30.0];
        let kept = kept_bands(&remembered, &graph, &places, &height);
        assert_eq!(kept, [Some(0.0), Some(100.0), None, Some(300.0), Some(395.0)]);
        // The marks take no seat: every box and dummy sits where it sat without them.
        let plain = Remembered::of_rows(&unmarked, graph.boxes, graph.chains.len());
        assert_eq!(places, plain.of_vertices(&graph));
        // A mark claiming more empty ranks before its row than there are (a sidecar is untrusted
        // input) starts the column after the last rank with boxes before it.
        let mut claimed = unmarked;
        claimed[2].push((Entry::Column, Some(1e6), None));
        let remembered = Remembered::of_rows(&claimed, graph.boxes, graph.chains.len());
        assert_eq!(kept_cuts(&remembered, &graph, &layers, &places), [2]);
    }

    #[test]
    fn rows_pointing_the_other_way_disagree() {
        let remembered =
            Remembered::of_rows(&[vec![(Entry::Box(1), None, None)], vec![(Entry::Box(0), None, None)]], 2, 1);
        let down = Ranked { edges: vec![(0, 1, false)], rank: vec![0, 1] };
        let up = Ranked { edges: vec![(1, 0, true)], rank: vec![1, 0] };
        assert_eq!(disagreements(&down, &remembered), 1);
        assert_eq!(disagreements(&up, &remembered), 0);
    }
}
