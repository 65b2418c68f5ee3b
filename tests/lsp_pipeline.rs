//! Runs the pygls-driven test of running ToF pipelines from the editor (tests/lsp/pipeline.py:
//! the ▶ Run pipeline lenses, each sample run with progress and equal to `gudsl run`'s outputs,
//! a cancelled run, the plan's and the files' problems as diagnostics, the refusals) against
//! the built binary. Without a GPU adapter (`GUDSL_NO_GPU=1`) the pipelines run on the CPU
//! reference.

#[path = "support/pygls.rs"]
mod pygls;

#[test]
fn pipelines_run_and_cancel_from_the_editor_with_pygls() {
    let mut args = vec![pygls::repo().into()];
    args.extend(pygls::gpu_args());
    pygls::run_script("pipeline.py", &args);
}
