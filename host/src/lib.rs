//! gudsl-host: the host side of GU-DSL's GPGPU extension (chapter 10.3): the device diagrams'
//! generated kernels compiled once and launched on the runtime's wgpu device with host arguments
//! and work ranges, as the framework's calc and calcRange nodes launch them; host activity
//! diagrams (`Main`) run by an interpreter that drives them (`run`); ToF pipelines modelled as
//! component-instance diagrams run on the runtime (`pipeline`); and what the command line and
//! the editor share about a model: its files' diagnostics (`diagnostics`) and the diagram a
//! name means (`named`).

pub mod access;
pub mod diagnostics;
pub mod launch;
pub mod named;
pub mod output;
pub mod pipeline;
pub mod run;

pub use launch::{Arg, LaunchError, Launcher, Number, WorkRange};
