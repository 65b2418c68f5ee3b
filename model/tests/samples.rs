//! Every document under `samples/` parses without a single diagnostic, and the seed corpus has
//! every listing of the dissertation.

use std::path::{Path, PathBuf};

fn gudsl_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        if path.is_dir() {
            gudsl_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "gudsl") {
            out.push(path);
        }
    }
}

fn samples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples")
}

#[test]
fn every_sample_parses_without_diagnostics() {
    let mut files = Vec::new();
    gudsl_files(&samples(), &mut files);
    files.sort();
    let mut failures = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).unwrap();
        let parse = gudsl_model::parse(&text);
        assert_eq!(parse.syntax_node().to_string(), text, "lossless: {}", file.display());
        for error in parse.errors() {
            let line = text[..u32::from(error.range.start()) as usize].lines().count().max(1);
            failures.push(format!("{}:{line}: {} {}", file.display(), error.code.as_str(), error.message));
        }
    }
    assert!(failures.is_empty(), "{} diagnostics:\n{}", failures.len(), failures.join("\n"));
}

/// The whole `samples/` folder as one workspace: every reference resolves, every rule holds.
#[test]
fn samples_check_clean_as_one_workspace() {
    let mut paths = Vec::new();
    gudsl_files(&samples(), &mut paths);
    paths.sort();
    let (host, files) = gudsl_model::AnalysisHost::with_files(
        paths.iter().map(|p| (p.display().to_string(), std::fs::read_to_string(p).unwrap())),
    );
    let analysis = host.analysis();
    let mut problems = Vec::new();
    for &file in &files {
        for d in analysis.diagnostics(file).unwrap().0 {
            problems.push(format!("{} {:?}: {} {}", analysis.file_path(file), d.range, d.code.as_str(), d.message));
        }
    }
    assert!(problems.is_empty(), "{} diagnostics:\n{}", problems.len(), problems.join("\n"));
}

#[test]
fn seed_has_every_listing() {
    // Any extension: Listing 25 is C++, kept as `listing25_*.cpp`.
    let names: Vec<String> = std::fs::read_dir(samples().join("seed"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    for listing in 1..=33 {
        let prefix = format!("listing{listing:02}_");
        assert!(names.iter().any(|n| n.starts_with(&prefix)), "no file for Listing {listing} ({prefix}*.gudsl)");
    }
    assert!(names.iter().any(|n| n.starts_with("main_full")), "no main_full.gudsl (Listings 30-33 as one file)");
    assert!(names.iter().any(|n| n.starts_with("appendixA_")), "no appendix A snippets");
    assert!(samples().join("seed/NOTES.md").is_file(), "samples/seed/NOTES.md records the repairs");
}
