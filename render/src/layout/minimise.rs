//! Crossing minimisation: which order each rank's vertices take. Median sweeps with
//! transposition from many starts, global sifting from the best of them, the order with the
//! fewest crossings kept (a shuffle's only where it saves enough: plain starts move less under an
//! edit).

use super::{order::Order, proper::Proper, sifting::GlobalOrder};

/// Reorders every rank of `layers` to reduce crossings: median sweeps with transposition from
/// `layers` and from seven more plain starts (breadth and depth first, down the edges and both
/// ways, each also mirrored) and from `SHUFFLED` shuffles of `layers` (`shuffled`:
/// deterministic), then global sifting of whole blocks from every plain start and the
/// `SIFTED_SHUFFLES` shuffles whose sweeps came out best. The best plain start's order wins
/// (`best_of`) unless the best shuffle's has enough fewer crossings (`worth_it`). The sweeps
/// end in local optima that differ much from start to start, so the many starts; sifting costs
/// more than the sweeps, and a start's sweeps predict where sifting ends, so only the best
/// shuffles are sifted. A large
/// graph gets fewer starts and passes (`Effort`), so that the work grows about linearly.
pub(super) fn minimise_crossings(layers: &mut [Vec<usize>], graph: &Proper, width: &dyn Fn(&[Vec<usize>]) -> f64) {
    let effort = Effort::for_graph(graph);
    let starts = [
        layers.to_vec(),
        graph.initial_layers(false, false),
        graph.initial_layers(true, true),
        graph.initial_layers(false, true),
    ];
    // Each start mirrored too: the sweeps break ties by position, so a mirror is a new start.
    let mirrored: Vec<Vec<Vec<usize>>> =
        starts.iter().map(|layers| layers.iter().map(|rank| rank.iter().rev().copied().collect()).collect()).collect();
    let plain: Vec<Vec<Vec<usize>>> = starts.into_iter().chain(mirrored).take(effort.plain).collect();
    let plain_count = plain.len();
    let mut swept: Vec<(Vec<Vec<usize>>, usize)> = Vec::new();
    for start in plain.into_iter().chain(shuffled(layers, graph, effort.shuffled)) {
        let (order, crossings) = sweeps(start, graph, &[]);
        if crossings == 0 {
            layers.clone_from_slice(&order);
            return;
        }
        swept.push((order, crossings));
    }
    // Every plain start and the shuffles whose sweeps came out best are sifted.
    let mut shuffles = swept.split_off(plain_count);
    shuffles.sort_by_key(|&(_, crossings)| crossings); // stable: the first of equals stays first
    swept.extend(shuffles.into_iter().take(effort.sifted_shuffles));
    let mut sifted: Vec<(Vec<Vec<usize>>, usize)> =
        swept.into_iter().map(|start| sifted(start, graph, effort.passes)).collect();
    let shuffles = sifted.split_off(plain_count);
    let plain = best_of(sifted, width);
    let chosen = match (plain, best_of(shuffles, width)) {
        (Some(plain), Some(shuffle)) if worth_it(shuffle.1, plain.1) => Some(shuffle),
        (Some(plain), _) => Some(plain),
        (None, shuffle) => shuffle,
    };
    if let Some((order, _)) = chosen {
        layers.clone_from_slice(&order);
    }
}

/// Of `candidates` (orders and their crossings, earliest start first) the one with the fewest
/// crossings; of equals the first, unless another makes the drawing (by `width`) `NARROWER`.
fn best_of(
    mut candidates: Vec<(Vec<Vec<usize>>, usize)>,
    width: &dyn Fn(&[Vec<usize>]) -> f64,
) -> Option<(Vec<Vec<usize>>, usize)> {
    let fewest = candidates.iter().map(|&(_, crossings)| crossings).min()?;
    candidates.retain(|&(_, crossings)| crossings == fewest);
    let widths: Vec<f64> = candidates.iter().map(|(order, _)| width(order)).collect();
    let narrowest = (0..widths.len()).min_by(|&a, &b| widths[a].total_cmp(&widths[b]))?;
    let chosen = if widths[narrowest] < NARROWER * widths[0] { narrowest } else { 0 };
    Some(candidates.swap_remove(chosen))
}

/// The order median sweeps find from the breadth-first start alone: a first idea of the
/// drawing, for measuring it.
pub(super) fn quick_order(graph: &Proper) -> Vec<Vec<usize>> {
    sweeps(graph.initial_layers(true, false), graph, &[]).0
}

/// The fewest crossings median sweeps find from the four plain starts.
pub(super) fn swept_crossings(graph: &Proper) -> usize {
    let starts = [(true, false), (false, false), (true, true), (false, true)];
    starts
        .iter()
        .map(|&(breadth_first, undirected)| sweeps(graph.initial_layers(breadth_first, undirected), graph, &[]).1)
        .min()
        .unwrap_or(0)
}

/// How much narrower (as a share of its width) another order with as few crossings must make
/// the drawing to be kept instead of the earliest start's.
const NARROWER: f64 = 0.95;

/// How many fewer crossings (as a share, or in all) the best shuffle's order must have to be
/// kept instead of the best plain start's: a shuffle's order is new after every edit, a plain
/// start's moves little, so a shuffle must be worth it — 5 % fewer, or 100 fewer where a
/// drawing has thousands (1 000 classes: 5 250 against 5 488, dot's 5 368).
const FEWER: f64 = 0.95;
const FEWER_IN_ALL: usize = 100;

/// Whether a shuffle's order with `shuffle` crossings is worth keeping over a plain start's
/// with `plain`.
fn worth_it(shuffle: usize, plain: usize) -> bool {
    shuffle as f64 <= FEWER * plain as f64 || shuffle + FEWER_IN_ALL <= plain
}

/// Random starts for crossing minimisation, and how many of them are sifted.
const SHUFFLED: usize = 16;
const SIFTED_SHUFFLES: usize = 4;

/// How many vertices (boxes and dummies) a graph may have for crossing minimisation to try
/// everything; beyond it the starts and sifting passes shrink in proportion.
const FULL_EFFORT: usize = 1000;

/// How many vertices make a graph huge: beyond, one sifting pass, and one way to rank
/// (`rank::candidates`).
pub(super) const HUGE: usize = 10 * FULL_EFFORT;

/// How many starts crossing minimisation sweeps from, how many it sifts, and how many
/// sifting passes it makes at most.
struct Effort {
    plain: usize,
    shuffled: usize,
    sifted_shuffles: usize,
    passes: usize,
}

impl Effort {
    /// Everything up to `FULL_EFFORT` vertices; beyond it each count shrinks by the share of
    /// `FULL_EFFORT` in the vertices (one plain start and two sifting passes at least; one pass
    /// beyond `HUGE` vertices).
    fn for_graph(graph: &Proper) -> Effort {
        let share = (FULL_EFFORT as f64 / graph.vertices().max(1) as f64).min(1.0);
        let scaled = |full: usize, least: usize| ((full as f64 * share).round() as usize).max(least);
        Effort {
            plain: scaled(8, 1),
            shuffled: scaled(SHUFFLED, 0),
            sifted_shuffles: scaled(SIFTED_SHUFFLES, 0),
            passes: scaled(12, if graph.vertices() > HUGE { 1 } else { 2 }),
        }
    }
}

/// `count` shuffles of every rank of `layers`: each vertex sorted by a pseudo-random key of
/// the shuffle's number and the vertex's identity (a box's index; a dummy's edge and place on
/// it), so that an edit shuffles the boxes it leaves alone as before.
fn shuffled(layers: &[Vec<usize>], graph: &Proper, count: usize) -> Vec<Vec<Vec<usize>>> {
    let mut identity: Vec<u64> = (0..graph.vertices() as u64).collect();
    for (e, chain) in graph.chains.iter().enumerate() {
        for (k, &v) in chain.iter().enumerate().filter(|&(_, &v)| v >= graph.boxes) {
            identity[v] = ((e as u64 + 1) << 32) | k as u64;
        }
    }
    (0..count as u64)
        .map(|shuffle| {
            let key = |v: usize| mix(identity[v] ^ mix(shuffle + 1));
            layers
                .iter()
                .map(|rank| {
                    let mut rank = rank.clone();
                    rank.sort_by_key(|&v| key(v));
                    rank
                })
                .collect()
        })
        .collect()
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `x`.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Global sifting from `order`: long edges move as a whole, which sweeps cannot do; then
/// transposition. The better of `order` and the result, with its crossings.
fn sifted((order, crossings): (Vec<Vec<usize>>, usize), graph: &Proper, passes: usize) -> (Vec<Vec<usize>>, usize) {
    if crossings == 0 {
        return (order, crossings);
    }
    let mut global = GlobalOrder::new(&Order::new(order.clone(), graph.vertices()), graph);
    let mut now = global.order.crossings(graph);
    for _ in 0..passes {
        global.sift_all(graph);
        let after = global.order.crossings(graph);
        if after >= now {
            break;
        }
        now = after;
    }
    let mut result = global.order;
    result.transpose(graph, false, &[]);
    let after = result.crossings(graph);
    if after < crossings {
        (result.layers, after)
    } else {
        (order, crossings)
    }
}

/// Median sweeps from `start`, alternately down and up, each followed by transposition (every
/// other pair of sweeps also swapping neighbours whose crossings tie, to leave a plateau), until
/// eight sweeps in a row bring nothing: the best order seen and its crossings. The `seated`
/// vertices (by vertex; none where empty) keep their order among themselves.
pub(super) fn sweeps(mut start: Vec<Vec<usize>>, graph: &Proper, seated: &[bool]) -> (Vec<Vec<usize>>, usize) {
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
        order.median_sweep(graph, sweep % 2 == 0, seated);
        order.transpose(graph, sweep % 4 >= 2, seated);
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

#[cfg(test)]
mod tests {
    use super::worth_it;

    #[test]
    fn a_shuffle_s_order_is_kept_for_5_percent_fewer_crossings_or_100_fewer() {
        assert!(worth_it(95, 100) && !worth_it(96, 100));
        assert!(worth_it(5250, 5488) && !worth_it(5400, 5488));
    }
}
