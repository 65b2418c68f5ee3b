//! Runs the pygls-driven test of running a model from the editor (tests/lsp/run.py: code
//! lenses, Show generated WGSL, ▶ Run with progress and cancellation, the refusals) against the
//! built binary. Without a GPU adapter (`GUDSL_NO_GPU=1`) the runs themselves are skipped.

#[path = "support/pygls.rs"]
mod pygls;

#[test]
fn run_show_wgsl_and_cancel_from_the_editor_with_pygls() {
    let mut args = vec![pygls::repo().join("samples").into()];
    args.extend(pygls::gpu_args());
    pygls::run_script("run.py", &args);
}
