//! The device diagrams of `samples/` generate WGSL that naga validates: the mean and bilateral
//! filters of Listings 15 and 16 and the findIndex reduction of Sec. 10.4.3.

use gudsl_model::{
    db::{RootDatabase, SourceFile, Workspace},
    hir::Semantics,
    library,
};

fn samples() -> (RootDatabase, Workspace) {
    let db = RootDatabase::default();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
    let mut files = library::library_files(&db);
    let mut stack = vec![root];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "gudsl") {
                let text = std::fs::read_to_string(&path).unwrap();
                files.push(SourceFile::new(&db, path.display().to_string(), text));
            }
        }
    }
    let workspace = Workspace::new(&db, files);
    (db, workspace)
}

#[test]
fn every_device_diagram_of_the_samples_generates_valid_wgsl() {
    let (db, workspace) = samples();
    let sema = Semantics::new(&db, workspace);
    let diagrams = gudsl_codegen::device_diagrams(&sema);
    let names: Vec<&str> = diagrams.iter().map(|d| d.fqn.as_str()).collect();
    for expected in ["AdFilterMean", "AdFindMinimumIndexFirstStage", "AdFindMinimumIndexSecondStage"] {
        assert!(names.contains(&expected), "{names:?}");
    }
    let mut failures = Vec::new();
    for diagram in diagrams {
        match gudsl_codegen::generate(&sema, diagram) {
            Ok(kernel) => {
                if std::env::var_os("SHOW_WGSL").is_some() {
                    println!("{}", kernel.wgsl);
                }
            }
            Err(errors) => failures.push(format!(
                "{}: {}",
                diagram.fqn,
                errors.iter().map(|e| format!("{:?} {}", e.range, e.message)).collect::<Vec<_>>().join("; ")
            )),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
