//! The page (or screen) a drawing is laid out for: a paper by name, an aspect ratio, a panel's
//! size, or none.

/// The page (or screen) a drawing is meant for, in the drawing's units (px, 1/96 in).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Page {
    pub width: f64,
    pub height: f64,
}

impl Default for Page {
    fn default() -> Page {
        Page::SCREEN
    }
}

impl Page {
    /// A landscape screen's diagram panel, 16:10.
    pub const SCREEN: Page = Page { width: 1600.0, height: 1000.0 };
    /// No page: the drawing as its ranks come, however wide or tall.
    pub const UNBOUNDED: Page = Page { width: f64::INFINITY, height: f64::INFINITY };

    /// A page of paper by name, upright (`A4`, `A3`, `Letter`; any case), or on its side with
    /// `-landscape` after the name; the drawing's units are px, 96 to the inch.
    pub fn paper(name: &str) -> Option<Page> {
        let lower = name.to_ascii_lowercase();
        let (paper, landscape) = match lower.strip_suffix("-landscape") {
            Some(paper) => (paper, true),
            None => (lower.as_str(), false),
        };
        let (width_mm, height_mm) = match paper {
            "a4" => (210.0, 297.0),
            "a3" => (297.0, 420.0),
            "letter" => (215.9, 279.4),
            _ => return None,
        };
        let page = Page { width: width_mm / 25.4 * 96.0, height: height_mm / 25.4 * 96.0 };
        Some(if landscape { page.turned() } else { page })
    }

    /// A page of width to height `width:height` as large as the screen (`SCREEN`'s area).
    pub fn with_aspect(width: f64, height: f64) -> Option<Page> {
        let aspect = width / height;
        if !(aspect.is_finite() && aspect > 0.0) {
            return None;
        }
        let area = Page::SCREEN.width * Page::SCREEN.height;
        Some(Page { width: (area * aspect).sqrt(), height: (area / aspect).sqrt() })
    }

    /// A page `width` × `height` px (a diagram panel's size), if both are numbers of at least
    /// one.
    pub fn of_size(width: f64, height: f64) -> Option<Page> {
        (width.is_finite() && height.is_finite() && width >= 1.0 && height >= 1.0).then_some(Page { width, height })
    }

    /// Whether a drawing `width` × `height` is to be made narrower: wider than the page, and
    /// wider for its height than `TOLERANCE` times the page's aspect ratio allows.
    pub(super) fn too_wide(self, width: f64, height: f64) -> bool {
        width > self.width && width / height > self.aspect() * TOLERANCE
    }

    /// Whether a drawing `width` × `height` is to be made less tall: taller than the page, and
    /// taller for its width than `TOLERANCE` times the page's aspect ratio allows.
    pub(super) fn too_tall(self, width: f64, height: f64) -> bool {
        height > self.height && width / height < self.aspect() / TOLERANCE
    }

    /// Width over height (1 for an unbounded page).
    pub fn aspect(self) -> f64 {
        let aspect = self.width / self.height;
        if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        }
    }

    /// The page turned on its side (for a layout drawn across and turned back).
    pub fn turned(self) -> Page {
        Page { width: self.height, height: self.width }
    }
}

/// How much earlier than the page's aspect ratio a drawing is reshaped: within this factor of
/// it, a drawing is left as its ranks come.
pub(super) const TOLERANCE: f64 = 1.3;
