//! Text measurement with the bundled DejaVu Sans (regular, bold, oblique): the font the SVG
//! names and the PNG rasterizer loads, so a label's measured width is the width it is drawn at,
//! on any machine.

use std::sync::OnceLock;

/// The font family the SVG names.
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// The bundled font files (`render/fonts/`, license beside them).
pub const REGULAR: &[u8] = include_bytes!("../fonts/DejaVuSans.ttf");
pub const BOLD: &[u8] = include_bytes!("../fonts/DejaVuSans-Bold.ttf");
pub const OBLIQUE: &[u8] = include_bytes!("../fonts/DejaVuSans-Oblique.ttf");

/// A font style.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Regular,
    Bold,
    Oblique,
    /// Regular, underlined (UML's static members).
    Underlined,
}

/// Advance widths of one face, in font units.
struct Face {
    units_per_em: f64,
    ascender: f64,
    descender: f64,
    /// Advances of the first 0x2500 code points (Latin, Greek, arrows, …); others use the face.
    table: Vec<u16>,
    data: &'static [u8],
}

impl Face {
    fn load(data: &'static [u8]) -> Face {
        let face = ttf_parser::Face::parse(data, 0).expect("the bundled font parses");
        let table = (0u32..0x2500)
            .map(|c| {
                char::from_u32(c)
                    .and_then(|ch| face.glyph_index(ch))
                    .and_then(|g| face.glyph_hor_advance(g))
                    .unwrap_or(0)
            })
            .collect();
        Face {
            units_per_em: face.units_per_em() as f64,
            ascender: face.ascender() as f64,
            descender: face.descender() as f64,
            table,
            data,
        }
    }

    fn advance(&self, ch: char) -> f64 {
        let code = ch as usize;
        if code < self.table.len() && self.table[code] != 0 {
            return self.table[code] as f64;
        }
        let face = ttf_parser::Face::parse(self.data, 0).expect("the bundled font parses");
        // Characters the font lacks are drawn by a fallback font; measure them as a box.
        face.glyph_index(ch).and_then(|g| face.glyph_hor_advance(g)).map_or(self.units_per_em * 0.6, f64::from)
    }
}

fn face(style: Style) -> &'static Face {
    static FACES: OnceLock<[Face; 3]> = OnceLock::new();
    let faces = FACES.get_or_init(|| [Face::load(REGULAR), Face::load(BOLD), Face::load(OBLIQUE)]);
    match style {
        Style::Regular | Style::Underlined => &faces[0],
        Style::Bold => &faces[1],
        Style::Oblique => &faces[2],
    }
}

/// The width of `text` at `size` pixels.
pub fn width(text: &str, size: f64, style: Style) -> f64 {
    let face = face(style);
    text.chars().map(|c| face.advance(c)).sum::<f64>() * size / face.units_per_em
}

/// The height of a line at `size` pixels (ascender to descender).
pub fn line_height(size: f64) -> f64 {
    let face = face(Style::Regular);
    (face.ascender - face.descender) * size / face.units_per_em
}

/// The distance from a line's top to its baseline at `size` pixels.
pub fn ascent(size: f64) -> f64 {
    let face = face(Style::Regular);
    face.ascender * size / face.units_per_em
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn measures_with_the_bundled_font() {
        let w = width("W", 12.0, Style::Regular);
        let i = width("i", 12.0, Style::Regular);
        assert!(w > 2.0 * i, "{w} vs {i}");
        // DejaVu Sans: the space advance is 651 of 2048 units.
        assert!((width(" ", 2048.0, Style::Regular) - 651.0).abs() < 1e-9);
        assert!(width("Image", 12.0, Style::Bold) > width("Image", 12.0, Style::Regular));
        assert_eq!(width("", 12.0, Style::Regular), 0.0);
        // Non-Latin text measures without panicking.
        assert!(width("Größe 😀 ✓", 12.0, Style::Oblique) > 0.0);
        assert!(line_height(12.0) > 12.0 && ascent(12.0) < line_height(12.0));
    }
}
