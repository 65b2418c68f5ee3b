//! Golden tests of the validation rules: `test_data/diagnostics/*.gudsl`, each a workspace of
//! one or more files (`//- name.gudsl` starts a file), the expected diagnostics in `.diag`
//! beside it. Files named `ok_*` must produce none; `err_*` must produce the code in their name.
//! `UPDATE_EXPECT=1 cargo test` rewrites the `.diag` files.

use std::path::Path;

use super::file_diagnostics;
use crate::{
    db::{RootDatabase, SourceFile, Workspace},
    text::{ColumnUnit, LineIndex},
};

/// Splits a fixture into `(path, text)` files.
pub(crate) fn split_fixture(text: &str) -> Vec<(String, String)> {
    let mut files: Vec<(String, String)> = Vec::new();
    for line in text.split_inclusive('\n') {
        if let Some(path) = line.strip_prefix("//- ") {
            files.push((path.trim().to_string(), String::new()));
        } else if let Some((_, body)) = files.last_mut() {
            body.push_str(line);
        } else {
            files.push(("main.gudsl".to_string(), line.to_string()));
        }
    }
    files
}

/// The diagnostics of a fixture, one line each: `path:line:col: severity[code]: message`.
pub(crate) fn render(text: &str) -> String {
    let db = RootDatabase::default();
    let files: Vec<(SourceFile, String)> =
        split_fixture(text).into_iter().map(|(path, body)| (SourceFile::new(&db, path, body.clone()), body)).collect();
    let library = crate::library::library_files(&db);
    let workspace = Workspace::new(&db, library.into_iter().chain(files.iter().map(|(f, _)| *f)).collect());
    let mut out = String::new();
    for (file, body) in &files {
        let index = LineIndex::new(body);
        for d in file_diagnostics(&db, workspace, *file) {
            let at = index.line_col(d.range.start(), ColumnUnit::Char);
            out.push_str(&format!(
                "{}:{}:{}: {}[{}]: {}\n",
                file.path(&db),
                at.line + 1,
                at.col + 1,
                d.severity.as_str(),
                d.code.as_str(),
                d.message
            ));
        }
    }
    out
}

/// The golden cases, `test_data/diagnostics/*.gudsl`, in name order.
pub(crate) fn cases() -> Vec<std::path::PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/diagnostics");
    let mut cases: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gudsl"))
        .collect();
    cases.sort();
    cases
}

#[test]
fn diagnostics_golden() {
    let cases = cases();
    assert!(cases.len() >= 20, "only {} cases", cases.len());
    let mut failures = Vec::new();
    for case in &cases {
        let name = case.file_stem().unwrap().to_string_lossy().into_owned();
        let actual = render(&std::fs::read_to_string(case).unwrap());
        if name.starts_with("ok_") && !actual.is_empty() {
            failures.push(format!("{name}: expected no diagnostics, got\n{actual}"));
        }
        if let Some(code) = name.strip_prefix("err_").and_then(|rest| rest.split('_').next()) {
            let code = code.to_uppercase();
            if !actual.contains(&format!("[{code}]")) {
                failures.push(format!("{name}: expected a {code} diagnostic, got\n{actual}"));
            }
        }
        let golden = case.with_extension("diag");
        if std::env::var_os("UPDATE_EXPECT").is_some() {
            std::fs::write(&golden, &actual).unwrap();
        } else if std::fs::read_to_string(&golden).unwrap_or_default() != actual {
            failures.push(format!("{name}: differs from {} (UPDATE_EXPECT=1 to accept):\n{actual}", golden.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
