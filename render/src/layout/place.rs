//! Coordinates: each vertex's x (Brandes–Köpf, `align`) with swimlanes shifted apart into
//! disjoint columns; each rank's band (top and height); the room each vertex takes.

use super::align;
use super::proper::Proper;
use super::{LayoutNode, Spacing};

/// How much room a vertex takes left and right of its centre line, and its height.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Extent {
    pub left: f64,
    pub right: f64,
    pub height: f64,
}

impl Extent {
    /// Each box's extent (centred on its line), then `vertices - boxes.len()` dummies' (none).
    pub(super) fn of_boxes(boxes: &[LayoutNode], vertices: usize) -> Vec<Extent> {
        let mut extent: Vec<Extent> =
            boxes.iter().map(|b| Extent { left: b.width / 2.0, right: b.width / 2.0, height: b.height }).collect();
        extent.resize(vertices, Extent::default());
        extent
    }
}

/// The least distance between the centres of `u` and its right neighbour `v` in a rank: long
/// edges run closer to each other than to boxes, and boxes keep the full gap.
pub(super) fn separation(graph: &Proper, extent: &[Extent], spacing: Spacing, u: usize, v: usize) -> f64 {
    let dummy = |v: usize| v >= graph.boxes;
    let gap = match (dummy(u), dummy(v)) {
        (true, true) => spacing.node_gap * 0.35,
        (false, false) => spacing.node_gap,
        _ => spacing.node_gap * 0.5,
    };
    extent[u].right + gap + extent[v].left
}

/// How far right the vertices at `x` reach (0 for none).
pub(super) fn right_edge(x: &[f64], extent: &[Extent]) -> f64 {
    x.iter().zip(extent).map(|(x, e)| x + e.right).fold(0.0, f64::max)
}

/// Centre x per vertex, the leftmost box edge at `spacing.margin`.
pub(super) fn horizontal(graph: &Proper, layers: &[Vec<usize>], extent: &[Extent], spacing: Spacing) -> Vec<f64> {
    let separation = |u: usize, v: usize| separation(graph, extent, spacing, u, v);
    let mut x = align::brandes_koepf(graph, layers, &separation);
    separate_groups(graph, &mut x, extent, spacing.node_gap * 2.0);
    let min_x = (0..graph.vertices()).map(|v| x[v] - extent[v].left).fold(f64::INFINITY, f64::min);
    for value in x.iter_mut() {
        *value += spacing.margin - min_x;
    }
    x
}

/// Shifts the swimlanes apart, in lane order, so their columns do not overlap; vertices of no
/// lane go with the last column.
fn separate_groups(graph: &Proper, x: &mut [f64], extent: &[Extent], gap: f64) {
    let lanes = graph.group.iter().filter(|&&g| g != usize::MAX).max().map_or(0, |g| g + 1);
    if lanes == 0 {
        return;
    }
    let mut offset = 0.0;
    let mut previous_right = f64::NEG_INFINITY;
    for lane in 0..lanes {
        let members: Vec<usize> = (0..graph.vertices()).filter(|&v| graph.group[v] == lane).collect();
        if members.is_empty() {
            continue;
        }
        let left = members.iter().map(|&v| x[v] - extent[v].left).fold(f64::INFINITY, f64::min);
        let right = members.iter().map(|&v| x[v] + extent[v].right).fold(f64::NEG_INFINITY, f64::max);
        let shift = if previous_right.is_finite() {
            (previous_right + gap - (left + offset)).max(0.0) + offset
        } else {
            offset
        };
        for &v in &members {
            x[v] += shift;
        }
        offset = shift;
        previous_right = right + shift;
    }
    for (value, &lane) in x.iter_mut().zip(&graph.group) {
        if lane == usize::MAX {
            *value += offset;
        }
    }
}

/// How far below where it would be a rank may be kept at its place in the layout before.
const KEPT_BELOW: f64 = 400.0;

/// The horizontal band of each rank: as tall as its tallest box. A lane rank (`bundle`) is
/// half the rank gap from its neighbours.
pub(super) struct Bands {
    pub top: Vec<f64>,
    pub height: Vec<f64>,
    /// Bottom of the last band plus the margin.
    pub total_height: f64,
}

impl Bands {
    pub fn new(layers: &[Vec<usize>], extent: &[Extent], spacing: Spacing, lane_ranks: &[bool]) -> Bands {
        let heights: Vec<f64> =
            layers.iter().map(|l| l.iter().map(|&v| extent[v].height).fold(0.0, f64::max)).collect();
        let lane = |r: usize| lane_ranks.get(r).copied().unwrap_or(false);
        let mut top = Vec::with_capacity(layers.len());
        let mut cursor = spacing.margin;
        for (r, h) in heights.iter().enumerate() {
            if r > 0 {
                cursor += if lane(r) || lane(r - 1) { spacing.rank_gap / 2.0 } else { spacing.rank_gap };
            }
            top.push(cursor);
            cursor += h;
        }
        Bands { top, height: heights, total_height: cursor + spacing.margin }
    }

    /// Each gap between ranks at least as tall as `room` asks (per gap, top down: the room of
    /// the tracks turning there), and each rank `kept` has a place for (the layout before's) at
    /// that place where the gap above leaves room for its tracks half as far apart, and nearest
    /// it where not; none further below than `KEPT_BELOW` (the place is the sidecar's: untrusted).
    /// The ranks below follow.
    pub fn settle(&mut self, room: &[f64], kept: &[Option<f64>]) {
        let Some(&last) = self.top.last() else { return };
        let original = self.top.clone();
        for r in 1..self.top.len() {
            // Moved as far as the rank above, and the gap grown where it must (a rank nothing
            // moves stays where it was to the last bit).
            let (gap, shift) = (original[r] - original[r - 1] - self.height[r - 1], self.top[r - 1] - original[r - 1]);
            let wanted = room.get(r - 1).copied().unwrap_or(0.0);
            let grown = |wanted: f64| original[r] + shift + (wanted - gap).max(0.0);
            let (natural, least) = (grown(wanted), grown(wanted / 2.0));
            self.top[r] = match kept.get(r).copied().flatten() {
                Some(at) if at <= natural + KEPT_BELOW => at.max(least - 1e-6),
                _ => natural,
            };
        }
        self.total_height += self.top[self.top.len() - 1] - last;
    }

    /// The whole height, and how much of it lies in the gaps between ranks.
    pub fn size(&self) -> (f64, f64) {
        let (first, last) = (self.top.first().copied().unwrap_or(0.0), self.top.last().copied().unwrap_or(0.0));
        let bottom = last + self.height.last().copied().unwrap_or(0.0);
        (self.total_height, bottom - first - self.height.iter().sum::<f64>())
    }

    /// The y of the middle of rank `r`.
    pub fn middle(&self, r: usize) -> f64 {
        self.top[r] + self.height[r] / 2.0
    }
}

#[cfg(test)]
mod tests {
    use super::Bands;

    /// Three ranks 20 tall, 10 apart.
    fn three() -> Bands {
        Bands { top: vec![0.0, 30.0, 60.0], height: vec![20.0; 3], total_height: 80.0 }
    }

    #[test]
    fn a_widened_gap_moves_the_ranks_below_it_down() {
        let mut bands = three();
        // The first gap wants 25, the second 5 (it has 10 already).
        bands.settle(&[25.0, 5.0], &[]);
        assert_eq!(bands.top, [0.0, 45.0, 75.0]);
        assert_eq!(bands.total_height, 95.0);
    }

    #[test]
    fn a_rank_stays_where_it_was_while_its_gap_s_tracks_fit_half_as_far_apart() {
        // The second rank was at 45: its gap now wants 40, 20 squeezed: it stays.
        let mut bands = three();
        bands.settle(&[40.0, 0.0], &[None, Some(45.0), None]);
        assert_eq!(bands.top, [0.0, 45.0, 75.0]);
        // Wanting 60 (30 squeezed): as near as it can be.
        let mut bands = three();
        bands.settle(&[60.0, 0.0], &[None, Some(45.0), None]);
        assert!((bands.top[1] - 50.0).abs() < 1e-5, "{:?}", bands.top);
        // Kept further down, where it was, but not far below where it would be.
        let mut bands = three();
        bands.settle(&[], &[None, Some(100.0), Some(1e7)]);
        assert_eq!(bands.top, [0.0, 100.0, 130.0]);
        assert_eq!(bands.total_height, 150.0);
    }
}
