//! `gudsl lsp` keeps the editor's text, exactly: documents with CRLF and lone-CR line ends
//! edited at positions a client computes, compared with the server's copy after every edit;
//! workspaces with FIFOs, link loops and device links; diagnostics cleared when a document
//! leaves; changes the spec does not allow refused, not guessed at.

#[path = "support/cli.rs"]
mod cli;

use cli::temp_dir;

#[path = "support/raw_lsp.rs"]
mod raw_lsp;

use std::{os::unix::fs::symlink, process::Command};

use raw_lsp::Lsp;
use serde_json::json;

/// A client's position of a byte offset: lines end at `\r\n`, `\r` and `\n`; columns count
/// UTF-16 units.
fn client_position(text: &str, offset: usize) -> (u32, u32) {
    let (mut line, mut col) = (0, 0);
    let mut chars = text[..offset].chars().peekable();
    while let Some(ch) = chars.next() {
        match ch {
            '\r' if chars.peek() == Some(&'\n') => {}
            '\r' | '\n' => (line, col) = (line + 1, 0),
            _ => col += ch.len_utf16() as u32,
        }
    }
    (line, col)
}

/// A small deterministic generator (xorshift), so a failure replays.
struct Rng(u64);

impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

/// An offset of `text` a client can name: a character boundary, not between `\r` and `\n`.
fn nameable_offset(text: &str, rng: &mut Rng) -> usize {
    loop {
        let offset = rng.below(text.len() + 1);
        let inside_crlf =
            offset > 0 && text.as_bytes()[offset - 1] == b'\r' && text.as_bytes().get(offset) == Some(&b'\n');
        if text.is_char_boundary(offset) && !inside_crlf {
            return offset;
        }
    }
}

#[test]
fn edits_on_crlf_and_lone_cr_lines_land_where_the_client_put_them() {
    let mut lsp = Lsp::start();
    lsp.initialize();
    let uri = "file:///ws/lines.gudsl";
    let mut text = String::from("ClassDiagram D\r{\r\n    // ä😀 note\r    public class C { }\n}\r\n");
    lsp.open(uri, &text);
    let pieces = ["\r", "\n", "\r\n", "x", "😀", "ä", " ", "class", "\r\r\n", ""];
    let mut rng = Rng(0x5eed_1234_5678_9abc);
    for version in 2..400 {
        let mut start = nameable_offset(&text, &mut rng);
        let mut end = nameable_offset(&text, &mut rng);
        if end < start {
            std::mem::swap(&mut start, &mut end);
        }
        // Mostly small edits.
        if end - start > 8 {
            end = start;
        }
        let insert = pieces[rng.below(pieces.len())];
        lsp.change(uri, version, (client_position(&text, start), client_position(&text, end)), insert);
        text.replace_range(start..end, insert);
        if version % 20 == 0 {
            assert_eq!(lsp.server_text(uri), json!(text), "after edit {version}");
        }
    }
    assert_eq!(lsp.server_text(uri), json!(text));
    // A diagnostic lands on the line and column the client counts.
    lsp.notify(
        "textDocument/didOpen",
        json!({"textDocument": {"uri": "file:///ws/d.gudsl", "languageId": "gudsl", "version": 1,
        "text": "ClassDiagram E\r{\r\n    // note\r    public class C { public Missing m; }\r\n    \"open\r\n}\r\n"}}),
    );
    let diagnostics = lsp.diagnostics_of("file:///ws/d.gudsl", 20).expect("diagnostics");
    let ranges: Vec<_> = diagnostics.iter().map(|d| (d["code"].clone(), d["range"].clone())).collect();
    let range = |l1, c1, l2, c2| json!({"start": {"line": l1, "character": c1}, "end": {"line": l2, "character": c2}});
    assert!(ranges.contains(&(json!("E0201"), range(3, 28, 3, 35))), "{ranges:?}");
    // The unterminated string ends before the line's `\r\n`, not a column past it.
    assert!(ranges.contains(&(json!("E0003"), range(4, 4, 4, 9))), "{ranges:?}");
}

#[test]
fn a_workspace_with_a_fifo_link_loops_a_device_link_and_a_second_name_loads_each_file_once() {
    let root = temp_dir("hostile-ws");
    std::fs::write(root.join("a.gudsl"), "ClassDiagram D { public class Image { public Missing m; } }\n").unwrap();
    assert!(Command::new("mkfifo").arg(root.join("x.gudsl")).status().unwrap().success());
    symlink(".", root.join("loop1")).unwrap();
    symlink(".", root.join("loop2")).unwrap();
    symlink("/dev/zero", root.join("zero.gudsl")).unwrap();
    // A second name for a.gudsl: read once, as `gudsl check` does.
    symlink("a.gudsl", root.join("alias.gudsl")).unwrap();
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    let a = format!("file://{}", root.join("a.gudsl").display());
    let diagnostics = lsp.diagnostics_of(&a, 20).expect("the workspace loads");
    assert_eq!(diagnostics.len(), 1, "one E0201, no E0205 from reading the file twice: {diagnostics:?}");
    let symbols = lsp.request("workspace/symbol", json!({"query": "Image"}));
    // The workspace's own `Image` once (the bundled library's `ImageContainer`, `QImage`, … too).
    let found = symbols["result"].as_array().expect("symbols");
    let own = found.iter().filter(|s| s["location"]["uri"].as_str().unwrap().starts_with("file:")).count();
    assert_eq!(own, 1, "{symbols}");
    let _ = std::fs::remove_dir_all(&root);
}

#[test]
fn diagnostics_of_a_document_that_leaves_the_workspace_are_cleared() {
    let root = temp_dir("leaving");
    let on_disk = root.join("gone.gudsl");
    std::fs::write(&on_disk, "ClassDiagram G { public class C { public Missing m; } }\n").unwrap();
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    let gone = format!("file://{}", on_disk.display());
    assert_eq!(lsp.diagnostics_of(&gone, 20).expect("loaded").len(), 1);
    // Deleted on disk, and the watcher says so.
    std::fs::remove_file(&on_disk).unwrap();
    lsp.notify("workspace/didChangeWatchedFiles", json!({"changes": [{"uri": gone, "type": 3}]}));
    assert_eq!(lsp.diagnostics_of(&gone, 20), Some(vec![]), "cleared on delete");
    // An unsaved buffer, closed without saving.
    let untitled = "untitled:Untitled-1";
    lsp.open(untitled, "ClassDiagram U { public class C { public Missing m; } }\n");
    assert_eq!(lsp.diagnostics_of(untitled, 20).expect("published").len(), 1);
    lsp.notify("textDocument/didClose", json!({"textDocument": {"uri": untitled}}));
    assert_eq!(lsp.diagnostics_of(untitled, 20), Some(vec![]), "cleared on close");
    // A file outside the workspace folder, closed.
    let outside = temp_dir("outside").join("o.gudsl");
    std::fs::write(&outside, "ClassDiagram O { public class C { public Missing m; } }\n").unwrap();
    let outside = format!("file://{}", outside.display());
    lsp.open(&outside, "ClassDiagram O { public class C { public Missing m; } }\n");
    assert_eq!(lsp.diagnostics_of(&outside, 20).expect("published").len(), 1);
    lsp.notify("textDocument/didClose", json!({"textDocument": {"uri": outside}}));
    assert_eq!(lsp.diagnostics_of(&outside, 20), Some(vec![]), "cleared on close");
}

#[test]
fn changes_the_spec_does_not_allow_are_refused_not_guessed_at() {
    let root = temp_dir("refused");
    let path = root.join("a.gudsl");
    std::fs::write(&path, "ClassDiagram A { public class C { } }\n").unwrap();
    let uri = format!("file://{}", path.display());
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    lsp.diagnostics_of(&uri, 20).expect("loaded");
    // A change to a document the editor never opened: ignored, and it stays closed.
    lsp.change(&uri, 2, ((0, 0), (0, 0)), "garbage ");
    assert_eq!(lsp.server_text(&uri), json!("ClassDiagram A { public class C { } }\n"));
    // A change whose range ends before it starts: refused, and the user is told.
    lsp.open(&uri, "ClassDiagram A { public class C { } }\n");
    lsp.change(&uri, 2, ((0, 10), (0, 5)), "X");
    let shown = lsp.notification("window/showMessage", 20, |_| true).expect("the user is told");
    assert!(shown["message"].as_str().unwrap().contains("was not applied"), "{shown}");
    assert_eq!(lsp.server_text(&uri), json!("ClassDiagram A { public class C { } }\n"));
    // A request with a reversed range: InvalidParams.
    let answer = lsp.request(
        "textDocument/inlayHint",
        json!({"textDocument": {"uri": uri}, "range": {"start": {"line": 0, "character": 9}, "end": {"line": 0, "character": 1}}}),
    );
    assert_eq!(answer["error"]["code"], -32602, "{answer}");
    // A rename the server refuses: RequestFailed, with the reason.
    let answer = lsp.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": uri}, "position": {"line": 0, "character": 3}, "newName": "B"}),
    );
    assert_eq!(answer["error"]["code"], -32803, "{answer}");
}

#[test]
fn the_edited_document_is_published_before_the_documents_its_edit_breaks() {
    let root = temp_dir("edited-first");
    let defs = "ClassDiagram Defs { public class Image { } }\n";
    let user = |n: u32| format!("ClassDiagram U{n} {{ import Defs.*; public class C {{ public Image i; }} }}\n");
    // The edited file sorts last, so an order by URI would publish it last.
    let files = [("a_user.gudsl", user(1)), ("b_user.gudsl", user(2)), ("z_defs.gudsl", defs.to_string())];
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    let uri = |name: &str| format!("file://{}", root.join(name).display());
    for (name, text) in &files {
        std::fs::write(root.join(name), text).unwrap();
        lsp.open(&uri(name), text);
    }
    let mut unseen: Vec<String> = files.iter().map(|(name, _)| uri(name)).collect();
    while !unseen.is_empty() {
        let published = lsp.notification("textDocument/publishDiagnostics", 20, |_| true).expect("published on open");
        assert_eq!(published["diagnostics"], json!([]), "{published}");
        unseen.retain(|u| published["uri"] != *u);
    }
    // Renaming the class breaks both users; the renamed one's own diagnostics come first.
    let column = defs.find("Image").unwrap() as u32 + 5;
    lsp.change(&uri("z_defs.gudsl"), 2, ((0, column), (0, column)), "X");
    let first = lsp.notification("textDocument/publishDiagnostics", 20, |_| true).expect("a publish");
    assert_eq!(first["uri"], uri("z_defs.gudsl"), "{first}");
    assert_eq!(first["version"], 2, "{first}");
    for name in ["a_user.gudsl", "b_user.gudsl"] {
        let diagnostics = lsp.diagnostics_of(&uri(name), 20).expect("the user is re-checked");
        assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    }
}

#[test]
fn the_bundled_library_is_a_read_only_document_definitions_lead_to() {
    let root = temp_dir("library");
    let kernel = "ClassDiagram K\n{\n    import OpenCL.GPU.*;\n    public class C implements OpenCL\n    {\n        public void m() { var int i = get_global_id(0); }\n    }\n}\n";
    let path = root.join("k.gudsl");
    std::fs::write(&path, kernel).unwrap();
    let uri = format!("file://{}", path.display());
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    lsp.open(&uri, kernel);
    assert_eq!(lsp.diagnostics_of(&uri, 20), Some(vec![]), "the author's import and a built-in resolve");
    // Go to the definition of `get_global_id`: the library's virtual document.
    let (line, character) = client_position(kernel, kernel.find("get_global_id").unwrap());
    let answer = lsp.request(
        "textDocument/definition",
        json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
    );
    let location = &answer["result"][0];
    let library = location["uri"].as_str().expect("a location").to_string();
    assert_eq!(library, "gudsl:/lib/opencl.gudsl", "{answer}");
    // Its text, for a client's read-only view.
    let text = lsp.server_text(&library);
    let text = text.as_str().expect("the library's text");
    let at = location["range"]["start"]["line"].as_u64().unwrap() as usize;
    assert!(
        text.lines().nth(at).unwrap().contains("get_global_id(int dimension)"),
        "{}",
        text.lines().nth(at).unwrap()
    );
    // Opened in the editor, it is not analysed as a second copy, nor published...
    lsp.open(&library, text);
    let published = lsp.notification("textDocument/publishDiagnostics", 3, |p| p["uri"] == library);
    assert_eq!(published, None, "the library is never published");
    // ...and hovering in it works.
    let (line, character) = client_position(text, text.find("get_local_id").unwrap());
    let hover = lsp.hover(&library, line, character);
    assert!(hover["result"]["contents"]["value"].as_str().unwrap_or_default().contains("get_local_id"), "{hover}");
    // A change is refused, and the user is told why.
    lsp.change(&library, 2, ((0, 0), (0, 0)), "garbage ");
    let shown = lsp.notification("window/showMessage", 20, |_| true).expect("the user is told");
    assert!(shown["message"].as_str().unwrap().contains("read-only"), "{shown}");
    assert_eq!(lsp.server_text(&library).as_str(), Some(text));
    // The user's file still resolves against the library (no duplicate of it was added).
    lsp.change(&uri, 2, ((0, 0), (0, 0)), " ");
    assert_eq!(lsp.diagnostics_of(&uri, 20), Some(vec![]));
    // Renaming a library declaration is refused with the reason.
    let (line, character) = client_position(kernel, kernel.find("get_global_id").unwrap());
    let answer = lsp.request(
        "textDocument/rename",
        json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character + 1}, "newName": "x"}),
    );
    assert!(answer["error"]["message"].as_str().unwrap_or_default().contains("read-only"), "{answer}");
}

#[test]
fn a_duplicate_is_published_with_the_first_declaration_as_related_information() {
    let root = temp_dir("related");
    let text = "ClassDiagram A\n{\n    public class C { }\n    public class C { }\n}\n";
    let uri = format!("file://{}", root.join("a.gudsl").display());
    let mut lsp = Lsp::start();
    lsp.initialize_in(Some(&root));
    lsp.open(&uri, text);
    let diagnostics = lsp.diagnostics_of(&uri, 20).expect("published");
    assert_eq!(diagnostics.len(), 1, "{diagnostics:?}");
    let related = &diagnostics[0]["relatedInformation"][0];
    assert_eq!(related["location"]["uri"], json!(uri), "{diagnostics:?}");
    assert_eq!(related["location"]["range"]["start"], json!({"line": 2, "character": 17}), "{diagnostics:?}");
    assert!(related["message"].as_str().unwrap().contains("first declared here"), "{related}");
}
