//! Ranks too wide for the page split in two (unzipped): where the drawing would be wider than
//! its page allows for its height, the widest ranks' boxes alternate between two ranks, in the
//! order a breadth-first walk meets them, so that siblings stagger instead of standing in one
//! long row (a third rank would make a row no narrower: `Estimate::width`). Decided before crossing minimisation (which
//! then orders the new ranks as any others), on estimates corrected by quick layouts.

use super::minimise::quick_order;
use super::page::TOLERANCE;
use super::place::{self, Bands};
use super::proper::Proper;
use super::{Extent, LayoutNode, Spacing};

/// The room a long edge takes in a rank it passes, as a share of the gap between boxes.
const DUMMY_ROOM: f64 = 0.35;

/// How many times the split is measured and corrected.
const ROUNDS: usize = 4;

/// How much narrower than unsplit a split drawing must measure for splitting more to be tried.
const NARROWER: f64 = 0.9;

/// Splits ranks of `rank` (of boxes `nodes` under the oriented `edges`) in two where the
/// drawing would not fit `page` and be wider than `TOLERANCE` times the page's aspect ratio,
/// widest first, until it is about as wide as the page's aspect ratio asks. How wide the drawing of
/// some ranks comes out is estimated from the ranks' widths, then measured on a quick layout
/// (one start of median sweeps, coordinates), and the aim corrected by what was measured.
/// Edges still point down: a rank's parts take its place, the ranks below move down.
pub(super) fn unzip(
    rank: &mut [usize],
    edges: &[(usize, usize, bool)],
    nodes: &[LayoutNode],
    groups: &[Option<usize>],
    labelled: bool,
    spacing: Spacing,
) {
    let page = spacing.page;
    // No drawing is too wide for an unbounded page: not worth a quick layout.
    if !page.width.is_finite() {
        return;
    }
    let measure = |rank: &[usize]| quick_size(rank, edges, nodes, groups, spacing);
    let (width, height) = measure(rank);
    let unsplit_width = width;
    if !page.too_wide(width, height) {
        return;
    }
    let estimate = Estimate::new(rank, edges, nodes, labelled, spacing);
    // Boxes alternate between a rank's parts in the order a breadth-first walk meets them.
    let walk: Vec<usize> = Proper::new(groups, edges, rank)
        .initial_layers(true, false)
        .concat()
        .into_iter()
        .filter(|&v| v < nodes.len())
        .collect();
    // How far a size is from the page's aspect ratio, and how much larger than the drawing
    // unsplit: more ranks make more dummies, and a drawing can grow tall instead of narrow.
    let area = width * height;
    let off = |(w, h): (f64, f64)| (w / h / page.aspect()).ln().abs() + (w * h / area).ln().max(0.0);
    let (mut best, mut best_off) = (rank.to_vec(), off((width, height)));
    let mut aim = page.aspect();
    for _ in 0..ROUNDS {
        let parts = estimate.parts(aim);
        let split = split(rank, &parts, &walk);
        let (width, height) = measure(&split);
        let (guess_width, guess_height) = estimate.size(&parts);
        if off((width, height)) < best_off {
            (best, best_off) = (split, off((width, height)));
        }
        // Near enough; or splitting ranks does not make this drawing narrower (its width is
        // where its boxes sit, not how many a rank has), so more would only make it taller.
        let near = (width / height / page.aspect()).ln().abs() < TOLERANCE.ln() / 2.0;
        if near || width > unsplit_width * NARROWER {
            break;
        }
        // The estimate misjudged the drawing by `measured / guessed`: aim that much lower.
        aim *= (guess_width / guess_height) / (width / height);
    }
    rank.copy_from_slice(&best);
}

/// The ranks with rank `r` split into `parts[r]` consecutive ranks, its boxes alternating
/// between them in the order of `walk`.
fn split(rank: &[usize], parts: &[usize], walk: &[usize]) -> Vec<usize> {
    let offsets: Vec<usize> = parts
        .iter()
        .scan(0, |next, &k| {
            let at = *next;
            *next += k;
            Some(at)
        })
        .collect();
    let mut seen = vec![0; parts.len()];
    let mut split = rank.to_vec();
    for &v in walk {
        let r = rank[v];
        split[v] = offsets[r] + seen[r] % parts[r];
        seen[r] += 1;
    }
    split
}

/// The width and height of a quick layout of boxes ranked by `rank` (labels left out).
fn quick_size(
    rank: &[usize],
    edges: &[(usize, usize, bool)],
    nodes: &[LayoutNode],
    groups: &[Option<usize>],
    spacing: Spacing,
) -> (f64, f64) {
    let graph = Proper::new(groups, edges, rank);
    let layers = quick_order(&graph);
    let extent = Extent::of_boxes(nodes, graph.vertices());
    let x = place::horizontal(&graph, &layers, &extent, spacing);
    (place::right_edge(&x, &extent) + spacing.margin, Bands::new(&layers, &extent, spacing, &[]).total_height)
}

/// What the layout of the ranks will measure, roughly: per rank the boxes' width, how many of
/// them and how many long edges pass it, and its height.
struct Estimate {
    box_width: Vec<f64>,
    boxes: Vec<usize>,
    passing: Vec<usize>,
    height: Vec<f64>,
    /// Between two ranks: the gap (with a row of labels, if any).
    between: f64,
    spacing: Spacing,
}

impl Estimate {
    fn new(
        rank: &[usize],
        edges: &[(usize, usize, bool)],
        nodes: &[LayoutNode],
        labelled: bool,
        spacing: Spacing,
    ) -> Estimate {
        let ranks = rank.iter().max().map_or(0, |r| r + 1);
        let mut estimate = Estimate {
            box_width: vec![0.0; ranks],
            boxes: vec![0; ranks],
            passing: vec![0; ranks],
            height: vec![0.0; ranks],
            between: spacing.rank_gap + if labelled { 16.0 } else { 0.0 },
            spacing,
        };
        for (v, node) in nodes.iter().enumerate() {
            let r = rank[v];
            estimate.box_width[r] += node.width;
            estimate.boxes[r] += 1;
            estimate.height[r] = estimate.height[r].max(node.height);
        }
        for &(a, b, _) in edges.iter().filter(|e| e.0 != e.1) {
            (rank[a] + 1..rank[b]).for_each(|r| estimate.passing[r] += 1);
        }
        estimate
    }

    /// The width of rank `r` split in `k` parts. Split, its boxes stand in columns: each box's
    /// edge from above passes the parts above it straight, so a box and the edges beside it
    /// take half a box and half a gap each; more than two parts make it no narrower.
    fn width(&self, r: usize, k: usize) -> f64 {
        let gap = self.spacing.node_gap;
        let boxes = self.box_width[r] + self.boxes[r] as f64 * gap;
        let passing = self.passing[r] as f64 * gap * DUMMY_ROOM;
        if k == 1 {
            boxes + passing
        } else {
            boxes / 2.0 + passing
        }
    }

    /// How many parts each rank splits into for the drawing to be no wider than `aspect`
    /// (as estimated): the widest rank gets one more part while it is too wide.
    fn parts(&self, aspect: f64) -> Vec<usize> {
        let ranks = self.boxes.len();
        let mut parts = vec![1; ranks];
        let mut widths: Vec<f64> = (0..ranks).map(|r| self.width(r, 1)).collect();
        let mut height = self.size(&parts).1;
        let widest =
            |widths: &[f64]| (0..widths.len()).max_by(|&a, &b| widths[a].total_cmp(&widths[b]).then(b.cmp(&a)));
        while let Some(r) = widest(&widths) {
            let narrower = self.width(r, parts[r] + 1) < widths[r];
            if widths[r] / height <= aspect || parts[r] >= self.boxes[r] || !narrower {
                break;
            }
            parts[r] += 1;
            widths[r] = self.width(r, parts[r]);
            height += self.height[r] + self.between;
        }
        parts
    }

    /// The estimated width and height of the drawing with each rank split into `parts`.
    fn size(&self, parts: &[usize]) -> (f64, f64) {
        let width = (0..parts.len()).map(|r| self.width(r, parts[r])).fold(0.0, f64::max);
        let count: usize = parts.iter().sum();
        let height: f64 = (0..parts.len()).map(|r| self.height[r] * parts[r] as f64).sum::<f64>()
            + count.saturating_sub(1) as f64 * self.between;
        (width, height)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::layout::{layered, LayoutInput, Page};

    /// A root over `n` children: one wide rank.
    fn wide_tree(n: usize) -> LayoutInput {
        LayoutInput {
            nodes: vec![LayoutNode { width: 100.0, height: 40.0 }; n + 1],
            edges: (1..=n).map(|v| (0, v)).collect(),
            ..Default::default()
        }
    }

    #[test]
    fn a_wide_rank_staggers_into_several() {
        // Siblings alternate between two ranks: with their edges straight down, the second
        // rank's pass between the first's, so the row is half as wide (more ranks would not
        // make it narrower: each edge to a lower rank needs its own column in the upper ones).
        let input = wide_tree(60);
        let unbounded = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert!(unbounded.width / unbounded.height > 20.0);
        let layout = layered(&input, Spacing::default());
        assert!(layout.width < unbounded.width * 0.55, "{} x {}", layout.width, layout.height);
        assert!(layout.height < unbounded.height * 2.5, "{} x {}", layout.width, layout.height);
        // Every child still below the root, siblings alternating between the new ranks.
        let y = |v: usize| layout.positions[v].y;
        assert!((1..=60).all(|v| y(v) > y(0)));
        let rows: std::collections::BTreeSet<i64> = (1..=60).map(|v| y(v) as i64).collect();
        assert_eq!(rows.len(), 2, "{rows:?}");
    }

    #[test]
    fn a_drawing_that_fits_its_page_is_left_as_it_comes() {
        let input = wide_tree(8);
        let unbounded = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert_eq!(layered(&input, Spacing::default()), unbounded);
    }
}
