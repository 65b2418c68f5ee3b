//! Runs the semantic checks over a folder, as `gudsl check` will: `cargo run --example check -- DIR`.
use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    hir::file_diagnostics,
    text::{ColumnUnit, LineIndex},
};

fn main() {
    let dir = std::env::args().nth(1).expect("usage: check DIR");
    let mut paths: Vec<_> = walk(std::path::Path::new(&dir));
    paths.sort();
    let db = RootDatabase::default();
    let files: Vec<(SourceFile, String)> = paths
        .iter()
        .map(|p| {
            let text = std::fs::read_to_string(p).unwrap();
            (SourceFile::new(&db, p.display().to_string(), text.clone()), text)
        })
        .collect();
    let workspace = Workspace::new(&db, files.iter().map(|(f, _)| *f).collect());
    for (file, text) in &files {
        let index = LineIndex::new(text);
        for d in file_diagnostics(&db, workspace, *file) {
            let at = index.line_col(d.range.start(), ColumnUnit::Char);
            println!(
                "{}:{}:{}: {}[{}]: {}",
                file.path(&db),
                at.line + 1,
                at.col + 1,
                d.severity.as_str(),
                d.code.as_str(),
                d.message
            );
        }
    }
}

fn walk(dir: &std::path::Path) -> Vec<std::path::PathBuf> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            out.extend(walk(&path));
        } else if path.extension().is_some_and(|e| e == "gudsl") {
            out.push(path);
        }
    }
    out
}
