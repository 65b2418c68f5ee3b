//! Every diagram of the samples (`samples/seed`, `framework`, `pipelines`) in one
//! workspace — the pipelines use the seed's classes. Shared by the crate's unit tests and the
//! reference pictures (`#[path]`-included: an integration test cannot see `cfg(test)` code).

use gudsl_model::{graph::Graph, AnalysisHost};

pub(crate) fn sample_graphs() -> Vec<Graph> {
    let samples = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
    let mut files = Vec::new();
    for dir in ["seed", "framework", "pipelines"] {
        let mut entries: Vec<_> = std::fs::read_dir(samples.join(dir)).unwrap().flatten().map(|e| e.path()).collect();
        entries.sort();
        for path in entries.into_iter().filter(|p| p.extension().is_some_and(|e| e == "gudsl")) {
            files.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
        }
    }
    let (host, files) = AnalysisHost::with_files(files);
    let analysis = host.analysis();
    files.iter().flat_map(|&f| analysis.graphs(f).unwrap().to_vec()).collect()
}

/// The sample diagram named `id` among `graphs`.
pub(crate) fn sample<'g>(graphs: &'g [Graph], id: &str) -> &'g Graph {
    graphs.iter().find(|g| g.id == id).unwrap_or_else(|| panic!("no sample diagram `{id}`"))
}
