//! SVG → PNG with resvg, using only the bundled fonts, so a PNG looks the same on every machine.

use std::sync::{Arc, OnceLock};

use resvg::{tiny_skia, usvg};

use crate::text;

/// Why an SVG could not be rasterized.
#[derive(Debug)]
pub enum PngError {
    /// The SVG did not parse.
    Svg(String),
    /// The drawing has no area, or is too large to allocate.
    Size,
    /// PNG encoding failed.
    Encode(String),
}

impl std::fmt::Display for PngError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PngError::Svg(e) => write!(f, "invalid SVG: {e}"),
            PngError::Size => write!(f, "the drawing has no area or is too large"),
            PngError::Encode(e) => write!(f, "PNG encoding failed: {e}"),
        }
    }
}

fn options() -> &'static usvg::Options<'static> {
    static OPTIONS: OnceLock<usvg::Options<'static>> = OnceLock::new();
    OPTIONS.get_or_init(|| {
        let mut db = usvg::fontdb::Database::new();
        for font in [text::REGULAR, text::BOLD, text::OBLIQUE] {
            db.load_font_data(font.to_vec());
        }
        db.set_sans_serif_family(text::FONT_FAMILY);
        usvg::Options { fontdb: Arc::new(db), font_family: text::FONT_FAMILY.to_string(), ..usvg::Options::default() }
    })
}

/// Parses an SVG as resvg sees it (used by tests to check every SVG is valid).
pub fn parse(svg: &str) -> Result<usvg::Tree, PngError> {
    usvg::Tree::from_str(svg, options()).map_err(|e| PngError::Svg(e.to_string()))
}

/// The scale exported pictures are drawn at (`gudsl render --format png`, `gudsl/graph`'s PNG, a
/// pipeline's plots): twice the scene's size, for sharp text.
pub const EXPORT_SCALE: f32 = 2.0;

/// Rasterizes an SVG at `scale` ([`EXPORT_SCALE`] for pictures a user keeps) into PNG bytes.
pub fn to_png(svg: &str, scale: f32) -> Result<Vec<u8>, PngError> {
    let tree = parse(svg)?;
    let size = tree.size().to_int_size().scale_by(scale).ok_or(PngError::Size)?;
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height()).ok_or(PngError::Size)?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(&tree, tiny_skia::Transform::from_scale(scale, scale), &mut pixmap.as_mut());
    pixmap.encode_png().map_err(|e| PngError::Encode(e.to_string()))
}
