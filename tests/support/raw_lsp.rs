//! A raw LSP client for the end-to-end tests: frames written byte for byte to the real
//! `gudsl lsp`, messages read on a thread so a test can wait with a timeout, and the server's
//! own requests answered.

#![allow(dead_code)] // Each test file uses its part.

use std::{
    io::{BufRead, BufReader, Read, Write},
    process::{Child, ChildStdin, Command, Stdio},
    sync::mpsc::{self, Receiver},
    time::Duration,
};

use serde_json::{json, Value};

/// The server as a client sees it: frames out, frames in (read on a thread, so a test can
/// wait with a timeout).
pub struct Lsp {
    pub child: Child,
    pub stdin: Option<ChildStdin>,
    messages: Receiver<Value>,
    next_id: i64,
}

impl Lsp {
    pub fn start() -> Lsp {
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
    pub fn raw(&mut self, bytes: &[u8]) {
        let stdin = self.stdin.as_mut().unwrap();
        stdin.write_all(bytes).unwrap();
        stdin.flush().unwrap();
    }

    pub fn send(&mut self, message: &Value) {
        let body = serde_json::to_vec(message).unwrap();
        self.raw(format!("Content-Length: {}\r\n\r\n", body.len()).as_bytes());
        self.raw(&body);
    }

    pub fn notify(&mut self, method: &str, params: Value) {
        self.send(&json!({"jsonrpc": "2.0", "method": method, "params": params}));
    }

    /// Sends a request and waits for its response, answering the server's own requests.
    pub fn request(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        self.send(&json!({"jsonrpc": "2.0", "id": id, "method": method, "params": params}));
        self.response_to(&json!(id))
    }

    pub fn response_to(&mut self, id: &Value) -> Value {
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

    pub fn initialize(&mut self) {
        self.initialize_in(None);
    }

    /// Initializes with a workspace folder (`rootUri`), if any.
    pub fn initialize_in(&mut self, root: Option<&std::path::Path>) {
        let root_uri = root.map(|r| format!("file://{}", r.display()));
        let response = self.request("initialize", json!({"processId": null, "rootUri": root_uri, "capabilities": {}}));
        assert!(response["result"]["capabilities"].is_object(), "{response}");
        self.notify("initialized", json!({}));
    }

    /// The next notification `method` for which `wanted` holds, within `seconds` (the server's
    /// requests are answered meanwhile); `None` if none came.
    pub fn notification(&mut self, method: &str, seconds: u64, wanted: impl Fn(&Value) -> bool) -> Option<Value> {
        self.notification_within(method, Duration::from_secs(seconds), wanted)
    }

    /// [`Lsp::notification`] within `wait`.
    pub fn notification_within(
        &mut self,
        method: &str,
        wait: Duration,
        wanted: impl Fn(&Value) -> bool,
    ) -> Option<Value> {
        let deadline = std::time::Instant::now() + wait;
        loop {
            let left = deadline.checked_duration_since(std::time::Instant::now())?;
            let message = self.messages.recv_timeout(left).ok()?;
            if message.get("method").is_some() && message.get("id").is_some() {
                self.send(&json!({"jsonrpc": "2.0", "id": message["id"], "result": null}));
                continue;
            }
            if message["method"] == method && wanted(&message["params"]) {
                return Some(message["params"].clone());
            }
        }
    }

    /// The published diagnostics of `uri`, the next time they are published.
    pub fn diagnostics_of(&mut self, uri: &str, seconds: u64) -> Option<Vec<Value>> {
        let params = self.notification("textDocument/publishDiagnostics", seconds, |p| p["uri"] == uri)?;
        Some(params["diagnostics"].as_array().cloned().unwrap_or_default())
    }

    /// The text the server holds for `uri` (`gudsl/viewFileText`).
    pub fn server_text(&mut self, uri: &str) -> Value {
        self.request("gudsl/viewFileText", json!({"uri": uri}))["result"].clone()
    }

    /// Sends one incremental change: `((line, character), (line, character))` and its text.
    pub fn change(&mut self, uri: &str, version: i32, range: ((u32, u32), (u32, u32)), text: &str) {
        let ((l1, c1), (l2, c2)) = range;
        self.notify(
            "textDocument/didChange",
            json!({"textDocument": {"uri": uri, "version": version}, "contentChanges": [{
                "range": {"start": {"line": l1, "character": c1}, "end": {"line": l2, "character": c2}},
                "text": text}]}),
        );
    }

    pub fn open(&mut self, uri: &str, text: &str) {
        self.notify(
            "textDocument/didOpen",
            json!({"textDocument": {"uri": uri, "languageId": "gudsl", "version": 1, "text": text}}),
        );
    }

    pub fn hover(&mut self, uri: &str, line: u32, character: u32) -> Value {
        self.request(
            "textDocument/hover",
            json!({"textDocument": {"uri": uri}, "position": {"line": line, "character": character}}),
        )
    }

    /// The next message the server sends (requests of its own included), within `seconds`.
    pub fn next_message(&mut self, seconds: u64) -> Option<Value> {
        self.messages.recv_timeout(Duration::from_secs(seconds)).ok()
    }

    /// Waits for the server to exit; its code, or `None` if it is still running after `seconds`.
    pub fn exit_code(&mut self, seconds: u64) -> Option<i32> {
        let deadline = std::time::Instant::now() + Duration::from_secs(seconds);
        while std::time::Instant::now() < deadline {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status.code();
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        None
    }

    /// The next error answer with this id (`null` for a message without a usable id).
    pub fn error_answer(&mut self, id: Value) -> i64 {
        loop {
            let message = self.next_message(20).expect("an error answer within 20 s");
            if message.get("method").is_some() && message.get("id").is_some() {
                self.send(&json!({"jsonrpc": "2.0", "id": message["id"], "result": null}));
                continue;
            }
            if message.get("id") == Some(&id) && message.get("error").is_some() {
                return message["error"]["code"].as_i64().unwrap();
            }
        }
    }
}

impl Drop for Lsp {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}
