//! gudsl-render: diagram graphs → layout → SVG/PNG. This first part is the layered layout.

pub mod layout;
pub mod text;
