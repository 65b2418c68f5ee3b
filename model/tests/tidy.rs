//! Source hygiene (ARCHITECTURE.md, "Invariants"): every Rust file of the project opens with a
//! `//!` line saying what it does and, unless generated, has at most 600 lines; ARCHITECTURE.md
//! names every top-level module of every crate; the modules of `hir` depend on each other
//! without circles.

use std::{
    collections::{BTreeMap, BTreeSet},
    path::{Path, PathBuf},
};

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            if name != "target" && !name.starts_with('.') && name != "corpus" && name != "artifacts" {
                rust_files(&path, out);
            }
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_rust_file_starts_with_a_module_doc() {
    let files = project_rust_files();
    assert!(files.len() > 10);
    let undocumented: Vec<String> = files
        .iter()
        .filter(|f| !std::fs::read_to_string(f).unwrap().starts_with("//!"))
        .map(|f| f.display().to_string())
        .collect();
    assert!(undocumented.is_empty(), "files without a leading `//!` line:\n{}", undocumented.join("\n"));
}

fn project_rust_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for dir in ["codegen", "host", "model", "server", "render", "runtime", "tests", "fuzz"] {
        rust_files(&root.join(dir), &mut files);
    }
    files
}

#[test]
fn no_hand_written_file_is_longer_than_600_lines() {
    let long: Vec<String> = project_rust_files()
        .iter()
        .filter(|f| !f.ends_with("generated.rs"))
        .filter_map(|f| {
            let lines = std::fs::read_to_string(f).unwrap().lines().count();
            (lines > 600).then(|| format!("{} ({lines} lines)", f.display()))
        })
        .collect();
    assert!(long.is_empty(), "split these by job:\n{}", long.join("\n"));
}

#[test]
fn architecture_names_every_top_level_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let architecture = std::fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
    let mut missing = Vec::new();
    for krate in ["codegen", "host", "model", "server", "render", "runtime"] {
        for entry in std::fs::read_dir(root.join(krate).join("src")).unwrap().flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            if ["lib.rs", "main.rs"].contains(&name.as_str()) {
                continue;
            }
            let written = if entry.path().is_dir() { format!("`{name}/`") } else { format!("`{name}`") };
            if !architecture.contains(&written) {
                missing.push(format!("{krate}/src/{name} (as {written})"));
            }
        }
    }
    assert!(missing.is_empty(), "ARCHITECTURE.md's code map does not name:\n{}", missing.join("\n"));
}

/// The text of a file without its comments (doc comments name modules in prose).
fn code_of(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().map(|line| line.split("//").next().unwrap_or_default()).collect::<Vec<_>>().join("\n")
}

/// The modules of `hir` that `code` uses: a module name followed by `::` (`items::TypeKind`,
/// `use super::{scope::Scope}`), or a name `hir/mod.rs` re-exports (`use super::Semantics`).
fn used_modules(code: &str, modules: &BTreeSet<String>, reexports: &BTreeMap<String, String>) -> BTreeSet<String> {
    let mut used = BTreeSet::new();
    let words: Vec<(usize, &str)> = code
        .match_indices(|c: char| !(c.is_alphanumeric() || c == '_'))
        .scan(0, |start, (at, sep)| {
            let word = (*start, &code[*start..at]);
            *start = at + sep.len();
            Some(word)
        })
        .filter(|(_, w)| !w.is_empty())
        .collect();
    for (at, word) in words {
        let before = code[..at].trim_end();
        let after = &code[at + word.len()..];
        if modules.contains(word) && after.starts_with("::") && !before.ends_with('.') {
            used.insert(word.to_string());
        } else if let Some(module) = reexports.get(word) {
            if before.ends_with("super::")
                || before.ends_with("hir::")
                || before.ends_with(',')
                || before.ends_with('{')
            {
                used.insert(module.clone());
            }
        }
    }
    used
}

#[test]
fn hir_modules_depend_on_each_other_without_circles() {
    let hir = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/hir");
    let test_only = ["golden", "tests"];
    let mut files: BTreeMap<String, Vec<PathBuf>> = BTreeMap::new();
    for entry in std::fs::read_dir(&hir).unwrap().flatten() {
        let path = entry.path();
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if name == "mod" || test_only.contains(&name.as_str()) {
            continue;
        }
        let mut module_files = Vec::new();
        if path.is_dir() {
            rust_files(&path, &mut module_files);
        } else {
            module_files.push(path);
        }
        files.insert(name, module_files);
    }
    let modules: BTreeSet<String> = files.keys().cloned().collect();
    assert!(modules.contains("semantics") && modules.contains("validate"), "{modules:?}");
    // `pub use x::{A, B};` in hir/mod.rs: A and B stand for module x.
    let mut reexports = BTreeMap::new();
    for line in code_of(&hir.join("mod.rs")).lines() {
        let Some(rest) = line.trim().strip_prefix("pub use ") else { continue };
        let Some((module, names)) = rest.split_once("::") else { continue };
        for name in names.split(|c: char| !(c.is_alphanumeric() || c == '_')).filter(|n| !n.is_empty()) {
            reexports.insert(name.to_string(), module.to_string());
        }
    }
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, paths) in &files {
        let mut deps = BTreeSet::new();
        for path in paths {
            deps.extend(used_modules(&code_of(path), &modules, &reexports));
        }
        deps.remove(module);
        graph.insert(module.clone(), deps);
    }
    // Depth-first search for a back edge.
    fn visit(
        module: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(start) = path.iter().position(|m| m == module) {
            let mut circle = path[start..].to_vec();
            circle.push(module.to_string());
            return Some(circle);
        }
        if !done.insert(module.to_string()) {
            return None;
        }
        path.push(module.to_string());
        for dep in &graph[module] {
            if let Some(circle) = visit(dep, graph, path, done) {
                return Some(circle);
            }
        }
        path.pop();
        None
    }
    let mut done = BTreeSet::new();
    for module in graph.keys() {
        let circle = visit(module, &graph, &mut Vec::new(), &mut done);
        assert!(circle.is_none(), "hir modules in a circle: {}\ngraph: {graph:#?}", circle.unwrap().join(" -> "));
    }
    // The facade sits above resolution, validation above everything it checks.
    assert!(graph["validate"].contains("semantics") && !graph["semantics"].contains("validate"), "{graph:#?}");
    assert!(graph["infer"].contains("semantics"), "{graph:#?}");
}
