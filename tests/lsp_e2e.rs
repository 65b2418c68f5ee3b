//! Runs the pygls-driven end-to-end test of `gudsl lsp` (tests/lsp/e2e.py) against the built
//! binary. `.ci/run` installs pygls; locally: `pip install pygls==2.1.1`.

use std::process::Command;

#[test]
fn lsp_end_to_end_with_pygls() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let output = Command::new("python3")
        .arg(repo.join("tests/lsp/e2e.py"))
        .arg(env!("CARGO_BIN_EXE_gudsl"))
        .arg(repo.join("samples"))
        .output()
        .expect("python3 runs (the end-to-end test needs Python 3 with pygls)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stderr.contains("No module named 'pygls'"),
        "pygls is not installed: `python3 -m pip install pygls==2.1.1`"
    );
    assert!(output.status.success(), "e2e failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("1 passed, 0 failed"), "{stdout}");
}
