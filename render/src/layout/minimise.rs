//! Crossing minimisation: which order each rank's vertices take. Median sweeps with
//! transposition from many starts, global sifting from the best of them, the order with the
//! fewest crossings kept (of equals, the narrowest drawing).

use super::{order::Order, proper::Proper, sifting::GlobalOrder};

/// Reorders every rank of `layers` to reduce crossings: median sweeps with transposition from
/// `layers` and from seven more starts (breadth and depth first, down the edges and both ways,
/// each also mirrored) and from `SHUFFLED` shuffles of `layers` (a fixed seed: deterministic),
/// then global sifting of whole blocks from the `SIFTED` best of those; the order with the fewest
/// crossings wins, of equals the one whose drawing is narrowest (by `width`), then the first.
/// The sweeps end in local optima that differ much from start to start, so the many starts;
/// sifting costs more than the sweeps, and a start's sweeps predict where sifting ends, so only
/// the best are sifted.
pub(super) fn minimise_crossings(layers: &mut [Vec<usize>], graph: &Proper, width: &dyn Fn(&[Vec<usize>]) -> f64) {
    let starts = [
        layers.to_vec(),
        graph.initial_layers(false, false),
        graph.initial_layers(true, true),
        graph.initial_layers(false, true),
    ];
    // Each start mirrored too: the sweeps break ties by position, so a mirror is a new start.
    let mirrored: Vec<Vec<Vec<usize>>> =
        starts.iter().map(|layers| layers.iter().map(|rank| rank.iter().rev().copied().collect()).collect()).collect();
    let mut swept: Vec<(Vec<Vec<usize>>, usize)> = Vec::new();
    for start in starts.into_iter().chain(mirrored).chain(shuffled(layers, SHUFFLED)) {
        let (order, crossings) = sweeps(start, graph);
        if crossings == 0 {
            layers.clone_from_slice(&order);
            return;
        }
        swept.push((order, crossings));
    }
    swept.sort_by_key(|(_, crossings)| *crossings); // stable: the first of equals stays first
    let sifted: Vec<(Vec<Vec<usize>>, usize)> =
        swept.into_iter().take(SIFTED).map(|start| sifted(start, graph)).collect();
    let fewest = sifted.iter().map(|(_, crossings)| *crossings).min();
    let best = sifted
        .into_iter()
        .filter(|(_, crossings)| Some(*crossings) == fewest)
        .map(|(order, _)| (width(&order), order))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    if let Some((_, best)) = best {
        layers.clone_from_slice(&best);
    }
}

/// The fewest crossings median sweeps find from the four plain starts.
pub(super) fn swept_crossings(graph: &Proper) -> usize {
    let starts = [(true, false), (false, false), (true, true), (false, true)];
    starts
        .iter()
        .map(|&(breadth_first, undirected)| sweeps(graph.initial_layers(breadth_first, undirected), graph).1)
        .min()
        .unwrap_or(0)
}

/// Random starts for crossing minimisation, and how many of all starts are sifted.
const SHUFFLED: usize = 16;
const SIFTED: usize = 8;

/// `count` shuffles of every rank of `layers`, from a fixed seed.
fn shuffled(layers: &[Vec<usize>], count: usize) -> Vec<Vec<Vec<usize>>> {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut below = |bound: usize| {
        state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (state >> 33) as usize % bound
    };
    (0..count)
        .map(|_| {
            let mut start = layers.to_vec();
            for rank in start.iter_mut() {
                for i in (1..rank.len()).rev() {
                    rank.swap(i, below(i + 1));
                }
            }
            start
        })
        .collect()
}

/// Global sifting from `order`: long edges move as a whole, which sweeps cannot do; then
/// transposition. The better of `order` and the result, with its crossings.
fn sifted((order, crossings): (Vec<Vec<usize>>, usize), graph: &Proper) -> (Vec<Vec<usize>>, usize) {
    if crossings == 0 {
        return (order, crossings);
    }
    let mut global = GlobalOrder::new(&Order::new(order.clone(), graph.vertices()), graph);
    let mut now = global.order.crossings(graph);
    for _ in 0..12 {
        global.sift_all(graph);
        let after = global.order.crossings(graph);
        if after >= now {
            break;
        }
        now = after;
    }
    let mut result = global.order;
    result.transpose(graph, false);
    let after = result.crossings(graph);
    if after < crossings {
        (result.layers, after)
    } else {
        (order, crossings)
    }
}

/// Median sweeps from `start`, alternately down and up, each followed by transposition (every
/// other pair of sweeps also swapping neighbours whose crossings tie, to leave a plateau), until
/// eight sweeps in a row bring nothing: the best order seen and its crossings.
fn sweeps(mut start: Vec<Vec<usize>>, graph: &Proper) -> (Vec<Vec<usize>>, usize) {
    for layer in start.iter_mut() {
        layer.sort_by_key(|&v| graph.group[v]);
    }
    let mut order = Order::new(start, graph.vertices());
    let mut best = order.layers.clone();
    let mut best_crossings = order.crossings(graph);
    let mut fruitless = 0;
    for sweep in 0..24 {
        if best_crossings == 0 || fruitless == 8 {
            break;
        }
        order.median_sweep(graph, sweep % 2 == 0);
        order.transpose(graph, sweep % 4 >= 2);
        let crossings = order.crossings(graph);
        if crossings < best_crossings {
            best_crossings = crossings;
            best.clone_from(&order.layers);
            fruitless = 0;
        } else {
            fruitless += 1;
        }
    }
    (best, best_crossings)
}
