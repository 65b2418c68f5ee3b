//! `gudsl check` and the language server publish the same diagnostics — both ask
//! `gudsl_host::diagnostics` — on every sample (checked together as one workspace), every
//! golden case of `model/test_data/diagnostics` (each alone), and workspaces whose device code
//! cannot be generated (E0301) or whose pipeline reads a file that is not what it needs (E0404).
//! Each diagnostic is compared by file, start (line, and column in characters), severity, code
//! and message.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/raw_lsp.rs"]
mod raw_lsp;

use std::{
    collections::{BTreeMap, BTreeSet},
    path::{Path, PathBuf},
    time::{Duration, Instant},
};

use cli::{gudsl, repo, temp_dir};
use raw_lsp::Lsp;
use serde_json::{json, Value};

/// One diagnostic as both sides can say it: path, line and column (from 0), severity, code,
/// message.
type Seen = (String, u64, u64, String, String, String);

/// What `gudsl check --format json` reports for `paths` (given canonical, as the editor's URIs
/// name them, so that messages naming a file name it alike).
fn checked(paths: &[&Path]) -> BTreeSet<Seen> {
    let paths: Vec<PathBuf> = paths.iter().map(|p| std::fs::canonicalize(p).unwrap()).collect();
    let output = gudsl().args(["check", "--format", "json"]).args(&paths).output().unwrap();
    let report: Value = serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!("check's JSON: {e}\n{}", String::from_utf8_lossy(&output.stderr));
    });
    assert!(report["unreadable"].as_array().unwrap().is_empty(), "{report}");
    report["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["path"].as_str().unwrap().to_string(),
                d["line"].as_u64().unwrap() - 1,
                d["column"].as_u64().unwrap() - 1,
                d["severity"].as_str().unwrap().to_string(),
                d["code"].as_str().unwrap().to_string(),
                d["message"].as_str().unwrap().to_string(),
            )
        })
        .collect()
}

/// A diagnostic the server published for `path` (its column converted from UTF-16 to
/// characters of `text`).
fn published(path: &str, text: &str, d: &Value) -> Seen {
    let line = d["range"]["start"]["line"].as_u64().unwrap();
    let utf16 = d["range"]["start"]["character"].as_u64().unwrap() as usize;
    let line_text = text.split('\n').nth(line as usize).unwrap_or_default();
    let mut units = 0;
    let column = line_text.chars().take_while(|c| {
        units += c.len_utf16();
        units <= utf16
    });
    let severity = match d["severity"].as_u64() {
        Some(1) => "error",
        Some(2) => "warning",
        other => panic!("severity {other:?}"),
    };
    let code = d["code"].as_str().unwrap().to_string();
    (path.to_string(), line, column.count() as u64, severity.into(), code, d["message"].as_str().unwrap().into())
}

/// What `lsp` publishes for `files` once each is open in it: the last publish of each, once
/// each has one and a second passed without another. Without a root folder the open files are
/// the whole workspace, and closing them leaves it empty again.
fn in_the_editor(lsp: &mut Lsp, files: &[PathBuf]) -> BTreeSet<Seen> {
    let mut texts = BTreeMap::new();
    for file in files {
        let path = std::fs::canonicalize(file).unwrap().display().to_string();
        let text = std::fs::read_to_string(file).unwrap();
        let uri = format!("file://{path}");
        lsp.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}}),
        );
        texts.insert(uri, (path, text));
    }
    let mut last: BTreeMap<String, Vec<Value>> = BTreeMap::new();
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let all_in = last.len() == texts.len();
        // One open file is published once for its version; several may be again as the
        // others arrive.
        let quiet = if !all_in {
            20_000
        } else if texts.len() == 1 {
            0
        } else {
            1_000
        };
        let next = lsp.notification_within("textDocument/publishDiagnostics", Duration::from_millis(quiet), |p| {
            p["uri"].as_str().is_some_and(|uri| texts.contains_key(uri))
        });
        let Some(params) = next else {
            assert!(all_in, "no diagnostics published for {:?}", texts.keys().filter(|u| !last.contains_key(*u)));
            break;
        };
        last.insert(params["uri"].as_str().unwrap().to_string(), params["diagnostics"].as_array().unwrap().clone());
        assert!(Instant::now() < deadline, "the server kept publishing");
    }
    for uri in texts.keys() {
        lsp.notify("textDocument/didClose", json!({"textDocument": {"uri": uri}}));
    }
    last.iter()
        .flat_map(|(uri, diagnostics)| {
            let (path, text) = &texts[uri];
            diagnostics.iter().map(|d| published(path, text, d)).collect::<Vec<_>>()
        })
        .collect()
}

/// A server started in `root` (none: no workspace folder).
fn server_in(root: Option<&Path>) -> Lsp {
    let mut lsp = Lsp::start();
    lsp.initialize_in(root.map(|r| std::fs::canonicalize(r).unwrap()).as_deref());
    lsp
}

/// The `.gudsl` files under `dir`.
fn gudsl_files(dir: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let path = entry.path();
        if path.is_dir() {
            files.extend(gudsl_files(&path));
        } else if path.extension().is_some_and(|e| e == "gudsl") {
            files.push(path);
        }
    }
    files.sort();
    files
}

fn assert_agree(what: &str, check: &BTreeSet<Seen>, editor: &BTreeSet<Seen>) {
    let only_check: Vec<_> = check.difference(editor).collect();
    let only_editor: Vec<_> = editor.difference(check).collect();
    assert!(
        only_check.is_empty() && only_editor.is_empty(),
        "{what}: check and the editor disagree\nonly in check: {only_check:#?}\nonly in the editor: {only_editor:#?}"
    );
}

#[test]
fn on_every_sample() {
    let samples = PathBuf::from(repo("samples"));
    let files = gudsl_files(&samples);
    assert!(files.len() > 40, "{files:?}");
    let check = checked(&[&samples]);
    assert_agree("samples", &check, &in_the_editor(&mut server_in(Some(&samples)), &files));
}

#[test]
fn on_every_golden_case() {
    let cases = gudsl_files(&PathBuf::from(repo("model/test_data/diagnostics")));
    assert!(cases.len() > 100, "{}", cases.len());
    let mut lsp = server_in(None);
    let mut found = 0;
    for case in &cases {
        let check = checked(&[case]);
        found += check.len();
        assert_agree(&case.display().to_string(), &check, &in_the_editor(&mut lsp, std::slice::from_ref(case)));
    }
    assert!(found > 100, "the golden cases have diagnostics: {found}");
}

/// An OpenCL class, a device diagram with a fork (no WGSL form: E0301 twice), and a pipeline
/// whose recording is no array (E0404).
const GPU_CLASS: &str = "ClassDiagram K\n{\n    import OpenCL.GPU.*;\n    public class Gpu implements OpenCL { }\n}\n";
const FORKED: &str = "ActivityDiagram Ad()\n{\n    swimlane L, owner K.Gpu\n    {\n        start S { => split; }\n        fork split { => a; => b; }\n        action a { => j; }\n        action b { => j; }\n        join j { => f; }\n        final f;\n    }\n}\n";
const PIPELINE: &str = "ComponentInstanceDiagram P\n{\n    import ToF.*;\n    Camera instantiates SimulatedCamera (frames = 1)\n    {\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Black.In.frame ]\n    }\n    Black instantiates BlackImageCorrection (channelA = \"a.npy\", channelB = \"a.npy\")\n    {\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n    }\n}\n";

#[test]
fn on_device_code_and_pipeline_file_errors() {
    let dir = temp_dir("errors");
    std::fs::write(dir.join("k.gudsl"), GPU_CLASS).unwrap();
    std::fs::write(dir.join("ad.gudsl"), FORKED).unwrap();
    std::fs::write(dir.join("p.gudsl"), PIPELINE).unwrap();
    std::fs::write(dir.join("a.npy"), b"not an array").unwrap();
    let check = checked(&[&dir]);
    let codes: BTreeSet<&str> = check.iter().map(|seen| seen.4.as_str()).collect();
    assert_eq!(codes, BTreeSet::from(["E0301", "E0404"]), "{check:#?}");
    let editor = in_the_editor(&mut server_in(Some(&dir)), &gudsl_files(&dir));
    assert_agree("device code and pipeline files", &check, &editor);
}
