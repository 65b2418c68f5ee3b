//! Runs the pygls-driven test of running ToF pipelines from the editor (tests/lsp/pipeline.py:
//! the ▶ Run pipeline lenses, each sample run with progress and equal to `gudsl run`'s outputs,
//! a cancelled run, the plan's and the files' problems as diagnostics, the refusals) against
//! the built binary. Without a GPU adapter (`GUDSL_NO_GPU=1`) the pipelines run on the CPU
//! reference. The second test drives the live preview (tests/lsp/preview.py).

#[path = "support/pygls.rs"]
mod pygls;

#[test]
fn pipelines_run_and_cancel_from_the_editor_with_pygls() {
    let mut args = vec![pygls::repo().into()];
    args.extend(pygls::gpu_args());
    pygls::run_script("pipeline.py", &args);
}

/// The live preview (tests/lsp/preview.py): on, a preview of the first frame; θ edited, only what
/// is downstream of motion compensation runs and the compensated error changes; a comment runs
/// nothing; an error stops it and its fix resumes it; the first of two quick edits is
/// cancelled; off, edits run nothing.
#[test]
fn the_live_preview_follows_edits_with_pygls() {
    let mut args = vec![pygls::repo().into()];
    args.extend(pygls::gpu_args());
    pygls::run_script("preview.py", &args);
}
