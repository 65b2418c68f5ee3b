//! Writes the SVG of every diagram of a folder (as one workspace) to an output folder:
//! `cargo run -p gudsl-render --example render_samples -- samples /tmp/svg`.
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    graph::file_graphs,
};

fn walk(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            walk(&path, out);
        } else if path.extension().is_some_and(|e| e == "gudsl") {
            out.push(path);
        }
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let input = std::path::PathBuf::from(args.next().expect("usage: render_samples DIR OUT"));
    let output = std::path::PathBuf::from(args.next().expect("usage: render_samples DIR OUT"));
    std::fs::create_dir_all(&output).unwrap();
    let mut paths = Vec::new();
    walk(&input, &mut paths);
    paths.sort();
    let db = RootDatabase::default();
    let files: Vec<SourceFile> = paths
        .iter()
        .map(|p| SourceFile::new(&db, p.display().to_string(), std::fs::read_to_string(p).unwrap()))
        .collect();
    let ws = Workspace::new(&db, files.clone());
    for file in files {
        for graph in file_graphs(&db, ws, file) {
            std::fs::write(output.join(format!("{}.svg", graph.id)), gudsl_render::svg::render(graph)).unwrap();
        }
    }
}
