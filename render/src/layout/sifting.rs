//! Global sifting (Bachmaier, Brandenburg, Brunner, Hübner: Global k-level crossing reduction,
//! 2011): one left-to-right order of blocks (a box, or all dummies of one long edge) that every
//! rank follows; each block in turn moves to the place in that order where its edges cross the
//! fewest others. Moving a long edge as a whole is what per-rank heuristics cannot do.

use std::cmp::Ordering;

use super::order::Order;
use super::proper::Proper;

pub(super) struct GlobalOrder {
    blocks: Vec<usize>,
    pub order: Order,
    /// Place of each block in `blocks`.
    index: Vec<usize>,
    /// First and last rank per block.
    span: Vec<(usize, usize)>,
    /// Lane per block.
    lane: Vec<usize>,
}

impl GlobalOrder {
    /// The block order nearest to `order`: blocks by group, then by their mean relative place in
    /// the ranks they cross.
    pub fn new(order: &Order, graph: &Proper) -> GlobalOrder {
        let place = |b: usize| {
            let members = &graph.blocks[b];
            members
                .iter()
                .map(|&v| (order.position[v] as f64 + 0.5) / order.layers[graph.rank[v]].len() as f64)
                .sum::<f64>()
                / members.len() as f64
        };
        let mut keyed: Vec<(usize, f64, usize)> =
            (0..graph.blocks.len()).map(|b| (graph.group[graph.blocks[b][0]], place(b), b)).collect();
        keyed.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)).then(a.2.cmp(&b.2)));
        let blocks: Vec<usize> = keyed.into_iter().map(|(_, _, b)| b).collect();
        let mut layers = vec![Vec::new(); order.layers.len()];
        for &b in &blocks {
            for &v in &graph.blocks[b] {
                layers[graph.rank[v]].push(v);
            }
        }
        let span = graph.blocks.iter().map(|m| (graph.rank[m[0]], graph.rank[m[m.len() - 1]])).collect();
        let lane = graph.blocks.iter().map(|m| graph.group[m[0]]).collect();
        let mut index = vec![0; blocks.len()];
        for (i, &b) in blocks.iter().enumerate() {
            index[b] = i;
        }
        GlobalOrder { blocks, order: Order::new(layers, order.position.len()), index, span, lane }
    }

    /// Sifts every block once.
    pub fn sift_all(&mut self, graph: &Proper) {
        for b in 0..graph.blocks.len() {
            self.sift(b, graph);
        }
    }

    /// Moves block `b` to the place in its lane's stretch of the order where its edges cross
    /// the fewest others. While `b` is sifted its vertices stay where they were in the ranks:
    /// `b` is placed virtually, before `blocks[place]`, and compared with others by that.
    pub(super) fn sift(&mut self, b: usize, graph: &Proper) {
        let from = self.index[b];
        self.blocks.remove(from);
        self.renumber_blocks(from);
        // The order is sorted by lane: b's lane is one stretch of it.
        let lane = self.lane[b];
        let start = self.blocks.partition_point(|&x| self.lane[x] < lane);
        let end = self.blocks.partition_point(|&x| self.lane[x] <= lane);
        // The cost changes only where b passes a block it shares ranks with: between two such
        // blocks every place costs the same, and the one nearest where b was is the best of them.
        let (mut cost, mut best_cost, mut best_place) = (0i64, 0i64, start);
        let mut best_distance = from.abs_diff(start);
        let mut consider = |cost: i64, low: usize, high: usize| {
            let place = from.clamp(low, high);
            let distance = from.abs_diff(place);
            if cost < best_cost || (cost == best_cost && distance < best_distance) {
                (best_cost, best_place, best_distance) = (cost, place, distance);
            }
        };
        let mut low = start;
        for c in self.sharing_ranks(b, lane, graph) {
            let place = self.index[c];
            consider(cost, low, place);
            let (first, last) = self.shared_ranks(b, c).expect("a block met in b's ranks shares them");
            cost += self.swap_cost(b, c, place, first, last, graph);
            low = place + 1;
        }
        consider(cost, low, end);
        self.blocks.insert(best_place, b);
        self.renumber_blocks(best_place.min(from));
        // Each rank follows the order: b's vertex goes after the vertices of earlier blocks.
        for &v in &graph.blocks[b] {
            let r = graph.rank[v];
            let old = self.order.position[v];
            let layer = &mut self.order.layers[r];
            layer.remove(old);
            let new = layer.partition_point(|&w| self.index[graph.block_of[w]] < best_place);
            layer.insert(new, v);
            let low = old.min(new);
            for (i, &w) in layer[low..=old.max(new)].iter().enumerate() {
                self.order.position[w] = low + i;
            }
        }
    }

    /// The blocks of `lane` other than `b` in the ranks `b` crosses, in the order.
    fn sharing_ranks(&self, b: usize, lane: usize, graph: &Proper) -> Vec<usize> {
        let (first, last) = self.span[b];
        let mut met: Vec<usize> = self.order.layers[first..=last]
            .iter()
            .flatten()
            .map(|&w| graph.block_of[w])
            .filter(|&c| c != b && self.lane[c] == lane)
            .collect();
        met.sort_unstable_by_key(|&c| self.index[c]);
        met.dedup();
        met
    }

    /// Recomputes the place in the order of every block from `start` on.
    fn renumber_blocks(&mut self, start: usize) {
        for (i, &x) in self.blocks.iter().enumerate().skip(start) {
            self.index[x] = i;
        }
    }

    /// The ranks both blocks cross, if any.
    fn shared_ranks(&self, b: usize, c: usize) -> Option<(usize, usize)> {
        let ((b_first, b_last), (c_first, c_last)) = (self.span[b], self.span[c]);
        let shared = (b_first.max(c_first), b_last.min(c_last));
        (shared.0 <= shared.1).then_some(shared)
    }

    /// How many more crossings there are with block `c` before `b` than with `b` before `c`,
    /// where `b` is sifted past `c = blocks[place]` and both are in ranks `first..=last`: only
    /// the edges at the two ends of that stretch can change.
    fn swap_cost(&self, b: usize, c: usize, place: usize, first: usize, last: usize, graph: &Proper) -> i64 {
        let compare = |x: usize, y: usize, b_first: bool| {
            if x == y {
                return Ordering::Equal;
            }
            let (bx, by) = (graph.block_of[x], graph.block_of[y]);
            let b_before = |other: usize| if other == c { b_first } else { self.index[other] > place };
            if bx == b {
                if b_before(by) {
                    Ordering::Less
                } else {
                    Ordering::Greater
                }
            } else if by == b {
                if b_before(bx) {
                    Ordering::Greater
                } else {
                    Ordering::Less
                }
            } else {
                self.order.position[x].cmp(&self.order.position[y])
            }
        };
        let mut cost = 0i64;
        let gaps = [first.checked_sub(1), Some(last).filter(|&l| l + 1 < self.order.layers.len())];
        for gap in gaps.into_iter().flatten() {
            for (s_top, s_bottom) in block_segments(&graph.blocks[b], gap, graph) {
                for (t_top, t_bottom) in block_segments(&graph.blocks[c], gap, graph) {
                    for (b_first, sign) in [(true, -1), (false, 1)] {
                        let (above, below) = (compare(s_top, t_top, b_first), compare(s_bottom, t_bottom, b_first));
                        if above != Ordering::Equal && below != Ordering::Equal && above != below {
                            cost += sign;
                        }
                    }
                }
            }
        }
        cost
    }
}

/// The segments of a block between rank `gap` and rank `gap + 1`.
fn block_segments<'g>(members: &[usize], gap: usize, graph: &'g Proper) -> impl Iterator<Item = (usize, usize)> + 'g {
    let first = graph.rank[members[0]];
    let at = |r: usize| r.checked_sub(first).and_then(|i| members.get(i)).copied();
    let (below, above) = (at(gap), at(gap + 1));
    let down = below.into_iter().flat_map(move |v| graph.down[v].iter().map(move |&w| (v, w)));
    let up = above.filter(|_| below.is_none()).into_iter().flat_map(move |v| graph.up[v].iter().map(move |&u| (u, v)));
    down.chain(up)
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::layout::order::tests::proper;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        /// Every block move predicts its own effect: the total never grows, and each rank
        /// stays the order of the blocks in it.
        #[test]
        fn sifting_never_adds_crossings(
            n in 2usize..14,
            raw in prop::collection::vec((0usize..14, 0usize..14), 1..30),
            lanes in prop::collection::vec(0usize..3, 14),
        ) {
            let edges: Vec<(usize, usize)> = raw.into_iter().map(|(a, b)| (a % n, b % n)).collect();
            let groups: Vec<Option<usize>> = lanes[..n].iter().map(|&g| Some(g)).collect();
            let graph = proper(n, &edges, &groups);
            let mut layers = graph.initial_layers(true, false);
            for layer in layers.iter_mut() {
                layer.sort_by_key(|&v| graph.group[v]);
            }
            let mut sifted = GlobalOrder::new(&Order::new(layers, graph.vertices()), &graph);
            let mut crossings = sifted.order.crossings(&graph);
            for b in 0..graph.blocks.len() {
                sifted.sift(b, &graph);
                let now = sifted.order.crossings(&graph);
                prop_assert!(now <= crossings, "sifting block {} raised crossings {} -> {}", b, crossings, now);
                crossings = now;
                for layer in &sifted.order.layers {
                    let places: Vec<usize> = layer
                        .iter()
                        .map(|&v| sifted.blocks.iter().position(|&x| x == graph.block_of[v]).unwrap())
                        .collect();
                    prop_assert!(places.windows(2).all(|w| w[0] < w[1]), "rank {:?} out of block order", layer);
                    let lanes: Vec<usize> = layer.iter().map(|&v| graph.group[v]).collect();
                    prop_assert!(lanes.windows(2).all(|w| w[0] <= w[1]));
                }
            }
        }
    }
}
