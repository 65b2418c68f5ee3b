//! gudsl-render: diagram graphs → a measured, laid-out scene (`scene`, with the layered layout
//! of `layout` and text measured in the bundled font) → writers that only draw it: SVG, the
//! layout JSON of the metrics script, and PNG through resvg.

mod geometry;
mod grid;
pub mod json;
pub mod layout;
pub mod pins;
pub mod png;
pub mod scene;
pub mod svg;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_arrange;
#[cfg(test)]
mod tests_bindings;
#[cfg(test)]
mod tests_memory;
pub mod text;
