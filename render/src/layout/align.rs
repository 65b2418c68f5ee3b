//! Brandes–Köpf horizontal coordinates (Fast and Simple Horizontal Coordinate Assignment, 2001,
//! with the block-graph compaction of its 2020 erratum): each vertex aligned with a median
//! neighbour into vertical blocks, in the four combinations of up/down and left/right, each
//! compacted under the separation constraints, then balanced. Long edges come out straight.

use std::collections::HashSet;

use super::proper::Proper;

/// Centre x per vertex; `separation(u, v)` is the least distance between the centres of `u` and
/// its right neighbour `v`.
pub(super) fn brandes_koepf(
    graph: &Proper,
    layers: &[Vec<usize>],
    separation: &dyn Fn(usize, usize) -> f64,
) -> Vec<f64> {
    let conflicts = type1_conflicts(graph, layers);
    let mut candidates: Vec<(Vec<f64>, bool)> = Vec::with_capacity(4);
    for downward in [true, false] {
        for leftmost in [true, false] {
            let mut oriented: Vec<Vec<usize>> =
                if downward { layers.to_vec() } else { layers.iter().rev().cloned().collect() };
            if !leftmost {
                oriented.iter_mut().for_each(|layer| layer.reverse());
            }
            let neighbours = if downward { &graph.up } else { &graph.down };
            let root = vertical_alignment(&oriented, neighbours, &conflicts, downward, graph.vertices());
            let oriented_separation = |u: usize, v: usize| if leftmost { separation(u, v) } else { separation(v, u) };
            let mut xs = compact(&oriented, &root, &oriented_separation);
            if !leftmost {
                xs.iter_mut().for_each(|x| *x = -*x);
            }
            candidates.push((xs, leftmost));
        }
    }
    balance(&candidates)
}

/// Segments (upper, lower) that cross a segment between two dummies: these never align, so long
/// edges stay straight.
fn type1_conflicts(graph: &Proper, layers: &[Vec<usize>]) -> HashSet<(usize, usize)> {
    let dummy = |v: usize| v >= graph.boxes;
    let mut position = vec![0; graph.vertices()];
    for layer in layers {
        for (i, &v) in layer.iter().enumerate() {
            position[v] = i;
        }
    }
    let mut conflicts = HashSet::new();
    for pair in layers.windows(2) {
        let (upper, lower) = (&pair[0], &pair[1]);
        let (mut k0, mut scanned) = (0, 0);
        for (l, &v) in lower.iter().enumerate() {
            let inner = if dummy(v) { graph.up[v].iter().copied().find(|&u| dummy(u)) } else { None };
            if inner.is_none() && l + 1 != lower.len() {
                continue;
            }
            let k1 = inner.map_or(upper.len(), |u| position[u]);
            for &w in &lower[scanned..=l] {
                for &u in &graph.up[w] {
                    if (position[u] < k0 || k1 < position[u]) && !(dummy(u) && dummy(w)) {
                        conflicts.insert((u, w));
                    }
                }
            }
            scanned = l + 1;
            k0 = k1;
        }
    }
    conflicts
}

/// The root (first vertex) of each vertex's block: vertices aligned with their median neighbour
/// in the previous rank of `layers`, without two alignments crossing.
fn vertical_alignment(
    layers: &[Vec<usize>],
    neighbours: &[Vec<usize>],
    conflicts: &HashSet<(usize, usize)>,
    downward: bool,
    vertices: usize,
) -> Vec<usize> {
    let mut position = vec![0; vertices];
    for layer in layers {
        for (i, &v) in layer.iter().enumerate() {
            position[v] = i;
        }
    }
    let mut root: Vec<usize> = (0..vertices).collect();
    let mut aligned = vec![false; vertices];
    for layer in layers.iter().skip(1) {
        let mut taken: Option<usize> = None;
        for &v in layer {
            let mut adjacent = neighbours[v].clone();
            if adjacent.is_empty() {
                continue;
            }
            adjacent.sort_by_key(|&u| position[u]);
            let d = adjacent.len();
            for m in [(d - 1) / 2, d / 2] {
                let u = adjacent[m];
                let segment = if downward { (u, v) } else { (v, u) };
                if !aligned[v] && !conflicts.contains(&segment) && taken.is_none_or(|t| t < position[u]) {
                    root[v] = root[u];
                    aligned[v] = true;
                    taken = Some(position[u]);
                }
            }
        }
    }
    root
}

/// Block positions: each block as far left as its left neighbours allow, then pulled right
/// towards its right neighbours where there is room.
fn compact(layers: &[Vec<usize>], root: &[usize], separation: &dyn Fn(usize, usize) -> f64) -> Vec<f64> {
    let vertices = root.len();
    // The block graph: left block -> right block, with the separation the pair needs.
    let mut left_of: Vec<Vec<(usize, f64)>> = vec![Vec::new(); vertices];
    let mut right_of: Vec<Vec<(usize, f64)>> = vec![Vec::new(); vertices];
    let mut indegree = vec![0usize; vertices];
    for layer in layers {
        for pair in layer.windows(2) {
            let (a, b) = (root[pair[0]], root[pair[1]]);
            let gap = separation(pair[0], pair[1]);
            right_of[a].push((b, gap));
            left_of[b].push((a, gap));
            indegree[b] += 1;
        }
    }
    let roots: Vec<usize> = (0..vertices).filter(|&v| root[v] == v).collect();
    let mut topological = Vec::with_capacity(roots.len());
    let mut ready: Vec<usize> = roots.iter().copied().filter(|&r| indegree[r] == 0).collect();
    while let Some(r) = ready.pop() {
        topological.push(r);
        for &(s, _) in &right_of[r] {
            indegree[s] -= 1;
            if indegree[s] == 0 {
                ready.push(s);
            }
        }
    }
    debug_assert_eq!(topological.len(), roots.len(), "alignments crossed: the block graph has a cycle");
    let mut xs = vec![0.0f64; vertices];
    for &r in &topological {
        xs[r] = left_of[r].iter().map(|&(p, gap)| xs[p] + gap).fold(0.0, f64::max);
    }
    for &r in topological.iter().rev() {
        let limit = right_of[r].iter().map(|&(s, gap)| xs[s] - gap).fold(f64::INFINITY, f64::min);
        if limit.is_finite() {
            xs[r] = xs[r].max(limit);
        }
    }
    (0..vertices).map(|v| xs[root[v]]).collect()
}

/// Aligns the four candidates to the narrowest one (left ones by their left end, right ones by
/// their right end) and takes, per vertex, the mean of the two middle values.
fn balance(candidates: &[(Vec<f64>, bool)]) -> Vec<f64> {
    let extent = |xs: &[f64]| {
        let min = xs.iter().copied().fold(f64::INFINITY, f64::min);
        let max = xs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (min, max)
    };
    let narrowest = candidates
        .iter()
        .map(|(xs, _)| extent(xs))
        .min_by(|a, b| (a.1 - a.0).total_cmp(&(b.1 - b.0)))
        .unwrap_or((0.0, 0.0));
    let shifted: Vec<Vec<f64>> = candidates
        .iter()
        .map(|(xs, leftmost)| {
            let (min, max) = extent(xs);
            let delta = if *leftmost { narrowest.0 - min } else { narrowest.1 - max };
            xs.iter().map(|x| x + delta).collect()
        })
        .collect();
    (0..shifted[0].len())
        .map(|v| {
            let mut values: Vec<f64> = shifted.iter().map(|xs| xs[v]).collect();
            values.sort_by(f64::total_cmp);
            (values[1] + values[2]) / 2.0
        })
        .collect()
}
