//! Source hygiene (ARCHITECTURE.md, "Invariants"): every Rust file of the project opens with a
//! `//!` line saying what it does and, unless generated, has at most 600 lines; ARCHITECTURE.md
//! names every top-level module of every crate; the modules of every module folder of every
//! crate depend on each other without circles.

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
    for krate in ["codegen", "files", "formats", "host", "model", "server", "render", "runtime"] {
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

/// The sibling modules that `code` uses: a module name followed by `::` where it starts a path
/// or follows `super::`, `self::` or `crate::` (`items::TypeKind`, `use super::{scope::Scope}`,
/// `crate::commands::run`), or a name the parent re-exports imported from it
/// (`use super::Semantics`).
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
        if modules.contains(word) && after.starts_with("::") && !before.ends_with('.') && names_a_sibling(code, at) {
            used.insert(word.to_string());
        } else if let Some(module) = reexports.get(word) {
            let in_use = code[..at].rfind("use ").is_some_and(|start| !code[start..at].contains(';'));
            if in_use && (before.ends_with("super::") || before.ends_with(',') || before.ends_with('{')) {
                used.insert(module.clone());
            }
        }
    }
    used
}

/// Whether the path segment at `at` is the first of a path that starts here or in the folder's
/// parent (`super::`, `self::`, `crate::`): inside a `use` tree, the path the innermost brace
/// around it extends decides (`use gudsl_model::{graph::Graph}` names no sibling `graph`).
fn names_a_sibling(code: &str, at: usize) -> bool {
    let from_parent = |before: &str| {
        let before = before.trim_end();
        !before.ends_with("::") || ["super::", "self::", "crate::"].iter().any(|p| before.ends_with(p))
    };
    let statement = code[..at].rfind(';').map_or(0, |end| end + 1);
    let is_use = |&(u, _): &(usize, &str)| {
        code[..statement + u].chars().next_back().is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
    };
    let Some(tree) = code[statement..at].match_indices("use ").find(is_use).map(|(u, _)| statement + u) else {
        return from_parent(&code[..at]);
    };
    let mut depth = 0;
    for (offset, c) in code[tree..at].char_indices().rev() {
        match c {
            '}' => depth += 1,
            '{' if depth == 0 => {
                let extended = code[tree..tree + offset].trim_end();
                return ["super::", "self::", "crate::"].iter().any(|p| extended.ends_with(p));
            }
            '{' => depth -= 1,
            _ => {}
        }
    }
    from_parent(&code[..at])
}

/// The modules a module folder declares (`mod x;` in its `mod.rs`, `lib.rs` or `main.rs`),
/// with their files, leaving out those only tests compile (`#[cfg(test)]`).
fn child_modules(parent: &Path) -> BTreeMap<String, Vec<PathBuf>> {
    let dir = parent.parent().unwrap();
    let code = code_of(parent);
    let mut children = BTreeMap::new();
    let mut test_only = false;
    for line in code.lines().map(str::trim) {
        if line.starts_with("#[cfg(test)]") {
            test_only = true;
            continue;
        }
        let declared = line.trim_start_matches("pub(crate) ").trim_start_matches("pub ");
        if let Some(name) = declared.strip_prefix("mod ").and_then(|rest| rest.strip_suffix(';')) {
            let (file, folder) = (dir.join(format!("{name}.rs")), dir.join(name));
            let mut files = Vec::new();
            if folder.is_dir() {
                rust_files(&folder, &mut files);
            }
            if file.is_file() {
                files.push(file);
            }
            if !test_only && !files.is_empty() {
                children.insert(name.to_string(), files);
            }
        }
        if !line.is_empty() {
            test_only = false;
        }
    }
    children
}

/// The circles of `graph`: each set of modules that reach each other (of two or more).
fn circles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<BTreeSet<String>> {
    let reach = |from: &str| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.to_string()];
        while let Some(module) = todo.pop() {
            for dep in &graph[&module] {
                if seen.insert(dep.clone()) {
                    todo.push(dep.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<String>> = graph.keys().map(|m| (m, reach(m))).collect();
    let mut circles: Vec<BTreeSet<String>> = Vec::new();
    for (module, from_it) in &reached {
        let circle: BTreeSet<String> =
            from_it.iter().filter(|other| reached[other].contains(*module)).cloned().collect();
        if circle.len() > 1 && !circles.contains(&circle) {
            circles.push(circle);
        }
    }
    circles
}

/// The code of a file without its comments and without its `#[cfg(test)]` module at the end
/// (tests may reach anywhere).
fn shipped_code_of(path: &Path) -> String {
    let code = code_of(path);
    let tests = code.match_indices("#[cfg(test)]\n").map(|(at, _)| at).find(|&at| {
        let next = code[at..].lines().nth(1).unwrap_or_default().trim();
        next.trim_start_matches("pub(super) ").trim_start_matches("pub(crate) ").starts_with("mod ")
            && next.ends_with('{')
    });
    match tests {
        Some(tests) => code[..tests].to_string(),
        None => code,
    }
}

/// How the modules declared by `parent` (a `mod.rs`, `lib.rs` or `main.rs`) use each other.
fn module_graph(parent: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let files = child_modules(parent);
    let modules: BTreeSet<String> = files.keys().cloned().collect();
    // `pub use x::{A, B};` in the parent: A and B stand for module x.
    let mut reexports = BTreeMap::new();
    for line in code_of(parent).lines() {
        let Some(rest) = line.trim().strip_prefix("pub use ") else { continue };
        let Some((module, names)) = rest.split_once("::") else { continue };
        if !modules.contains(module) {
            continue;
        }
        for name in names.split(|c: char| !(c.is_alphanumeric() || c == '_')).filter(|n| !n.is_empty()) {
            reexports.insert(name.to_string(), module.to_string());
        }
    }
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (module, paths) in &files {
        let mut deps = BTreeSet::new();
        for path in paths {
            deps.extend(used_modules(&shipped_code_of(path), &modules, &reexports));
        }
        deps.remove(module);
        graph.insert(module.clone(), deps);
    }
    graph
}

/// Every module folder of the crates: their `lib.rs`/`main.rs` and every `mod.rs` under `src/`.
fn module_folders() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut parents = Vec::new();
    for krate in ["codegen", "host", "model", "server", "render", "runtime"] {
        let mut files = Vec::new();
        rust_files(&root.join(krate).join("src"), &mut files);
        parents.extend(files.into_iter().filter(|f| {
            let name = f.file_name().unwrap().to_string_lossy();
            name == "mod.rs" || (f.parent().unwrap().ends_with("src") && (name == "lib.rs" || name == "main.rs"))
        }));
    }
    parents.sort();
    parents
}

#[test]
fn modules_depend_on_each_other_without_circles() {
    let folders = module_folders();
    assert!(folders.len() > 20, "{folders:?}");
    let circles: Vec<String> = folders
        .iter()
        .flat_map(|parent| {
            let graph = module_graph(parent);
            let folder = parent.parent().unwrap().display().to_string();
            circles(&graph).into_iter().map(move |circle| {
                let edges: Vec<String> = circle
                    .iter()
                    .flat_map(|m| graph[m].iter().filter(|d| circle.contains(*d)).map(move |d| format!("{m} -> {d}")))
                    .collect();
                format!("{folder}: {}", edges.join(", "))
            })
        })
        .collect();
    assert!(circles.is_empty(), "modules in a circle:\n{}", circles.join("\n"));
}

#[test]
fn the_modules_stand_where_architecture_says() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let hir = module_graph(&src.join("hir/mod.rs"));
    // The facade sits above resolution, validation above everything it checks.
    assert!(hir["validate"].contains("semantics") && !hir["semantics"].contains("validate"), "{hir:#?}");
    assert!(hir["infer"].contains("semantics"), "{hir:#?}");
    // The language server and the commands share what they share below both.
    let server = module_graph(&src.join("../../server/src/main.rs"));
    assert!(!server["lsp"].contains("commands") && !server["commands"].contains("lsp"), "{server:#?}");
}

/// The functions of `code` longer than `limit` lines: (name, first line, lines). A function
/// runs from its `fn` to the brace that closes its body (braces in strings and characters
/// skipped).
fn long_functions(code: &str, limit: usize) -> Vec<(String, usize, usize)> {
    let lines: Vec<&str> = code.lines().collect();
    let mut long = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let trimmed = line.trim_start();
        let signature = [
            "pub fn ",
            "fn ",
            "pub(crate) fn ",
            "pub(super) fn ",
            "async fn ",
            "pub async fn ",
            "pub(super) async fn ",
            "const fn ",
            "pub const fn ",
        ]
        .iter()
        .find_map(|prefix| trimmed.strip_prefix(prefix));
        let Some(rest) = signature else { continue };
        let name: String = rest.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect();
        let mut depth = 0i32;
        let mut opened = false;
        let mut end = None;
        'lines: for (at, text) in lines.iter().enumerate().skip(start) {
            let mut chars = text.chars().peekable();
            let mut in_string = false;
            while let Some(c) = chars.next() {
                match c {
                    '\\' if in_string => {
                        chars.next();
                    }
                    '"' => in_string = !in_string,
                    '\'' if !in_string => {
                        // A character literal ('{', '\'') or a lifetime ('a): skip a literal.
                        let literal: String = chars.clone().take(3).collect();
                        if literal.starts_with('\\') || literal.chars().nth(1) == Some('\'') {
                            while chars.next().is_some_and(|c| c != '\'') {}
                        }
                    }
                    ';' if !in_string && !opened && depth == 0 => break 'lines, // a declaration without a body
                    '{' if !in_string => {
                        depth += 1;
                        opened = true;
                    }
                    '}' if !in_string => {
                        depth -= 1;
                        if opened && depth == 0 {
                            end = Some(at);
                            break 'lines;
                        }
                    }
                    _ => {}
                }
            }
        }
        if let Some(end) = end {
            let length = end - start + 1;
            if length > limit {
                long.push((name, start + 1, length));
            }
        }
    }
    long
}

#[test]
fn no_function_is_longer_than_120_lines() {
    let crates = ["codegen", "host", "model", "server", "render", "runtime"];
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut long = Vec::new();
    for krate in crates {
        let mut files = Vec::new();
        rust_files(&root.join(krate).join("src"), &mut files);
        for file in files.iter().filter(|f| !f.ends_with("generated.rs") && !f.ends_with("tests.rs")) {
            let name = file.file_name().unwrap().to_string_lossy();
            if name.starts_with("tests_") || file.components().any(|c| c.as_os_str() == "tests") {
                continue;
            }
            for (function, line, lines) in long_functions(&shipped_code_of(file), 120) {
                long.push(format!("{}:{line}: `{function}` has {lines} lines", file.display()));
            }
        }
    }
    assert!(long.is_empty(), "split these by stage:\n{}", long.join("\n"));
}

#[test]
fn long_functions_are_measured_from_fn_to_its_closing_brace() {
    let body = "    let x = '{';\n    let s = \"}\";\n".repeat(3);
    let code = format!("fn short() {{}}\nfn measured() {{\n{body}}}\nfn declared();\n");
    assert_eq!(long_functions(&code, 5), vec![("measured".to_string(), 2, 8)]);
    assert!(long_functions(&code, 8).is_empty());
}

/// A hash of `text` that stays the same across machines and line endings (FNV-1a, 64 bits).
fn stable_hash(text: &str) -> String {
    let hash = text
        .bytes()
        .filter(|&b| b != b'\r')
        .fold(0xcbf2_9ce4_8422_2325u64, |hash, byte| (hash ^ byte as u64).wrapping_mul(0x0000_0100_0000_01b3));
    format!("{hash:016x}")
}

/// The server's extension protocol (`server/src/lsp/ext.rs`) changes only together with its
/// documentation and its client's types (rust-analyzer's `lsp/ext.rs` hash check): both record
/// the hash of the file they were last checked against.
#[test]
fn the_extension_protocol_and_its_documents_change_together() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let ext = std::fs::read_to_string(root.join("server/src/lsp/ext.rs")).unwrap();
    let line = format!("lsp/ext.rs hash: {}", stable_hash(&ext));
    for document in ["docs/protocol.md", "vscode-extension/src/protocol.ts"] {
        let text = std::fs::read_to_string(root.join(document)).unwrap();
        assert!(
            text.contains(&line),
            "server/src/lsp/ext.rs changed: bring {document} up to date with it, then write `{line}` in it"
        );
    }
}

/// The `[dependencies]` of a crate's manifest: their names.
fn dependencies(krate: &str) -> BTreeSet<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let manifest = std::fs::read_to_string(root.join(krate).join("Cargo.toml")).unwrap();
    let section = manifest.split("\n[dependencies]\n").nth(1).unwrap_or_default();
    let section = section.split("\n[").next().unwrap_or_default();
    section
        .lines()
        .filter(|line| !line.trim_start().starts_with('#'))
        .filter_map(|line| line.split(['=', '.', ' ']).next())
        .filter(|name| !name.is_empty())
        .map(str::to_string)
        .collect()
}

/// The crate graph ARCHITECTURE.md draws: each crate's dependencies among the project's own,
/// one way; `model` and `files` at the ground; the host drives the GPU only through the
/// runtime (no wgpu of its own).
#[test]
fn crates_depend_on_each_other_as_architecture_draws() {
    let own = |krate: &str| -> BTreeSet<String> {
        dependencies(krate).into_iter().filter(|d| d.starts_with("gudsl-")).collect()
    };
    let expected = [
        ("model", vec![]),
        ("files", vec![]),
        ("formats", vec!["gudsl-files"]),
        ("runtime", vec!["gudsl-files", "gudsl-formats"]),
        ("codegen", vec!["gudsl-model"]),
        ("render", vec!["gudsl-model"]),
        ("host", vec!["gudsl-codegen", "gudsl-files", "gudsl-formats", "gudsl-model", "gudsl-render", "gudsl-runtime"]),
        (
            "server",
            vec![
                "gudsl-codegen",
                "gudsl-files",
                "gudsl-formats",
                "gudsl-host",
                "gudsl-model",
                "gudsl-render",
                "gudsl-runtime",
            ],
        ),
    ];
    for (krate, deps) in expected {
        let deps: BTreeSet<String> = deps.into_iter().map(str::to_string).collect();
        assert_eq!(own(krate), deps, "{krate}'s dependencies among the project's crates");
    }
    assert!(dependencies("runtime").contains("wgpu"), "{:?}", dependencies("runtime"));
    assert!(!dependencies("host").contains("wgpu"), "the host reaches the GPU through the runtime");
}

/// The model does no I/O: texts come in through its inputs (its golden tests read their cases).
#[test]
fn the_model_reads_and_writes_no_file() {
    let mut files = Vec::new();
    rust_files(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut files);
    let doing_io: Vec<String> = files
        .iter()
        .filter(|f| !f.ends_with("golden.rs") && !f.ends_with("tests.rs"))
        .filter(|f| {
            let code = shipped_code_of(f);
            ["std::fs", "fs::File", "std::net", "std::process"].iter().any(|io| code.contains(io))
        })
        .map(|f| f.display().to_string())
        .collect();
    assert!(doing_io.is_empty(), "the model does no I/O:\n{}", doing_io.join("\n"));
}

/// One way to touch a model's files (issue 48): the host and the runtime open, read and write
/// no file themselves — they go through `gudsl-files` (folders as capabilities) and
/// `gudsl-formats`, whose only path-based write is `arrays::write` for a file the user named.
#[test]
fn only_gudsl_files_touches_the_files_a_model_names() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = Vec::new();
    for krate in ["host", "runtime", "formats"] {
        rust_files(&root.join(krate).join("src"), &mut files);
    }
    let touching: Vec<String> = files
        .iter()
        .filter(|f| !f.ends_with("tests.rs"))
        .filter_map(|f| {
            let code = shipped_code_of(f);
            let calls = [
                "fs::read",
                "fs::write(",
                "fs::create_dir",
                "fs::remove",
                "fs::rename",
                "fs::metadata",
                "fs::canonicalize",
                "OpenOptions",
                "File::open(",
                "File::create(",
                "image::open(",
            ];
            // A call, not part of a longer name (`DepthFile::open(` is ours).
            let called = |io: &str| {
                code.match_indices(io).any(|(at, _)| !code[..at].ends_with(|c: char| c.is_alphanumeric() || c == '_'))
            };
            let mut found: Vec<&str> = calls.iter().copied().filter(|io| called(io)).collect();
            if f.ends_with("formats/src/arrays.rs") && code.matches("fs::write(").count() == 1 {
                // `arrays::write(path, …)`: `gudsl calibrate-phases`' output, named by the user.
                found.retain(|io| *io != "fs::write(");
            }
            (!found.is_empty()).then(|| format!("{} ({})", f.display(), found.join(", ")))
        })
        .collect();
    assert!(touching.is_empty(), "files touched outside gudsl-files:\n{}", touching.join("\n"));
}
