//! Golden tests of the parser: one document a file under `test_data/parser/{ok,err}`, the
//! expected tree and errors beside it in `.rast`. `UPDATE_EXPECT=1 cargo test` rewrites them.

use std::path::{Path, PathBuf};

use super::{debug_dump, parse};

fn test_data(dir: &str) -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("test_data/parser").join(dir);
    let mut files: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap_or_else(|e| panic!("{}: {e}", root.display()))
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|ext| ext == "gudsl"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no test documents in {}", root.display());
    files
}

/// Compares `actual` with the `.rast` file beside `case`, or rewrites it under UPDATE_EXPECT.
fn check_golden(case: &Path, actual: &str) -> Result<(), String> {
    let golden = case.with_extension("rast");
    if std::env::var_os("UPDATE_EXPECT").is_some() {
        std::fs::write(&golden, actual).unwrap();
        return Ok(());
    }
    let expected = std::fs::read_to_string(&golden).unwrap_or_default();
    if expected == actual {
        Ok(())
    } else {
        Err(format!(
            "{} differs from the parse (run with UPDATE_EXPECT=1 to accept):\n{}",
            golden.display(),
            first_difference(&expected, actual)
        ))
    }
}

fn first_difference(expected: &str, actual: &str) -> String {
    for (i, (e, a)) in expected.lines().zip(actual.lines()).enumerate() {
        if e != a {
            return format!("line {}:\n  expected: {e}\n  actual:   {a}", i + 1);
        }
    }
    format!("lengths differ: {} vs {} lines", expected.lines().count(), actual.lines().count())
}

#[test]
fn ok_documents_parse_without_errors() {
    let mut failures = Vec::new();
    for case in test_data("ok") {
        let text = std::fs::read_to_string(&case).unwrap();
        let parsed = parse(&text);
        assert_eq!(parsed.syntax_node().to_string(), text, "lossless: {}", case.display());
        if !parsed.errors().is_empty() {
            failures.push(format!("{}: unexpected errors {:?}", case.display(), parsed.errors()));
        }
        if let Err(diff) = check_golden(&case, &debug_dump(&parsed)) {
            failures.push(diff);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Each broken document has exactly one fault, so it must give exactly one error, and the
/// golden tree shows the rest of the document parsed into the right nodes.
#[test]
fn err_documents_report_one_error_each() {
    let mut failures = Vec::new();
    for case in test_data("err") {
        let text = std::fs::read_to_string(&case).unwrap();
        let parsed = parse(&text);
        assert_eq!(parsed.syntax_node().to_string(), text, "lossless: {}", case.display());
        if parsed.errors().len() != 1 {
            failures.push(format!(
                "{}: expected exactly one error, got {}:\n{}",
                case.display(),
                parsed.errors().len(),
                parsed.errors().iter().map(|e| format!("  {:?} {}", e.range, e.message)).collect::<Vec<_>>().join("\n")
            ));
        }
        if let Err(diff) = check_golden(&case, &debug_dump(&parsed)) {
            failures.push(diff);
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
