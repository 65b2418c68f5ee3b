//! gudsl-render: diagram graphs → layered layout → SVG, with text measured in the bundled font.

pub mod layout;
pub mod png;
pub mod svg;
pub mod text;
