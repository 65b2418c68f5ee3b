//! Runs the pygls-driven test of running a model from the editor (tests/lsp/run.py: code
//! lenses, Show generated WGSL, ▶ Run with progress and cancellation, the refusals) against the
//! built binary. Without a GPU adapter (`GUDSL_NO_GPU=1`) the runs themselves are skipped.

use std::process::Command;

#[test]
fn run_show_wgsl_and_cancel_from_the_editor_with_pygls() {
    let repo = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut command = Command::new("python3");
    command.arg(repo.join("tests/lsp/run.py")).arg(env!("CARGO_BIN_EXE_gudsl")).arg(repo.join("samples"));
    if std::env::var_os("GUDSL_NO_GPU").is_some() {
        command.arg("--no-gpu");
    }
    let output = command.output().expect("python3 runs (the test needs Python 3 with pygls)");
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(
        !stderr.contains("No module named 'pygls'"),
        "pygls is not installed: `python3 -m pip install pygls==2.1.1`"
    );
    assert!(output.status.success(), "run.py failed:\n{stdout}\n{stderr}");
    assert!(stdout.contains("1 passed, 0 failed"), "{stdout}");
}
