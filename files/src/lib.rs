//! The one way gudsl touches files on a model's behalf. A model names files — inputs, outputs,
//! the layout sidecar beside it — and a cloned repository of models is untrusted input, so
//! every such file is reached through a [`Folder`] the user named: paths resolve beneath it
//! (no `..`, absolute path or link leads out), only regular files are read, never more than a
//! caller's limit, opening never blocks (a FIFO, `/dev/stdin`), and writes go to a temporary
//! file renamed over the name, into output folders that hold no links.

mod error;
mod folder;
mod growing;
mod output;
#[cfg(test)]
mod tests;

pub use error::{FileError, Problem};
pub use folder::{lexical, Folder, Opened, Stamp};
pub use growing::Growing;
