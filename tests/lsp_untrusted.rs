//! `gudsl lsp` on a workspace that attacks its user (issue 48), byte for byte over stdio: a
//! model whose files are the server's own streams, a FIFO or a device; layout sidecars that are
//! a FIFO or `/dev/zero`; a document URI with `..%2F` in it; graph edits of the read-only
//! library; a client that is not trusted. Every request on another document is answered within
//! a second, and nothing is read or written outside the workspace.

#[path = "support/cli.rs"]
mod cli;
#[path = "support/raw_lsp.rs"]
mod raw_lsp;

use std::{
    os::unix::fs::symlink,
    path::Path,
    process::Command,
    time::{Duration, Instant},
};

use raw_lsp::Lsp;
use serde_json::{json, Value};

const DEFS: &str = "ClassDiagram Defs\n{\n    public class Image\n    {\n        public int width;\n    }\n}\n";

/// The pipeline `name` whose depth images are read from `path`.
fn model(name: &str, path: &str) -> String {
    format!(
        "ComponentInstanceDiagram {name}\n{{\n    import ToF.*;\n    Source instantiates DepthFile (path = \"{path}\")\n    {{\n        Out : DepthOut ( provider depth = IDepthImageProvider() );\n        [ source Out.depth ==> target Writer.In.depth ]\n    }}\n    Writer instantiates NpyWriter ( )\n    {{\n        In : DepthIn ( processor depth = IDepthImageProcessor() );\n    }}\n}}\n"
    )
}

fn uri(path: &Path) -> String {
    format!("file://{}", path.display())
}

/// A hover on `Image` in `defs`, answered within a second.
fn answered_at_once(lsp: &mut Lsp, defs: &str, after: &str) {
    let started = Instant::now();
    let hover = lsp.hover(defs, 2, 19);
    assert!(
        hover["result"]["contents"]["value"].as_str().is_some_and(|v| v.contains("class Image")),
        "{after}: {hover}"
    );
    assert!(started.elapsed() < Duration::from_secs(1), "{after}: answered after {:?}", started.elapsed());
}

/// The messages of the diagnostics published for `uri` that say `wanted`, within 20 s.
fn diagnostic_saying(lsp: &mut Lsp, uri: &str, wanted: &str) -> String {
    let found = lsp.notification("textDocument/publishDiagnostics", 20, |n| {
        n["uri"] == uri && n["diagnostics"].as_array().is_some_and(|d| d.iter().any(|d| message(d).contains(wanted)))
    });
    let found = found.unwrap_or_else(|| panic!("no diagnostic of {uri} says {wanted:?}"));
    found["diagnostics"].as_array().unwrap().iter().map(message).collect::<Vec<_>>().join("\n")
}

fn message(diagnostic: &Value) -> String {
    diagnostic["message"].as_str().unwrap_or_default().to_string()
}

/// A workspace folder holding a FIFO named `fifo` and a link to `/dev/zero` named `zero`, a
/// server started in it, and the URI of a harmless document it has open.
fn hostile_workspace(name: &str, fifo: &str, zero: &str) -> (std::path::PathBuf, Lsp, String) {
    let ws = cli::temp_dir(name);
    assert!(Command::new("mkfifo").arg(ws.join(fifo)).status().unwrap().success());
    symlink("/dev/zero", ws.join(zero)).unwrap();
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&ws));
    let defs = uri(&ws.join("defs.gudsl"));
    lsp.open(&defs, DEFS);
    (ws, lsp, defs)
}

#[test]
fn files_naming_the_servers_streams_a_fifo_or_a_device_are_diagnostics_not_freezes() {
    let (ws, mut lsp, defs) = hostile_workspace("lsp-streams", "fifo.npy", "zero.npy");
    for (k, (path, why)) in [
        ("/dev/stdin", "lies outside"),
        ("/dev/stdout", "lies outside"),
        ("/dev/stderr", "lies outside"),
        ("fifo.npy", "is a FIFO, not a regular file"),
        ("zero.npy", "lies outside"),
    ]
    .into_iter()
    .enumerate()
    {
        let file = uri(&ws.join(format!("m{k}.gudsl")));
        lsp.open(&file, &model(&format!("P{k}"), path));
        let said = diagnostic_saying(&mut lsp, &file, why);
        assert!(said.contains(path), "{path}: {said}");
        // Typing in the model checks it again; the other document is answered meanwhile.
        lsp.change(&file, 2, ((0, 0), (0, 0)), "// typed\n");
        answered_at_once(&mut lsp, &defs, path);
    }
    assert!(lsp.child.try_wait().unwrap().is_none(), "the server exited");
}

/// `gudsl/graph` of the diagram `name` of `file`.
fn graph(lsp: &mut Lsp, file: &str, name: &str) -> Value {
    lsp.request("gudsl/graph", json!({"textDocument": {"uri": file}, "diagram": name}))
}

/// Moves the instance `Source` of the diagram `name` of `file`.
fn move_source(lsp: &mut Lsp, file: &str, name: &str) -> Value {
    let op = json!({"op": "move", "element": "Source", "position": {"x": 40, "y": 40}});
    let params = json!({"textDocument": {"uri": file, "version": 1}, "diagram": name, "operations": [op]});
    lsp.request("gudsl/applyGraphEdit", params)
}

#[test]
fn a_fifo_or_dev_zero_sidecar_is_refused_at_once_and_other_documents_still_move() {
    let (ws, mut lsp, defs) = hostile_workspace("lsp-sidecars", "fifo.gudsl.layout", "zero.gudsl.layout");
    for (name, why) in [("fifo", "is a FIFO"), ("zero", "lies outside")] {
        let file = uri(&ws.join(format!("{name}.gudsl")));
        lsp.open(&file, &model(name, "depth.npy"));
        let started = Instant::now();
        let answer = graph(&mut lsp, &file, name);
        assert!(started.elapsed() < Duration::from_secs(2), "{name}: {answer}");
        assert!(answer.to_string().contains(why), "{name}: the sidecar's problem is said: {answer}");
        let refused = move_source(&mut lsp, &file, name);
        assert!(refused.to_string().contains(why), "{name}: {refused}");
    }
    // Another document's sidecar is written meanwhile.
    let fine = ws.join("fine.gudsl");
    lsp.open(&uri(&fine), &model("fine", "depth.npy"));
    graph(&mut lsp, &uri(&fine), "fine");
    let moved = move_source(&mut lsp, &uri(&fine), "fine");
    assert!(moved["result"]["layout"].is_object(), "{moved}");
    assert!(ws.join("fine.gudsl.layout").is_file());
    answered_at_once(&mut lsp, &defs, "after the sidecars");
}

#[test]
fn a_document_uri_leading_out_of_the_workspace_gets_no_sidecar_and_the_library_no_edit() {
    let base = cli::temp_dir("lsp-uris");
    let ws = base.join("ws");
    std::fs::create_dir_all(ws.join("sub")).unwrap();
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&ws));
    let sneaky = format!("file://{}/sub/..%2F..%2Fevil.gudsl", ws.display());
    lsp.open(&sneaky, &model("Evil", "depth.npy"));
    graph(&mut lsp, &sneaky, "Evil");
    let refused = move_source(&mut lsp, &sneaky, "Evil");
    assert!(refused.to_string().contains("outside the workspace folders"), "{refused}");
    assert!(!base.join("evil.gudsl.layout").exists() && !ws.join("sub/..%2F..%2Fevil.gudsl.layout").exists());

    let library = "gudsl:/lib/tof.gudsl";
    for op in [
        json!({"op": "delete", "element": "ToF.RawFrame"}),
        json!({"op": "setProperty", "element": "ToF.RawFrame", "property": "abstract", "value": "true"}),
        json!({"op": "create", "kind": "class", "parent": "ToF", "name": "Planted"}),
    ] {
        let params = json!({"textDocument": {"uri": library, "version": null}, "diagram": "ToF", "operations": [op]});
        let answer = lsp.request("gudsl/applyGraphEdit", params);
        assert!(answer.to_string().contains("read-only"), "{op}: {answer}");
    }
}

#[test]
fn an_untrusted_workspace_reads_no_file_a_model_names_and_runs_nothing() {
    let ws = cli::temp_dir("lsp-untrusted");
    assert!(Command::new("mkfifo").arg(ws.join("fifo.npy")).status().unwrap().success());
    let mut lsp = Lsp::start();
    let answer = lsp.request(
        "initialize",
        json!({"processId": null, "rootUri": uri(&ws), "capabilities": {}, "initializationOptions": {"trusted": false}}),
    );
    assert!(answer["result"]["capabilities"].is_object(), "{answer}");
    lsp.notify("initialized", json!({}));
    let file = uri(&ws.join("m.gudsl"));
    lsp.open(&file, &model("P", "missing.npy"));
    let read = lsp.notification("textDocument/publishDiagnostics", 3, |p| p.to_string().contains("E0404"));
    assert!(read.is_none(), "no file is read, so no E0404: {read:?}");
    let run = lsp.request("workspace/executeCommand", json!({"command": "gudsl.runPipeline", "arguments": ["P"]}));
    assert!(run.to_string().contains("not trusted"), "{run}");
    assert!(!ws.join("gudsl-out").exists());
}

/// A repository's `.vscode/settings.json` cannot name the program VS Code starts as the server,
/// its arguments or the folder runs write into (`machine` scope: user settings only, as
/// rust-analyzer's server path); in Restricted Mode the extension declares itself limited and
/// VS Code ignores those settings; and the server learns trust from the client.
#[test]
fn the_vs_code_extension_lets_no_workspace_name_a_program_or_a_folder() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../vscode-extension");
    let manifest: Value = serde_json::from_str(&std::fs::read_to_string(root.join("package.json")).unwrap()).unwrap();
    let settings = &manifest["contributes"]["configuration"]["properties"];
    let named = ["gudsl.server.path", "gudsl.server.extraArgs", "gudsl.run.outputFolder"];
    for setting in named {
        assert_eq!(settings[setting]["scope"], "machine", "{setting}");
    }
    let untrusted = &manifest["capabilities"]["untrustedWorkspaces"];
    assert_eq!(untrusted["supported"], "limited");
    assert_eq!(untrusted["restrictedConfigurations"], json!(named));
    let server = std::fs::read_to_string(root.join("src/server.ts")).unwrap();
    assert!(server.contains("initializationOptions: { trusted: vscode.workspace.isTrusted }"));
    let extension = std::fs::read_to_string(root.join("src/extension.ts")).unwrap();
    assert!(extension.contains("onDidGrantWorkspaceTrust"), "granting trust restarts the server");
}

/// The CPU time the process `pid` has used, in seconds.
fn cpu_seconds(pid: u32) -> f64 {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).unwrap();
    let fields: Vec<&str> = stat.rsplit(')').next().unwrap().split_whitespace().collect();
    // utime and stime: the 14th and 15th fields, the 12th and 13th after the command's name.
    let ticks: f64 = fields[11].parse::<f64>().unwrap() + fields[12].parse::<f64>().unwrap();
    ticks / 100.0
}

#[test]
fn a_cancelled_run_stops_inside_its_frame_instead_of_computing_on() {
    let ws = cli::temp_dir("lsp-cancel-inside");
    // One frame of 1024 × 1024 pixels of 8 × 8 rays: about a billion ray casts, many seconds.
    let model = "ComponentInstanceDiagram Big\n{\n    import ToF.*;\n    Camera instantiates SimulatedCamera (frames = 1, width = 1024, height = 1024, supersampling = 8)\n    {\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Demod.In.frame ]\n    }\n    Demod instantiates Demodulation ( )\n    {\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n    }\n}\n";
    let file = ws.join("big.gudsl");
    std::fs::write(&file, model).unwrap();
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&ws));
    lsp.open(&uri(&file), model);
    let run = json!({"command": "gudsl.runPipeline", "arguments": [{"diagram": "Big", "cpu": true}]});
    lsp.send(&json!({"jsonrpc": "2.0", "id": 500, "method": "workspace/executeCommand", "params": run}));
    std::thread::sleep(Duration::from_secs(3));
    let pid = lsp.child.id();
    let (before, still) = (cpu_seconds(pid), Instant::now());
    std::thread::sleep(Duration::from_millis(500));
    let busy = (cpu_seconds(pid) - before) / still.elapsed().as_secs_f64();
    assert!(busy > 0.5, "the frame is being simulated ({busy:.2} of a core)");

    lsp.notify("$/cancelRequest", json!({"id": 500}));
    let answer = lsp.response_to(&json!(500));
    assert!(answer["error"].is_object(), "{answer}");
    std::thread::sleep(Duration::from_millis(500));
    let (after, since) = (cpu_seconds(pid), Instant::now());
    std::thread::sleep(Duration::from_secs(1));
    let busy = (cpu_seconds(pid) - after) / since.elapsed().as_secs_f64();
    assert!(busy < 0.2, "half a second after the cancel the server still computes {busy:.2} of a core");
}

#[test]
fn a_run_from_the_editor_writes_into_the_workspace_or_a_private_folder_never_a_shared_one() {
    use std::os::unix::fs::PermissionsExt;
    let base = cli::temp_dir("lsp-destination");
    let ws = base.join("ws");
    std::fs::create_dir_all(&ws).unwrap();
    let depth = b"\x93NUMPY\x01\x00v\x00{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
    let mut npy = depth.to_vec();
    npy.extend(std::iter::repeat_n(b' ', 128 - npy.len() - 1));
    npy.push(b'\n');
    npy.extend([0u8; 24]);
    for folder in [&ws, &base] {
        std::fs::write(folder.join("depth.npy"), &npy).unwrap();
    }
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&ws));
    let inside = ws.join("inside.gudsl");
    let outside = base.join("outside.gudsl");
    let mut outputs = Vec::new();
    for (file, name) in [(&inside, "Inside"), (&outside, "Outside")] {
        let text = model(name, "depth.npy");
        std::fs::write(file, &text).unwrap();
        lsp.open(&uri(file), &text);
        let run = json!({"command": "gudsl.runPipeline", "arguments": [{"diagram": name, "cpu": true}]});
        let answer = lsp.request("workspace/executeCommand", run);
        let output = answer["result"]["output"].as_str().unwrap_or_else(|| panic!("{answer}")).to_string();
        outputs.push(std::path::PathBuf::from(output));
        lsp.notify("textDocument/didClose", json!({"textDocument": {"uri": uri(file)}}));
    }
    assert_eq!(outputs[0], ws.join("gudsl-out/Inside"), "as `gudsl run` writes, in the workspace folder");
    let private = outputs[1].parent().unwrap().parent().unwrap();
    assert!(outputs[1].ends_with("gudsl-out/Outside") && !private.starts_with(&base), "{:?}", outputs[1]);
    assert!(!outputs[1].starts_with(std::env::temp_dir().join("gudsl-run")), "not the old shared path");
    let mode = std::fs::metadata(private).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode, 0o700, "{} is private", private.display());
    assert!(outputs[1].join("Writer/distance_0000.npy").is_file());
}
