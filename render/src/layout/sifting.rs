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
        GlobalOrder { blocks, order: Order::new(layers, order.position.len()) }
    }

    /// Sifts every block once.
    pub fn sift_all(&mut self, graph: &Proper) {
        for b in 0..graph.blocks.len() {
            self.sift(b, graph);
        }
    }

    /// Moves block `b` to the place in its group's stretch of the order where its edges cross
    /// the fewest others.
    fn sift(&mut self, b: usize, graph: &Proper) {
        let members = &graph.blocks[b];
        let group = graph.group[members[0]];
        let from = self.blocks.iter().position(|&x| x == b).unwrap_or(0);
        self.blocks.remove(from);
        let start = self.blocks.iter().position(|&x| graph.group[graph.blocks[x][0]] == group).unwrap_or(from);
        let end = self.blocks.iter().rposition(|&x| graph.group[graph.blocks[x][0]] == group).map_or(from, |i| i + 1);
        // Put b first in its group's stretch, in the order and in each of its ranks.
        self.blocks.insert(start, b);
        for &v in members {
            let r = graph.rank[v];
            let layer = &mut self.order.layers[r];
            layer.remove(self.order.position[v]);
            let first = layer.iter().position(|&w| graph.group[w] >= group).unwrap_or(layer.len());
            layer.insert(first, v);
            self.order.renumber(r);
        }
        let (first_rank, last_rank) = (graph.rank[members[0]], graph.rank[members[members.len() - 1]]);
        let mut best_places: Vec<usize> = members.iter().map(|&v| self.order.position[v]).collect();
        let (mut cost, mut best_cost, mut best_index) = (0i64, 0i64, start);
        let mut best_distance = from.abs_diff(start);
        for index in start + 1..=end {
            let c = self.blocks[index];
            let other = &graph.blocks[c];
            let (c_first, c_last) = (graph.rank[other[0]], graph.rank[other[other.len() - 1]]);
            let (shared_first, shared_last) = (first_rank.max(c_first), last_rank.min(c_last));
            if shared_first <= shared_last {
                cost += self.swap_cost(b, c, shared_first, shared_last, graph);
                for r in shared_first..=shared_last {
                    let (v, w) = (members[r - first_rank], other[r - c_first]);
                    let (pv, pw) = (self.order.position[v], self.order.position[w]);
                    self.order.layers[r].swap(pv, pw);
                    self.order.position[v] = pw;
                    self.order.position[w] = pv;
                }
            }
            self.blocks.swap(index - 1, index);
            let distance = from.abs_diff(index);
            if cost < best_cost || (cost == best_cost && distance < best_distance) {
                (best_cost, best_index, best_distance) = (cost, index, distance);
                best_places = members.iter().map(|&v| self.order.position[v]).collect();
            }
        }
        if best_index != end {
            self.blocks.remove(end);
            self.blocks.insert(best_index, b);
            for (&v, &place) in members.iter().zip(&best_places) {
                let r = graph.rank[v];
                let layer = &mut self.order.layers[r];
                layer.remove(self.order.position[v]);
                layer.insert(place, v);
                self.order.renumber(r);
            }
        }
    }

    /// How many more crossings there are with block `c` before `b` than with `b` before `c`,
    /// where both are adjacent in ranks `first..=last`: only the edges at the two ends of that
    /// stretch can change.
    fn swap_cost(&self, b: usize, c: usize, first: usize, last: usize, graph: &Proper) -> i64 {
        let compare = |x: usize, y: usize, b_first: bool| {
            if x == y {
                return Ordering::Equal;
            }
            let (bx, by) = (graph.block_of[x], graph.block_of[y]);
            if bx == b && by == c {
                if b_first {
                    Ordering::Less
                } else {
                    Ordering::Greater
                }
            } else if bx == c && by == b {
                if b_first {
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
            let b_segments = block_segments(&graph.blocks[b], gap, graph);
            let c_segments = block_segments(&graph.blocks[c], gap, graph);
            for &(s_top, s_bottom) in &b_segments {
                for &(t_top, t_bottom) in &c_segments {
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
fn block_segments(members: &[usize], gap: usize, graph: &Proper) -> Vec<(usize, usize)> {
    let first = graph.rank[members[0]];
    let at = |r: usize| r.checked_sub(first).and_then(|i| members.get(i)).copied();
    if let Some(v) = at(gap) {
        graph.down[v].iter().map(|&w| (v, w)).collect()
    } else if let Some(v) = at(gap + 1) {
        graph.up[v].iter().map(|&u| (u, v)).collect()
    } else {
        Vec::new()
    }
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
            let mut layers = graph.initial_layers();
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
