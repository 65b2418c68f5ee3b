//! Uniform grids of boxes and of segments: which of thousands of them meet a box is asked for
//! each of thousands of candidate spots (free room for a node, a label's place), so each is
//! kept in the cells of a grid its bounding box touches and only those cells are searched.

use rustc_hash::FxHashMap;

use crate::geometry::{intersects, segment_meets_box, Point, Rect};

/// The side of a cell.
const CELL: f64 = 80.0;

/// How many cells an item may touch before it is kept apart and tested against every query (a
/// huge or non-finite one would otherwise fill the grid).
const MOST_CELLS: i64 = 4096;

/// Items bucketed by the grid cells their bounding boxes touch.
pub(crate) struct Cells<T> {
    cells: FxHashMap<(i64, i64), Vec<T>>,
    /// Items touching more than `MOST_CELLS` cells.
    apart: Vec<T>,
}

impl<T: Copy> Cells<T> {
    pub fn new() -> Cells<T> {
        Cells { cells: FxHashMap::default(), apart: Vec::new() }
    }

    /// Adds `item`, found by any box that meets `bounds`.
    pub fn insert(&mut self, bounds: Rect, item: T) {
        match cells_of(bounds) {
            Some(cells) => cells.for_each(|cell| self.cells.entry(cell).or_default().push(item)),
            None => self.apart.push(item),
        }
    }

    /// Whether an item near `r` (in a cell `r` touches, or kept apart) passes `test`.
    pub fn any(&self, r: Rect, test: impl Fn(&T) -> bool) -> bool {
        if self.apart.iter().any(&test) {
            return true;
        }
        match cells_of(r) {
            Some(mut cells) => cells.any(|cell| self.cells.get(&cell).is_some_and(|items| items.iter().any(&test))),
            None => self.cells.values().flatten().any(&test),
        }
    }
}

/// The grid cells a box touches, unless there are more than `MOST_CELLS` of them (or the box is
/// not finite).
fn cells_of(r: Rect) -> Option<impl Iterator<Item = (i64, i64)>> {
    let cell = |v: f64| (v / CELL).floor();
    let (x0, x1, y0, y1) = (cell(r.x), cell(r.x + r.width), cell(r.y), cell(r.y + r.height));
    let count = (x1 - x0 + 1.0) * (y1 - y0 + 1.0);
    if !(count.is_finite() && count <= MOST_CELLS as f64) {
        return None;
    }
    let (x0, x1, y0, y1) = (x0 as i64, x1 as i64, y0 as i64, y1 as i64);
    Some((x0..=x1).flat_map(move |x| (y0..=y1).map(move |y| (x, y))))
}

/// The box a segment spans.
pub(crate) fn span(a: Point, b: Point) -> Rect {
    Rect { x: a.x.min(b.x), y: a.y.min(b.y), width: (a.x - b.x).abs(), height: (a.y - b.y).abs() }
}

/// Line segments: which pass through a box.
pub(crate) struct Segments(Cells<(Point, Point)>);

impl Default for Segments {
    fn default() -> Segments {
        Segments(Cells::new())
    }
}

impl Segments {
    pub fn new(segments: impl Iterator<Item = (Point, Point)>) -> Segments {
        let mut cells = Cells::new();
        for (a, b) in segments {
            cells.insert(span(a, b), (a, b));
        }
        Segments(cells)
    }

    /// Whether a segment passes through `r`.
    pub fn meet(&self, r: Rect) -> bool {
        self.0.any(r, |&(a, b)| segment_meets_box(a, b, r))
    }
}

/// Boxes, each with its index (the order they were added in): which overlap a box.
pub(crate) struct Boxes(Cells<(usize, Rect)>, usize);

impl Boxes {
    pub fn new(boxes: impl IntoIterator<Item = Rect>) -> Boxes {
        let mut grid = Boxes(Cells::new(), 0);
        boxes.into_iter().for_each(|b| grid.push(b));
        grid
    }

    /// Adds a box; its index is the number of boxes added before it.
    pub fn push(&mut self, b: Rect) {
        self.0.insert(b, (self.1, b));
        self.1 += 1;
    }

    /// Whether a box other than those `except` names (by index) overlaps `r`.
    pub fn overlap(&self, r: Rect, except: &[usize]) -> bool {
        self.0.any(r, |&(i, b)| intersects(r, b) && !except.contains(&i))
    }

    /// Whether the segment from `a` to `b` meets a box other than those `except` names.
    pub fn meet_segment(&self, a: Point, b: Point, except: &[usize]) -> bool {
        self.0.any(span(a, b), |&(i, r)| segment_meets_box(a, b, r) && !except.contains(&i))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_what_a_scan_finds() {
        let rect = |x: f64, y: f64, width: f64, height: f64| Rect { x, y, width, height };
        let boxes = [rect(0.0, 0.0, 50.0, 30.0), rect(300.0, 10.0, 1000.0, 20.0), rect(-1e300, 0.0, 2e300, 1.0)];
        let grid = Boxes::new(boxes);
        for probe in [rect(40.0, 20.0, 5.0, 5.0), rect(700.0, 0.0, 5.0, 15.0), rect(0.0, 0.5, 5.0, 1.0)] {
            let scan = boxes.iter().any(|b| intersects(probe, *b));
            assert_eq!(grid.overlap(probe, &[]), scan, "{probe:?}");
        }
        // The huge box is kept apart, and found; one named in `except` is not.
        assert!(grid.overlap(rect(5e6, 0.2, 1.0, 0.5), &[]));
        assert!(!grid.overlap(rect(5e6, 0.2, 1.0, 0.5), &[2]));
        assert!(!grid.overlap(rect(100.0, 100.0, 10.0, 10.0), &[]));
        let p = |x: f64, y: f64| Point { x, y };
        for (from, to) in
            [(p(-10.0, 15.0), p(2000.0, 15.0)), (p(60.0, -5.0), p(60.0, 40.0)), (p(25.0, -50.0), p(25.0, -1.0))]
        {
            let scan = boxes.iter().any(|b| segment_meets_box(from, to, *b));
            assert_eq!(grid.meet_segment(from, to, &[]), scan, "{from:?} {to:?}");
        }
        assert!(!grid.meet_segment(p(-10.0, 15.0), p(40.0, 15.0), &[0]));
        let a = Point { x: 0.0, y: 0.0 };
        let segments =
            Segments::new([(a, Point { x: 0.0, y: 5000.0 }), (a, Point { x: f64::NAN, y: 1.0 })].into_iter());
        assert!(segments.meet(rect(-1.0, 4000.0, 2.0, 2.0)));
        assert!(!segments.meet(rect(10.0, 4000.0, 2.0, 2.0)));
    }
}
