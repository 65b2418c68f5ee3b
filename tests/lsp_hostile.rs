//! `gudsl lsp` against hostile clients, byte for byte over stdio: documents that used to crash
//! the server, malformed messages, requests the spec says must be answered, and exits. After
//! each hostile input a valid request must still be answered.

#[path = "support/raw_lsp.rs"]
mod raw_lsp;

use raw_lsp::Lsp;
use serde_json::{json, Value};

const SMALL: &str = "ClassDiagram Defs\n{\n    public class Image\n    {\n        public int width;\n    }\n}\n";

#[test]
fn a_hundred_thousand_link_chain_on_did_open_does_not_kill_the_server() {
    let mut lsp = Lsp::start();
    lsp.initialize();
    for chain in [
        format!("x = {};", vec!["1"; 100_000].join(" + ")),
        format!("x = y{};", ".b".repeat(100_000)),
        format!("x = y{};", "[0]".repeat(100_000)),
        format!("x = f{};", "()".repeat(100_000)),
    ] {
        let text =
            format!("ActivityDiagram A(int x, int y) {{ swimlane L {{ start S {{ {chain} => f; }} final f; }} }}\n");
        lsp.open("file:///ws/chain.gudsl", &text);
        lsp.open("file:///ws/defs.gudsl", SMALL);
        let hover = lsp.hover("file:///ws/defs.gudsl", 2, 19);
        assert!(hover["result"]["contents"]["value"].as_str().is_some_and(|v| v.contains("class Image")), "{hover}");
        lsp.notify("textDocument/didClose", json!({"textDocument": {"uri": "file:///ws/chain.gudsl"}}));
    }
    assert!(lsp.child.try_wait().unwrap().is_none(), "the server exited");
}

fn frame(body: &[u8]) -> Vec<u8> {
    let mut out = format!("Content-Length: {}\r\n\r\n", body.len()).into_bytes();
    out.extend_from_slice(body);
    out
}

#[test]
fn a_malformed_message_costs_one_answer_not_the_session() {
    let mut lsp = Lsp::start();
    lsp.initialize();
    lsp.open("file:///ws/defs.gudsl", SMALL);
    let counted_in_characters = r#"{"jsonrpc":"2.0","method":"window/logMessage","params":{"message":"é"}}"#;
    let cases: Vec<(&str, Vec<u8>, i64)> = vec![
        ("not JSON", b"Content-Length: 9\r\n\r\n{not json".to_vec(), -32700),
        ("invalid UTF-8", frame(b"{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"params\":\"\xff\xfe\"}"), -32700),
        (
            "length counted in characters",
            [
                format!("Content-Length: {}\r\n\r\n", counted_in_characters.chars().count()).as_bytes(),
                counted_in_characters.as_bytes(),
            ]
            .concat(),
            -32700,
        ),
        ("fractional id", frame(br#"{"jsonrpc":"2.0","id":1.5,"method":"shutdown"}"#), -32600),
        ("batch", frame(br#"[{"jsonrpc":"2.0","id":90,"method":"shutdown"}]"#), -32600),
        ("JSON-RPC 1.0", frame(br#"{"jsonrpc":"1.0","id":91,"method":"shutdown"}"#), -32600),
        ("garbage between frames", b"GET / HTTP/1.1\r\n\r\n".to_vec(), -32700),
        (
            "a length of a terabyte",
            b"Content-Length: 1000000000000\r\n\r\n{\"jsonrpc\":\"2.0\",\"id\":92,\"method\":\"shutdown\"}".to_vec(),
            -32700,
        ),
    ];
    for (what, bytes, code) in cases {
        lsp.raw(&bytes);
        let id = if what == "JSON-RPC 1.0" { json!(91) } else { Value::Null };
        assert_eq!(lsp.error_answer(id), code, "{what}");
        // The session goes on: a valid request is answered.
        let hover = lsp.hover("file:///ws/defs.gudsl", 2, 19);
        assert!(
            hover["result"]["contents"]["value"].as_str().is_some_and(|v| v.contains("class Image")),
            "{what}: {hover}"
        );
    }
}

#[test]
fn dollar_requests_are_answered_with_method_not_found() {
    let mut lsp = Lsp::start();
    lsp.initialize();
    let answer = lsp.request("$/gudsl/unknown", json!({}));
    assert_eq!(answer["error"]["code"], -32601, "{answer}");
    // `$/` notifications (cancel, progress) are fine and unanswered.
    lsp.notify("$/cancelRequest", json!({"id": 1}));
    let answer = lsp.request("workspace/symbol", json!({"query": ""}));
    assert!(answer["result"].is_array(), "{answer}");
}

/// A server past `initialize` and `initialized`, whose own requests (registerCapability) this
/// client never answers.
fn initialized_leaving_the_servers_requests_unanswered(root_uri: Value, capabilities: Value) -> Lsp {
    let mut lsp = Lsp::start();
    lsp.send(&json!({"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {
        "processId": null, "rootUri": root_uri, "capabilities": capabilities}}));
    let answer = lsp.next_message(20).expect("the initialize answer");
    assert_eq!(answer["id"], 1, "{answer}");
    lsp.notify("initialized", json!({}));
    lsp
}

#[test]
fn exit_ends_the_process_with_the_code_the_spec_asks_for() {
    // After shutdown: 0.
    let mut lsp = Lsp::start();
    lsp.initialize();
    let answer = lsp.request("shutdown", Value::Null);
    assert!(answer.get("error").is_none(), "{answer}");
    lsp.notify("exit", Value::Null);
    assert_eq!(lsp.exit_code(5), Some(0));
    // Without shutdown: 1, even right after `initialized` with the server's own requests unanswered.
    let mut lsp = initialized_leaving_the_servers_requests_unanswered(Value::Null, json!({}));
    lsp.notify("exit", Value::Null);
    assert_eq!(lsp.exit_code(5), Some(1));
    // The end of the input, right after `initialized`: the process ends too.
    let mut lsp = initialized_leaving_the_servers_requests_unanswered(Value::Null, json!({}));
    lsp.stdin = None;
    assert_eq!(lsp.exit_code(5), Some(1));
}

#[test]
fn a_client_that_never_answers_the_servers_requests_still_gets_its_workspace() {
    let root = std::env::temp_dir().join(format!("gudsl-hostile-ws-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    std::fs::write(root.join("broken.gudsl"), "ClassDiagram D { class C { public Missing m; } }\n").unwrap();
    let root_uri = format!("file://{}", root.display());
    let mut lsp = initialized_leaving_the_servers_requests_unanswered(
        json!(root_uri),
        json!({"window": {"workDoneProgress": true}}),
    );
    // Never answer registerCapability or workDoneProgress/create: diagnostics still come.
    let mut published = None;
    while let Some(message) = lsp.next_message(20) {
        if message["method"] == "textDocument/publishDiagnostics" {
            published = Some(message);
            break;
        }
    }
    let published = published.expect("diagnostics for the workspace without answering the server's requests");
    assert!(published["params"]["uri"].as_str().unwrap().ends_with("broken.gudsl"), "{published}");
    assert_eq!(published["params"]["diagnostics"][0]["code"], "E0201", "{published}");
    let _ = std::fs::remove_dir_all(&root);
}
