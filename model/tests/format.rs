//! Formatter properties over every clean document we have (samples, parser goldens, a generated
//! workspace): the output parses clean, keeps every token and comment in order, and formatting
//! it again changes nothing.

use gudsl_model::{format::format, parse, SyntaxKind};

fn tokens(text: &str) -> Vec<(SyntaxKind, String)> {
    parse(text)
        .syntax_node()
        .descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .filter(|t| t.kind() != SyntaxKind::WHITESPACE)
        .map(|t| (t.kind(), t.text().trim_end().to_string()))
        .collect()
}

fn corpus() -> Vec<(String, String)> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    let mut dirs = vec![root.join("../samples"), root.join("test_data/parser/ok")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "gudsl") {
                out.push((path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    for file in gudsl_model::synth::workspace(8, 2_000) {
        out.push((file.path, file.text));
    }
    out
}

#[test]
fn formatting_keeps_every_token_and_comment_and_is_idempotent() {
    let corpus = corpus();
    assert!(corpus.len() > 40);
    for (path, text) in corpus {
        let once = format(&parse(&text)).unwrap_or_else(|| panic!("{path} has syntax errors"));
        assert!(parse(&once).errors().is_empty(), "{path}: formatted text does not parse:\n{once}");
        assert_eq!(tokens(&once), tokens(&text), "{path}: tokens changed");
        let twice = format(&parse(&once)).unwrap();
        assert_eq!(twice, once, "{path}: not idempotent");
    }
}
