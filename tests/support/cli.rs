//! What the end-to-end tests of the binary share: the built `gudsl`, paths in the repository,
//! and a fresh scratch folder per test.

#![allow(dead_code)] // each test binary takes what it needs

use std::{path::PathBuf, process::Command};

/// The built binary, ready for arguments.
pub fn gudsl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gudsl"))
}

/// `path` (relative to the repository root) as an absolute path.
pub fn repo(path: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path).to_string_lossy().into_owned()
}

/// An empty folder of its own for the test `name` of this test binary and process.
pub fn temp_dir(name: &str) -> PathBuf {
    let binary = env!("CARGO_CRATE_NAME");
    let dir = std::env::temp_dir().join(format!("gudsl-{binary}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}
