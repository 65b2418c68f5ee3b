//! Runs the pygls-driven end-to-end test of `gudsl lsp` (tests/lsp/e2e.py) against the built
//! binary.

#[path = "support/pygls.rs"]
mod pygls;

#[test]
fn lsp_end_to_end_with_pygls() {
    pygls::run_script("e2e.py", &[pygls::repo().join("samples").into()]);
}
