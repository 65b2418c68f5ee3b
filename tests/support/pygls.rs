//! Runs a pygls-driven test script of `tests/lsp/` against the built binary and fails with its
//! output unless it reports "1 passed, 0 failed". `.ci/run` installs pygls; locally:
//! `python3 -m pip install pygls==2.1.1`.

#![allow(dead_code)] // each test binary takes what it needs

use std::{ffi::OsString, path::PathBuf, process::Command};

/// The repository's root.
pub fn repo() -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `python3 tests/lsp/<script> <gudsl> <args…>`, checked.
pub fn run_script(script: &str, args: &[OsString]) {
    let output = Command::new("python3")
        .arg(repo().join("tests/lsp").join(script))
        .arg(env!("CARGO_BIN_EXE_gudsl"))
        .args(args)
        .output()
        .expect("python3 runs (the test needs Python 3 with pygls)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stderr.contains("No module named 'pygls'"),
        "pygls is not installed: `python3 -m pip install pygls==2.1.1`"
    );
    assert!(output.status.success(), "{script} failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("1 passed, 0 failed"), "{stdout}");
}

/// `--no-gpu` when the tests run without an adapter (`GUDSL_NO_GPU`).
pub fn gpu_args() -> Vec<OsString> {
    std::env::var_os("GUDSL_NO_GPU").map(|_| OsString::from("--no-gpu")).into_iter().collect()
}
