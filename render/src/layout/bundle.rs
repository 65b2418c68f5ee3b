//! Parallel edges that carry end labels (two associations between the same classes, say):
//! fanned apart, each with room beside it for the labels at its ends. A bundle between adjacent
//! ranks gets a rank of its own between them (a lane rank), so that each of its edges has a dummy
//! there; the dummy next to each end is made as wide and tall as that end's labels, and the
//! labels go right of it (`Room::labels`).

use std::collections::BTreeMap;

use super::proper::Proper;
use super::{Extent, LABEL_OFFSET};

/// A label's size: width and height.
pub(super) type Size = (f64, f64);

/// The edges between the same two boxes, whichever way each points, in groups of two or more
/// (edge indices in input order; the groups in the order of their boxes). A box's loops to
/// itself are in none.
pub(crate) fn parallel_edges(ends: impl IntoIterator<Item = (usize, usize)>) -> Vec<Vec<usize>> {
    let mut by_boxes: BTreeMap<(usize, usize), Vec<usize>> = BTreeMap::new();
    for (e, (a, b)) in ends.into_iter().enumerate().filter(|(_, (a, b))| a != b) {
        by_boxes.entry((a.min(b), a.max(b))).or_default().push(e);
    }
    by_boxes.into_values().filter(|edges| edges.len() > 1).collect()
}

/// Per edge: whether it runs in a bundle, between the same two boxes as another edge, whose end
/// labels need the room: two of its edges carry end labels, or one of three or more does (it
/// may run between the others). One labelled edge beside one other has a free side for them.
pub(super) fn bundled(edges: &[(usize, usize)], end_labels: &[[Option<Size>; 2]]) -> Vec<bool> {
    let labelled = |e: usize| end_labels.get(e).is_some_and(|ends| ends.iter().any(Option::is_some));
    let mut bundled = vec![false; edges.len()];
    let crowded = |members: &&Vec<usize>| match members.iter().filter(|&&e| labelled(e)).count() {
        0 => false,
        1 => members.len() > 2,
        _ => true,
    };
    for members in parallel_edges(edges.iter().copied()).iter().filter(crowded) {
        members.iter().for_each(|&e| bundled[e] = true);
    }
    bundled
}

/// Inserts a lane rank between every two adjacent ranks that a bundled edge joins; the ranks
/// below move down. Returns, per rank after that, whether it is a lane rank. Where the ranks
/// were `doubled` (for middle labels), a bundle between boxes two ranks apart already has the
/// rank between them: it becomes the lane rank, and none is inserted.
pub(super) fn insert_lane_ranks(
    rank: &mut [usize],
    edges: &[(usize, usize, bool)],
    bundled: &[bool],
    doubled: bool,
) -> Vec<bool> {
    let ranks = rank.iter().max().map_or(0, |r| r + 1);
    let step = if doubled { 2 } else { 1 };
    let mut lane_below = vec![false; ranks];
    for (&(a, b, _), _) in edges.iter().zip(bundled).filter(|(_, &bundled)| bundled) {
        if rank[b] == rank[a] + step {
            lane_below[rank[a]] = true;
        }
    }
    if doubled {
        return (0..ranks).map(|r| r > 0 && lane_below[r - 1]).collect();
    }
    let mut shift = Vec::with_capacity(ranks);
    let mut lane_rank = Vec::with_capacity(ranks * 2);
    for (r, &lane) in lane_below.iter().enumerate() {
        shift.push(lane_rank.len() - r);
        lane_rank.push(false);
        if lane {
            lane_rank.push(true);
        }
    }
    for r in rank.iter_mut() {
        *r += shift[*r];
    }
    lane_rank
}

/// Where the end labels of bundled edges go: beside which dummy, at the top of its rank's band
/// (the upper box's end) or at the bottom.
pub(super) struct Room {
    pub labels: Vec<Placed>,
}

/// One end label beside a dummy: the end it belongs to (0: the edge's source in the input, 1:
/// its target), the dummy, and whether it sits at the band's top (the upper end's label).
pub(super) struct Placed {
    pub edge: usize,
    pub end: usize,
    pub dummy: usize,
    pub at_top: bool,
    pub size: Size,
}

/// Between the upper end's labels and the lower end's beside one dummy.
const ENDS_APART: f64 = 24.0;

impl Room {
    /// Makes the dummies next to the ends of each bundled edge as wide and tall as that end's
    /// labels (right of the dummy), in `extent`.
    pub fn reserve(
        graph: &Proper,
        edges: &[(usize, usize, bool)],
        bundled: &[bool],
        end_labels: &[[Option<Size>; 2]],
        extent: &mut [Extent],
    ) -> Room {
        let mut labels = Vec::new();
        for (e, &(_, _, reversed)) in edges.iter().enumerate().filter(|&(e, _)| bundled[e]) {
            let chain = &graph.chains[e];
            if chain.len() < 3 {
                continue;
            }
            // In the input's direction the source is the upper box unless the edge was turned.
            let (upper, lower) = if reversed { (1, 0) } else { (0, 1) };
            let ends = end_labels.get(e).copied().unwrap_or_default();
            let (first, last) = (chain[1], chain[chain.len() - 2]);
            for (end, dummy, at_top) in [(upper, first, true), (lower, last, false)] {
                let Some(size) = ends[end] else { continue };
                let room = &mut extent[dummy];
                room.right = room.right.max(LABEL_OFFSET + size.0);
                // Labels of both ends beside one dummy: apart, so each reads as its end's.
                room.height += size.1 + if room.height > 0.0 { ENDS_APART } else { 0.0 };
                labels.push(Placed { edge: e, end, dummy, at_top, size });
            }
        }
        Room { labels }
    }
}

/// Moves the dummies of each bundle in a lane rank next to each other, centred under the middle
/// of the bundle's boxes, as far as their neighbours in the rank leave room: Brandes–Köpf
/// aligns one of them with the boxes and leaves the others wherever compaction pushed them.
/// `separation(u, v)` is the least distance between neighbours' centres; no centre goes left of
/// `least` plus its room.
pub(super) fn gather(
    graph: &Proper,
    layers: &[Vec<usize>],
    lane_ranks: &[bool],
    bundled: &[bool],
    x: &mut [f64],
    separation: &dyn Fn(usize, usize) -> f64,
    least: &dyn Fn(usize) -> f64,
) {
    // Per dummy in a lane rank: its bundle's boxes.
    let mut bundle_of = vec![None; graph.vertices()];
    for (chain, _) in graph.chains.iter().zip(bundled).filter(|(chain, &b)| b && chain.len() == 3) {
        if lane_ranks.get(graph.rank[chain[1]]).copied().unwrap_or(false) {
            bundle_of[chain[1]] = Some((chain[0].min(chain[2]), chain[0].max(chain[2])));
        }
    }
    for layer in layers.iter().filter(|l| l.first().is_some_and(|&v| lane_ranks[graph.rank[v]])) {
        let mut start = 0;
        while start < layer.len() {
            let key = bundle_of[layer[start]];
            let end = (start..layer.len()).find(|&i| bundle_of[layer[i]] != key).unwrap_or(layer.len());
            if let Some((a, b)) = key {
                let run = &layer[start..end];
                let steps = std::iter::once(0.0).chain(run.windows(2).map(|w| separation(w[0], w[1])));
                let offsets: Vec<f64> = steps
                    .scan(0.0, |sum, step| {
                        *sum += step;
                        Some(*sum)
                    })
                    .collect();
                let span = offsets[offsets.len() - 1];
                let left = match start {
                    0 => least(run[0]),
                    _ => x[layer[start - 1]] + separation(layer[start - 1], run[0]),
                };
                let right =
                    layer.get(end).map_or(f64::INFINITY, |&next| x[next] - separation(run[run.len() - 1], next));
                if right - span >= left {
                    let first = ((x[a] + x[b]) / 2.0 - span / 2.0).clamp(left, right - span);
                    for (&v, offset) in run.iter().zip(&offsets) {
                        x[v] = first + offset;
                    }
                }
            }
            start = end;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{layered, LayoutInput, LayoutNode, Spacing};
    use super::*;
    use crate::geometry::{intersects, segment_meets_box, Rect};

    #[test]
    fn only_edges_between_the_same_boxes_crowding_end_labels_are_bundled() {
        let label = Some((30.0, 14.0));
        let edges = [(0, 1), (1, 0), (1, 2), (2, 3), (3, 2), (4, 4), (4, 4), (5, 6), (6, 5), (5, 6), (7, 8), (8, 7)];
        let ends = [
            [None, label],
            [label, None],
            [label, None],
            [None; 2],
            [None; 2],
            [label, None],
            [label, None],
            [None; 2],
            [None, label],
            [None; 2],
            [label, None],
            [None; 2],
        ];
        // 0 and 1 in both directions, both labelled; three edges between 5 and 6, one labelled.
        // Not: 1 -> 2 alone, 2 and 3 without labels, a box's loops to itself, and 7 and 8 with
        // one labelled edge of two (its labels have a free side).
        let expected = [true, true, false, false, false, false, false, true, true, true, false, false];
        assert_eq!(bundled(&edges, &ends), expected.to_vec());
    }

    #[test]
    fn a_lane_rank_goes_only_where_a_bundle_joins_adjacent_ranks() {
        // Ranks 0 1 2 3: a bundle between ranks 1 and 2, another edge from 0 to 1.
        let mut rank = vec![0, 1, 2, 3];
        let edges = [(0, 1, false), (1, 2, false), (1, 2, true), (2, 3, false)];
        let lanes = insert_lane_ranks(&mut rank, &edges, &[false, true, true, false], false);
        assert_eq!(rank, vec![0, 1, 3, 4]);
        assert_eq!(lanes, vec![false, false, true, false, false]);
        // Doubled ranks: the rank between is the lane, nothing moves.
        let mut doubled = vec![0, 2, 4, 6];
        let lanes = insert_lane_ranks(&mut doubled, &edges, &[false, true, true, false], true);
        assert_eq!(doubled, vec![0, 2, 4, 6]);
        assert_eq!(lanes, vec![false, false, false, true, false, false, false]);
    }

    /// Two boxes over a third; `k` edges from 0 to 1 (every other one turned), each with an end
    /// label at both ends, and 1 -> 2 without.
    fn parallel(k: usize) -> LayoutInput {
        let nodes = vec![LayoutNode { width: 70.0, height: 50.0 }; 3];
        let mut edges: Vec<(usize, usize)> = (0..k).map(|i| if i % 2 == 0 { (0, 1) } else { (1, 0) }).collect();
        edges.push((1, 2));
        let mut end_labels = vec![[Some((64.0, 28.0)), Some((12.0, 14.0))]; k];
        end_labels.push([None; 2]);
        LayoutInput { nodes, edges, end_labels, ..Default::default() }
    }

    #[test]
    fn parallel_edges_fan_out_with_their_end_labels_beside_them() {
        // Also where a middle label doubles the ranks (then the rank between is the lane).
        for (k, middle) in [(2, false), (3, false), (4, false), (3, true)] {
            let mut input = parallel(k);
            if middle {
                input.labels = vec![None; k + 1];
                input.labels[k] = Some((50.0, 14.0));
            }
            let layout = layered(&input, Spacing::default());
            let boxes: Vec<Rect> = layout
                .positions
                .iter()
                .zip(&input.nodes)
                .map(|(p, n)| Rect { x: p.x, y: p.y, width: n.width, height: n.height })
                .collect();
            let mut labels = Vec::new();
            for e in 0..k {
                for end in 0..2 {
                    let at = layout.end_labels[e][end].expect("each bundled edge's end label has a place");
                    let (width, height) = input.end_labels[e][end].unwrap();
                    labels.push(Rect { x: at.x, y: at.y, width, height });
                }
            }
            for (i, label) in labels.iter().enumerate() {
                assert!(!boxes.iter().any(|b| intersects(*label, *b)), "{k} edges: label {i} on a box");
                assert!(!labels[i + 1..].iter().any(|l| intersects(*label, *l)), "{k} edges: labels overlap");
                for route in &layout.edges {
                    assert!(!route.windows(2).any(|s| segment_meets_box(s[0], s[1], *label)), "{k}: edge on label {i}");
                }
            }
            // A label at an end lies nearer that end's box than the other's.
            for e in 0..k {
                let (source, target) = input.edges[e];
                for (end, near, far) in [(0, source, target), (1, target, source)] {
                    let label = labels[2 * e + end];
                    let distance = |b: Rect| (label.y + label.height / 2.0 - (b.y + b.height / 2.0)).abs();
                    assert!(distance(boxes[near]) < distance(boxes[far]), "{k} edges: edge {e}'s end {end}");
                }
            }
            // The gap under box 1 keeps its height: the lane rank is only between 0 and 1.
            let gap = boxes[2].y - boxes[1].y - boxes[1].height;
            let labelled = if middle { 14.0 } else { 0.0 };
            assert_eq!(gap, Spacing::default().rank_gap + labelled, "{k} edges");
            // The bundle runs under its boxes (gathered in its lane), not off to a side.
            for route in &layout.edges[..k] {
                let lane = route[route.len() / 2].x;
                let centre = boxes[0].x + boxes[0].width / 2.0;
                assert!((lane - centre).abs() < k as f64 * 90.0, "{k} edges: lane at {lane}, boxes at {centre}");
            }
        }
    }

    #[test]
    fn a_bundle_runs_beside_its_boxes_among_other_edges() {
        let label = (40.0, 14.0);
        let mut far = 0;
        for seed in 0..30 {
            let nodes: Vec<LayoutNode> = (0..14).map(|_| LayoutNode { width: 60.0, height: 30.0 }).collect();
            let mut edges = crate::layout::tests::pseudo_random_edges(seed, 14, 20);
            // Boxes 0 and 1: a bundle of two edges and one neighbour each above and below.
            edges.retain(|&(a, b)| a.min(b) > 1);
            edges.extend([(0, 1), (1, 0), (2, 1), (0, 3), (4, 0), (1, 5)]);
            let mut end_labels = vec![[None; 2]; edges.len()];
            end_labels[edges.len() - 6] = [Some(label), Some(label)];
            end_labels[edges.len() - 5] = [Some(label), None];
            let input = LayoutInput { nodes, edges: edges.clone(), end_labels, ..Default::default() };
            let layout = layered(&input, Spacing::default());
            let centre = |v: usize| layout.positions[v].x + 30.0;
            let (low, high) = (centre(0).min(centre(1)), centre(0).max(centre(1)));
            for route in &layout.edges[edges.len() - 6..edges.len() - 4] {
                let middle = route[route.len() / 2].x;
                // Within the two lanes' room (a label and the gaps) of the boxes' centres.
                if middle < low - 60.0 || middle > high + 60.0 {
                    far += 1;
                }
            }
        }
        assert_eq!(far, 0, "bundled edges far from their boxes");
    }

    #[test]
    fn without_a_bundle_the_layout_ignores_end_labels() {
        let mut input = parallel(1);
        let plain = layered(&LayoutInput { end_labels: Vec::new(), ..input.clone() }, Spacing::default());
        let labelled = layered(&input, Spacing::default());
        assert_eq!(plain.positions, labelled.positions);
        assert_eq!(plain.edges, labelled.edges);
        assert!(labelled.end_labels.iter().flatten().all(Option::is_none));
        // Two edges, one without a label, between them: no bundle either.
        input.edges.push((0, 1));
        input.end_labels.push([None; 2]);
        let two = layered(&input, Spacing::default());
        assert_eq!(two.positions[1].y - two.positions[0].y, 50.0 + Spacing::default().rank_gap);
    }
}
