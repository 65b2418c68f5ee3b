//! Runs the pygls-driven test of the graph view over LSP (tests/lsp/graph.py: `gudsl/diagrams`
//! and `gudsl/graph` on the dissertation's listings, each graph's SVG equal to `gudsl render`'s,
//! ids and geometry across edits, the refusals) against the built binary.

#[path = "support/pygls.rs"]
mod pygls;

#[test]
fn diagrams_and_graphs_are_served_to_any_client_with_pygls() {
    pygls::run_script("graph.py", &[pygls::repo().into()]);
}
