//! A drawing too tall for its page wrapped into columns side by side, as a newspaper is read:
//! its ranks cut into runs of about equal height (each cut where few edges cross, near where
//! it should be), each run moved right of the one before and up to the top. An edge a cut
//! divides leaves its run straight down, runs right under it into a corridor between the
//! columns, up, right over the next run and down into it; each such edge has lanes of its
//! own, nested so that they cross no more than they did. Across each column, stretches none of
//! its content uses are squeezed out (`squeeze`).

use std::collections::HashMap;

use super::place::Bands;
use super::squeeze::Squeeze;
use super::{Layout, LayoutInput, Point, Spacing};

/// Between the lanes of the edges a cut divides.
const LANE: f64 = 10.0;

/// The most columns a drawing is wrapped into.
const MOST_COLUMNS: usize = 64;

/// How much more page a layout before's columns may need than the best cut afresh, and stay.
const KEEP_WITHIN: f64 = 1.1;

/// Cuts that need at most this much more page than the least are as good (then fewer columns,
/// less area decide).
const NEARLY: f64 = 1.02;

/// Wraps `layout` (of `input`, its ranks in `bands`) into columns where it does not fit its
/// page and is taller than `TOLERANCE` times the page's aspect ratio allows; into as many as
/// show it largest on the page (the page a drawing needs is set by its width or its height,
/// whichever is further out of the page's proportion: so both its aspect ratio and its area
/// count). The columns a layout before started at the ranks `kept` stay while they need a page
/// at most `KEEP_WITHIN` times the best's: an edit does not tip the cuts. Returns the first rank
/// of each column after the first (none where the layout is not wrapped).
pub(super) fn wrap(
    layout: &mut Layout,
    input: &LayoutInput,
    bands: &Bands,
    spacing: Spacing,
    kept: &[usize],
) -> Vec<usize> {
    let page = spacing.page;
    let ranks = bands.top.len();
    if !page.too_tall(layout.width, layout.height) || ranks < 2 {
        return Vec::new();
    }
    let measured = Measured::new(layout, input, bands);
    let needs = |(width, height): (f64, f64)| (width / page.aspect()).max(height);
    let measure = |columns: Columns| (needs(columns.size(spacing)), columns);
    let candidates: Vec<(f64, Columns)> = (2..=ranks.min(MOST_COLUMNS))
        .flat_map(|count| [even_cuts(&measured, bands, count), balanced_cuts(bands, count)])
        .flatten()
        .filter_map(|first| Columns::cut(&measured, bands, first, spacing.node_gap))
        .map(measure)
        .collect();
    let best = chosen_columns(candidates, spacing);
    let kept = Some(kept)
        .filter(|cuts| !cuts.is_empty() && cuts.iter().all(|&r| r < ranks))
        .and_then(|cuts| Columns::cut(&measured, bands, [&[0], cuts].concat(), spacing.node_gap))
        .map(measure);
    let chosen = match (kept, best) {
        (Some(kept), Some(best)) if kept.0 <= KEEP_WITHIN * best.0 => Some(kept),
        (_, best) => best,
    };
    match chosen.filter(|(need, _)| *need < needs((layout.width, layout.height))) {
        Some((_, columns)) => {
            columns.apply(layout, input, &measured, spacing);
            columns.first[1..].to_vec()
        }
        None => Vec::new(),
    }
}

/// Of the `candidates` (each with the page it needs), one that needs the least page, or nearly
/// (within `NEARLY`): of those the fewest columns, then the least area.
fn chosen_columns(candidates: Vec<(f64, Columns)>, spacing: Spacing) -> Option<(f64, Columns)> {
    let least = candidates.iter().map(|c| c.0).fold(f64::INFINITY, f64::min);
    let area = |columns: &Columns| {
        let (width, height) = columns.size(spacing);
        width * height
    };
    candidates.into_iter().filter(|c| c.0 <= least * NEARLY).min_by(|a, b| {
        a.1.first.len().cmp(&b.1.first.len()).then(area(&a.1).total_cmp(&area(&b.1))).then(a.0.total_cmp(&b.0))
    })
}

/// What the layout holds per rank band: the stretches across it its content takes, and how
/// many edge segments cross the gap below each band.
struct Measured {
    /// Per band, the stretches across it that its boxes, labels and edges take.
    spans: Vec<Vec<(f64, f64)>>,
    crossing: Vec<usize>,
    /// The y that divides band `r` from band `r + 1` (the middle of the gap between them).
    divide: Vec<f64>,
}

impl Measured {
    fn new(layout: &Layout, input: &LayoutInput, bands: &Bands) -> Measured {
        let ranks = bands.top.len();
        let divide = (0..ranks - 1).map(|r| (bands.top[r] + bands.height[r] + bands.top[r + 1]) / 2.0).collect();
        let mut measured = Measured { spans: vec![Vec::new(); ranks], crossing: vec![0; ranks], divide };
        let mut reach = Vec::new();
        for (rect, _) in rects(layout, input) {
            reach.push((measured.band(rect.1 + rect.3 / 2.0), rect.0, rect.0 + rect.2));
        }
        for route in &layout.edges {
            reach.extend(route.iter().map(|p| (measured.band(p.y), p.x, p.x)));
            for s in route.windows(2) {
                let (a, b) = (measured.band(s[0].y), measured.band(s[1].y));
                (a.min(b)..a.max(b)).for_each(|gap| measured.crossing[gap] += 1);
            }
        }
        for (r, left, right) in reach {
            measured.spans[r].push((left, right));
        }
        measured
    }

    /// The band a y lies in (a y in a gap: the band it is nearer).
    fn band(&self, y: f64) -> usize {
        self.divide.partition_point(|&d| d < y)
    }
}

/// Each box's and each placed label's (x, y, width, height), with where it is kept in
/// `layout`: a box, a middle label or an end label (by edge and end).
fn rects(layout: &Layout, input: &LayoutInput) -> Vec<((f64, f64, f64, f64), Held)> {
    let mut all = Vec::new();
    for (v, at) in layout.positions.iter().enumerate() {
        all.push(((at.x, at.y, input.nodes[v].width, input.nodes[v].height), Held::Box(v)));
    }
    for (e, at) in layout.labels.iter().enumerate() {
        if let (Some(at), Some(Some((w, h)))) = (at, input.labels.get(e)) {
            all.push(((at.x, at.y, *w, *h), Held::Label(e)));
        }
    }
    for (e, ends) in layout.end_labels.iter().enumerate() {
        for (end, at) in ends.iter().enumerate() {
            let size = input.end_labels.get(e).and_then(|sizes| sizes[end]);
            if let (Some(at), Some((w, h))) = (at, size) {
                all.push(((at.x, at.y, w, h), Held::End(e, end)));
            }
        }
    }
    all
}

#[derive(Clone, Copy)]
enum Held {
    Box(usize),
    Label(usize),
    End(usize, usize),
}

/// The ranks cut into columns: per column its first band, where its content starts (left and
/// top), how wide (squeezed) and tall it is, and how many edges each cut divides.
struct Columns {
    first: Vec<usize>,
    squeeze: Vec<Squeeze>,
    left: Vec<f64>,
    top: Vec<f64>,
    width: Vec<f64>,
    height: Vec<f64>,
    /// Edges crossing each cut (between column `j` and `j + 1`).
    divided: Vec<usize>,
}

impl Columns {
    /// The ranks cut into columns before the bands `first`, each column measured and squeezed
    /// (none where a column would hold no band).
    fn cut(measured: &Measured, bands: &Bands, first: Vec<usize>, gap: f64) -> Option<Columns> {
        let (ranks, count) = (bands.top.len(), first.len());
        let bottom = |r: usize| bands.top[r] + bands.height[r];
        let mut columns = Columns {
            first,
            squeeze: Vec::new(),
            left: Vec::new(),
            top: Vec::new(),
            width: Vec::new(),
            height: Vec::new(),
            divided: Vec::new(),
        };
        for j in 0..count {
            let (from, to) = (columns.first[j], columns.first.get(j + 1).copied().unwrap_or(ranks));
            if from >= to {
                return None;
            }
            let squeeze = Squeeze::new(measured.spans[from..to].concat(), gap);
            let (left, width) = squeeze.extent()?;
            columns.squeeze.push(squeeze);
            columns.left.push(left);
            columns.top.push(bands.top[from]);
            columns.width.push(width);
            columns.height.push(bottom(to - 1) - bands.top[from]);
            if j + 1 < count {
                columns.divided.push(measured.crossing[to - 1]);
            }
        }
        Some(columns)
    }

    /// The room between column `j` and the next: the gap and a lane per divided edge.
    fn corridor(&self, j: usize, spacing: Spacing) -> f64 {
        spacing.node_gap + LANE * self.divided[j].saturating_sub(1) as f64
    }

    /// The lanes above and below the columns.
    fn channel(&self) -> f64 {
        LANE * self.divided.iter().copied().max().unwrap_or(0) as f64
    }

    fn size(&self, spacing: Spacing) -> (f64, f64) {
        let corridors: f64 = (0..self.divided.len()).map(|j| self.corridor(j, spacing)).sum();
        let width = self.width.iter().sum::<f64>() + corridors + 2.0 * spacing.margin;
        let tallest = self.height.iter().copied().fold(0.0, f64::max);
        (width, tallest + 2.0 * self.channel() + 2.0 * spacing.margin)
    }

    /// Moves each column into place and routes the divided edges between them.
    fn apply(&self, layout: &mut Layout, input: &LayoutInput, measured: &Measured, spacing: Spacing) {
        let top = spacing.margin + self.channel();
        let mut shift = Vec::with_capacity(self.first.len());
        let mut right = Vec::with_capacity(self.first.len());
        let mut x = spacing.margin;
        for j in 0..self.first.len() {
            shift.push(Point { x: x - self.left[j], y: top - self.top[j] });
            right.push(x + self.width[j]);
            x = right[j] + self.divided.get(j).map_or(0.0, |_| self.corridor(j, spacing));
        }
        let column = |y: f64| self.first.partition_point(|&f| f <= measured.band(y)) - 1;
        let moved = |p: Point, j: usize| Point { x: self.squeeze[j].at(p.x) + shift[j].x, y: p.y + shift[j].y };
        for ((x, y, _, h), held) in rects(layout, input) {
            let at = moved(Point { x, y }, column(y + h / 2.0));
            match held {
                Held::Box(v) => layout.positions[v] = at,
                Held::Label(e) => layout.labels[e] = Some(at),
                Held::End(e, end) => layout.end_labels[e][end] = Some(at),
            }
        }
        let lane = lanes(&layout.edges, &column, self.divided.len());
        for (e, route) in layout.edges.iter_mut().enumerate() {
            let mut wrapped = Vec::with_capacity(route.len());
            for (s, &p) in route.iter().enumerate() {
                let j = column(p.y);
                wrapped.push(moved(p, j));
                let Some(&(cut, i, k)) = lane.get(&(e, s)) else { continue };
                let next = route[s + 1];
                let (upper, lower) = if j == cut { (p, next) } else { (next, p) };
                let (upper, lower) = (moved(upper, cut), moved(lower, cut + 1));
                let low = top + self.height[cut] + LANE * (k - i) as f64;
                let across = right[cut] + spacing.node_gap / 2.0 + LANE * (k - 1 - i) as f64;
                let high = top - LANE * (i + 1) as f64;
                let mut detour = [
                    Point { x: upper.x, y: low },
                    Point { x: across, y: low },
                    Point { x: across, y: high },
                    Point { x: lower.x, y: high },
                ];
                if j != cut {
                    detour.reverse();
                }
                wrapped.extend(detour);
            }
            *route = wrapped;
        }
        (layout.width, layout.height) = self.size(spacing);
    }
}

/// The first band of each of `count` columns of about equal height, each cut at the gap with
/// the fewest crossing edges of the five nearest where it should be.
fn even_cuts(measured: &Measured, bands: &Bands, count: usize) -> Option<Vec<usize>> {
    let ranks = bands.top.len();
    let total = bands.top[ranks - 1] + bands.height[ranks - 1] - bands.top[0];
    let mut first = vec![0];
    for j in 1..count {
        let wanted = bands.top[0] + total * j as f64 / count as f64;
        // Gap g lies under band g: the one nearest `wanted`, after the last cut.
        let after = *first.last()?;
        let nearest = measured.divide.partition_point(|&d| d < wanted).min(ranks - 2).max(after);
        let gaps = nearest.saturating_sub(2).max(after)..=(nearest + 2).min(ranks - 2);
        let gap = gaps.min_by_key(|&g| (measured.crossing[g], g.abs_diff(nearest)))?;
        first.push(gap + 1);
    }
    Some(first)
}

/// The first band of each of `count` columns cut so that the tallest is as short as it can be
/// (none where fewer columns hold the bands as well).
fn balanced_cuts(bands: &Bands, count: usize) -> Option<Vec<usize>> {
    let ranks = bands.top.len();
    let bottom = |r: usize| bands.top[r] + bands.height[r];
    // The columns, each as many bands as fit under `tallest`, greedily.
    let cut = |tallest: f64| {
        let mut first = vec![0];
        for r in 1..ranks {
            if bottom(r) - bands.top[*first.last()?] > tallest {
                first.push(r);
            }
        }
        Some(first)
    };
    let (mut low, mut high) = (0.0, bottom(ranks - 1) - bands.top[0]);
    for _ in 0..50 {
        let middle = (low + high) / 2.0;
        if cut(middle).is_some_and(|first| first.len() <= count) {
            high = middle;
        } else {
            low = middle;
        }
    }
    cut(high).filter(|first| first.len() == count)
}

/// Per segment of `routes` one of the `cuts` divides (by edge and segment): its cut, its lane
/// among the cut's and how many the cut divides; lanes numbered left to right where the
/// segments leave the column above.
fn lanes(
    routes: &[Vec<Point>],
    column: &dyn Fn(f64) -> usize,
    cuts: usize,
) -> HashMap<(usize, usize), (usize, usize, usize)> {
    let mut divided: Vec<Vec<(f64, f64, usize, usize)>> = vec![Vec::new(); cuts];
    for (e, route) in routes.iter().enumerate() {
        for (s, pair) in route.windows(2).enumerate() {
            let (a, b) = (column(pair[0].y), column(pair[1].y));
            let (upper, lower) = if a < b { (pair[0], pair[1]) } else { (pair[1], pair[0]) };
            if a != b {
                divided[a.min(b)].push((upper.x, lower.x, e, s));
            }
        }
    }
    let mut lane = HashMap::new();
    for (j, segments) in divided.iter_mut().enumerate() {
        segments.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
        let k = segments.len();
        for (i, &(_, _, e, s)) in segments.iter().enumerate() {
            lane.insert((e, s), (j, i, k));
        }
    }
    lane
}

#[cfg(test)]
mod tests {
    use super::{balanced_cuts, Bands};
    use crate::geometry::{segment_meets_box, Rect};
    use crate::layout::{layered, Entry, LayoutInput, LayoutNode, Page, Remembered, RowEntry, Spacing};

    /// A flow of `n` steps down, with a loop back every ten steps and a label on each loop.
    fn long_flow(n: usize) -> LayoutInput {
        let mut edges: Vec<(usize, usize)> = (1..n).map(|v| (v - 1, v)).collect();
        edges.extend((10..n).step_by(10).map(|v| (v, v - 7)));
        let labels = edges.iter().map(|&(a, b)| (a > b).then_some((40.0, 14.0))).collect();
        LayoutInput {
            nodes: (0..n).map(|i| LayoutNode { width: 80.0 + (i % 3) as f64 * 20.0, height: 40.0 }).collect(),
            edges,
            labels,
            flow: true,
            ..Default::default()
        }
    }

    #[test]
    fn a_tall_flow_wraps_into_columns_near_the_page_s_aspect() {
        let input = long_flow(120);
        let unwrapped = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert!(unwrapped.width / unwrapped.height < 0.1);
        let layout = layered(&input, Spacing::default());
        let (aspect, target) = (layout.width / layout.height, Page::SCREEN.aspect());
        assert!(aspect > target / 1.5 && aspect < target * 1.5, "{} x {}", layout.width, layout.height);
        let rect = |v: usize| {
            let at = layout.positions[v];
            Rect { x: at.x, y: at.y, width: input.nodes[v].width, height: input.nodes[v].height }
        };
        for v in 0..input.nodes.len() {
            let r = rect(v);
            assert!(r.x >= 0.0 && r.y >= 0.0 && r.x + r.width <= layout.width && r.y + r.height <= layout.height);
        }
        for (e, route) in layout.edges.iter().enumerate() {
            let (a, b) = input.edges[e];
            // Each edge still joins its boxes' borders, and passes through no other box.
            assert_eq!(route[0].y, if a < b { rect(a).y + rect(a).height } else { rect(a).y });
            for v in (0..input.nodes.len()).filter(|&v| v != a && v != b) {
                assert!(!route.windows(2).any(|s| segment_meets_box(s[0], s[1], rect(v))), "edge {e} through box {v}");
            }
            assert!(route.iter().all(|p| p.x >= 0.0 && p.x <= layout.width && p.y >= 0.0 && p.y <= layout.height));
        }
        // Reading order: a later step is lower in its column or in a column further right.
        let columns: std::collections::BTreeSet<i64> = (0..input.nodes.len()).map(|v| rect(v).x as i64 / 400).collect();
        assert!(columns.len() >= 3, "{columns:?}");
        for v in 1..input.nodes.len() {
            let (p, q) = (layout.positions[v - 1], layout.positions[v]);
            assert!(q.y > p.y || q.x > p.x, "step {v} reads before step {}", v - 1);
        }
    }

    #[test]
    fn a_layout_keeps_the_columns_its_rows_remember_while_they_fit_nearly_as_well() {
        let input = long_flow(120);
        let fresh = layered(&input, Spacing::default());
        // The rows that start a column, and the rows with columns starting at `starts` instead.
        let starts = |rows: &[Vec<RowEntry>]| -> Vec<usize> {
            (0..rows.len()).filter(|&r| rows[r].iter().any(|e| e.0 == Entry::Column)).collect()
        };
        let starting = |starts: &[usize]| -> Vec<Vec<RowEntry>> {
            let mut rows = fresh.rows.clone();
            rows.iter_mut().for_each(|row| row.retain(|e| e.0 != Entry::Column));
            starts.iter().for_each(|&r| rows[r].push((Entry::Column, Some(0.0), None)));
            rows
        };
        let again = |starts: &[usize]| {
            let remembered = Remembered::of_rows(&starting(starts), input.nodes.len(), input.edges.len());
            layered(&LayoutInput { remembered, ..input.clone() }, Spacing::default())
        };
        let afresh = starts(&fresh.rows);
        assert!(afresh.len() >= 2, "{afresh:?}");
        assert_eq!(starts(&again(&afresh).rows), afresh);
        // Each column a row later than afresh: nearly as good, kept.
        let later: Vec<usize> = afresh.iter().map(|r| r + 1).collect();
        assert_eq!(starts(&again(&later).rows), later);
        // Two columns, the first of one row: the drawing would need a far larger page; cut afresh.
        assert_eq!(starts(&again(&[1]).rows), afresh);
    }

    #[test]
    fn balanced_cuts_make_the_tallest_column_as_short_as_it_can_be() {
        // Bands 10 tall, 10 apart, but the third 50 tall: of two columns the tallest is 90 tall
        // at best (the first three bands, or the last three).
        let height = vec![10.0, 10.0, 50.0, 10.0, 10.0];
        let mut top = vec![0.0];
        for h in &height[..4] {
            top.push(top.last().unwrap() + h + 10.0);
        }
        let bands = Bands { top, height, total_height: 140.0 };
        assert_eq!(balanced_cuts(&bands, 2), Some(vec![0, 3]));
        assert_eq!(balanced_cuts(&bands, 5), Some(vec![0, 1, 2, 3, 4]));
        assert_eq!(balanced_cuts(&bands, 6), None);
    }

    #[test]
    fn a_flow_that_fits_its_page_is_not_wrapped() {
        let input = long_flow(8);
        let unwrapped = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        assert_eq!(layered(&input, Spacing::default()), unwrapped);
        // Taller than the page, but the page is about as narrow: left as it comes.
        let input = long_flow(40);
        let unwrapped = layered(&input, Spacing { page: Page::UNBOUNDED, ..Spacing::default() });
        let narrow = Page { width: unwrapped.width / 2.0, height: unwrapped.height / 2.5 };
        assert_eq!(layered(&input, Spacing { page: narrow, ..Spacing::default() }), unwrapped);
    }
}
