//! `gudsl lsp` against hostile clients, byte for byte over stdio: documents that used to crash
//! the server, malformed messages, requests the spec says must be answered, and exits. After
//! each hostile input a valid request must still be answered.

use std::{
    io::{BufRead, BufReader, Read, Write},
    process::{Child, ChildStdin, Command, Stdio},
    sync::mpsc::{self, Receiver},
    time::Duration,
};

use serde_json::{json, Value};

/// The server as a client sees it: frames out, frames in (read on a thread, so a test can
/// wait with a timeout).
struct Lsp {
    child: Child,
    stdin: Option<ChildStdin>,
    messages: Receiver<Value>,
    next_id: i64,
}

impl Lsp {
    fn start() -> Lsp {
        let mut child = Command::new(env!("CARGO_BIN_EXE_gudsl"))
            .arg("lsp")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let stdout = child.stdout.take().unwrap();
        let stdin = child.stdin.take();
        let (sender, messages) = mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(stdout);
            loop {
                let mut length = None;
                loop {
                    let mut line = String::new();
                    if reader.read_line(&mut line).unwrap_or(0) == 0 {
                        return;
                    }
                    let line = line.trim_end();
                    if line.is_empty() {
                        break;
                    }
                    if let Some(value) = line.strip_prefix("Content-Length: ") {
                        length = value.parse::<usize>().ok();
                    }
                }
                let mut body = vec![0; length.unwrap_or(0)];
                if reader.read_exact(&mut body).is_err() {
                    return;
                }
                match serde_json::from_slice(&body) {
                    Ok(value) => {
                        if sender.send(value).is_err() {
                            return;
                        }
                    }
                    Err(_) => return,
                }
            }
        });
        Lsp { child, stdin, messages, next_id: 1 }
    }

    /// Writes raw bytes (a frame, or garbage).
    fn raw(&mut self, bytes: &[u8]) {
        let stdin = self.stdin.as_mut().unwrap();
        stdin.write_all(bytes).unwrap();
        stdin.flush().unwrap();
    }

    fn send(&mut self, message: &Value) {
        let body = serde_json::to_vec(message).unwrap();
        self.raw(format!("Content-Length: {}\r\n\r\n", body.len()).as_bytes());
        self.raw(&body);
    }

    fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and waits for its response, answering the server's own requests.
    fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        self.response_to(&json!(id))
    }

    fn response_to(&mut self, id: &Value) -> Value {
        loop {
            let message = self
                .messages
                .recv_timeout(Duration::from_secs(20))
                .unwrap_or_else(|_| panic!("no response to request {id} within 20 s"));
            if message.get("method").is_some() && message.get("id").is_some() {
                // A request of the server's (registerCapability, progress): answer it.
                self.send(&json!({"jsonrpc": "2.0", "id": message["id"], "result": null}));
                continue;
            }
            if message.get("id") == Some(id) {
                return message;
            }
        }
    }

    fn initialize(&mut self) {
        let response = self.request("initialize", json!({"processId": null, "rootUri": null, "capabilities": {}}));
        assert!(response["result"]["capabilities"].is_object(), "{response}");
        self.notify("initialized", json!({}));
    }

    fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}}),
        );
    }

    fn hover(&mut self, uri: &str, line: u32, character: u32) -> Value {
        self.request(
            "textDocument/hover",
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        )
    }
}

impl Drop for Lsp {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

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
