//! The stdio transport in front of tower-lsp-server. It reads the client's frames itself so that
//! one bad message costs one message, not the session: a body that is not UTF-8 or not JSON is
//! answered with ParseError, a batch, another `jsonrpc` version or an id that is neither a
//! string nor an integer with InvalidRequest, garbage between frames is skipped up to the next
//! `Content-Length` header — and reading goes on. A request for a `$/` method is answered with
//! MethodNotFound (the spec asks for an answer). `exit`, or the end of the input, ends the process
//! at once: code 0 after `shutdown`, else 1. Everything else goes to tower-lsp-server unchanged,
//! and every frame either side writes reaches stdout whole. Stdin and stdout are read and
//! written on two threads of their own, never on tokio's (bounded) blocking pool.

use std::{
    io::{Read, Write},
    process::ExitCode,
};

use serde_json::{json, Value};
use tokio::{
    io::{AsyncRead, AsyncReadExt, AsyncWriteExt},
    sync::{mpsc, oneshot},
};

/// What the reader found next in the input.
#[derive(Debug, PartialEq, Eq)]
pub(super) enum Frame {
    /// A frame's body.
    Body(Vec<u8>),
    /// Bytes that are no frame (skipped up to the next header).
    Garbage,
    /// A header declaring more than [`MAX_MESSAGE_BYTES`]: its body is skipped as garbage.
    TooLong(usize),
}

/// The longest message read (a document of the 16 MiB a model file may hold, JSON-escaped,
/// fits many times): a header declaring more is answered as malformed, not waited for.
pub(super) const MAX_MESSAGE_BYTES: usize = 256 << 20;

/// Splits a byte stream into frames: `Content-Length: N` (any case, among other headers), an
/// empty line, N bytes. It never gives up: whatever is not a frame is reported and skipped.
#[derive(Default)]
pub(super) struct Frames {
    buffer: Vec<u8>,
    /// Garbage was reported and no frame has followed yet: more of it is skipped silently, so
    /// one run of garbage is reported once however the reads cut it.
    skipping: bool,
}

/// What [`Frames::scan`] took off the buffer.
enum Scanned {
    /// Bytes outside any frame (a run of them may come in several pieces).
    Junk,
    /// A header whose length is not a number: one bad frame.
    BadHeader,
    TooLong(usize),
    Body(Vec<u8>),
}

const HEADER: &[u8] = b"content-length:";

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w.eq_ignore_ascii_case(needle))
}

impl Frames {
    pub(super) fn push(&mut self, bytes: &[u8]) {
        self.buffer.extend_from_slice(bytes);
    }

    /// The next frame, if the buffer holds one (or garbage before one); `None`: read more.
    pub(super) fn next(&mut self) -> Option<Frame> {
        loop {
            match self.scan()? {
                Scanned::Junk if self.skipping => continue,
                Scanned::Junk => {
                    self.skipping = true;
                    return Some(Frame::Garbage);
                }
                Scanned::BadHeader => return Some(Frame::Garbage),
                Scanned::TooLong(length) => {
                    // What follows is its body: skipped as garbage, reported with this answer.
                    self.skipping = true;
                    return Some(Frame::TooLong(length));
                }
                Scanned::Body(body) => {
                    self.skipping = false;
                    return Some(Frame::Body(body));
                }
            }
        }
    }

    /// Takes the next thing off the buffer; `None`: read more.
    fn scan(&mut self) -> Option<Scanned> {
        let Some(start) = find(&self.buffer, HEADER) else {
            // Keep a tail that may be the start of a header cut by the read.
            let keep = HEADER.len() - 1;
            if self.buffer.len() > keep
                && self.buffer[..self.buffer.len() - keep].iter().any(|b| !b.is_ascii_whitespace())
            {
                self.buffer.drain(..self.buffer.len() - keep);
                return Some(Scanned::Junk);
            }
            return None;
        };
        // A header starts a line: what stands before it (other than line breaks) is garbage.
        let before = &self.buffer[..start];
        if before.iter().any(|b| !b.is_ascii_whitespace()) {
            self.buffer.drain(..start);
            return Some(Scanned::Junk);
        }
        let end_of_headers = find(&self.buffer[start..], b"\r\n\r\n")? + start;
        let header = &self.buffer[start + HEADER.len()..end_of_headers];
        let line_end = find(header, b"\r\n").unwrap_or(header.len());
        let length = std::str::from_utf8(&header[..line_end]).ok().and_then(|v| v.trim().parse::<usize>().ok());
        let body_start = end_of_headers + 4;
        let Some(length) = length else {
            self.buffer.drain(..body_start);
            return Some(Scanned::BadHeader);
        };
        if length > MAX_MESSAGE_BYTES {
            self.buffer.drain(..body_start);
            return Some(Scanned::TooLong(length));
        }
        if self.buffer.len() < body_start + length {
            return None;
        }
        let body = self.buffer[body_start..body_start + length].to_vec();
        self.buffer.drain(..body_start + length);
        Some(Scanned::Body(body))
    }

    /// Whatever is left when the input ends (an incomplete frame or trailing garbage).
    pub(super) fn has_leftover(&self) -> bool {
        self.buffer.iter().any(|b| !b.is_ascii_whitespace())
    }
}

/// JSON-RPC error codes.
const PARSE_ERROR: i64 = -32700;
const INVALID_REQUEST: i64 = -32600;
const METHOD_NOT_FOUND: i64 = -32601;

fn error(id: Value, code: i64, message: &str) -> Vec<u8> {
    serde_json::to_vec(&json!({"jsonrpc": "2.0", "id": id, "error": {"code": code, "message": message}}))
        .unwrap_or_default()
}

/// What to do with one body from the client.
#[derive(Debug, PartialEq)]
pub(super) enum Verdict {
    /// Pass it to the server (`shutdown`: a shutdown request).
    Forward { shutdown: bool },
    /// Answer it here and drop it.
    Answer(Vec<u8>),
    /// The client said `exit`.
    Exit,
}

/// Checks one body against JSON-RPC 2.0 as LSP uses it.
pub(super) fn judge(body: &[u8]) -> Verdict {
    let Ok(text) = std::str::from_utf8(body) else {
        return Verdict::Answer(error(Value::Null, PARSE_ERROR, "the message is not UTF-8"));
    };
    let message: Value = match serde_json::from_str(text) {
        Ok(message) => message,
        Err(e) => return Verdict::Answer(error(Value::Null, PARSE_ERROR, &format!("the message is not JSON: {e}"))),
    };
    let Value::Object(object) = &message else {
        let what = if message.is_array() { "batches are not part of LSP" } else { "a message is a JSON object" };
        return Verdict::Answer(error(Value::Null, INVALID_REQUEST, what));
    };
    let id = object.get("id");
    let id_is_valid = id.is_none_or(|id| id.is_string() || id.is_i64() || id.is_u64());
    let answer_id = if id_is_valid { id.cloned().unwrap_or(Value::Null) } else { Value::Null };
    if object.get("jsonrpc").and_then(Value::as_str) != Some("2.0") {
        return Verdict::Answer(error(
            answer_id,
            INVALID_REQUEST,
            "only JSON-RPC 2.0 (`\"jsonrpc\": \"2.0\"`) is spoken",
        ));
    }
    if !id_is_valid {
        return Verdict::Answer(error(Value::Null, INVALID_REQUEST, "an id is a string or an integer"));
    }
    let method = object.get("method");
    if method.is_some_and(|m| !m.is_string()) {
        return Verdict::Answer(error(answer_id, INVALID_REQUEST, "a method is a string"));
    }
    let method = method.and_then(Value::as_str);
    if method.is_none() && id.is_none() {
        return Verdict::Answer(error(
            Value::Null,
            INVALID_REQUEST,
            "neither a request, a notification nor a response",
        ));
    }
    match (method, id) {
        (Some("exit"), None) => Verdict::Exit,
        (Some(m), Some(_)) if m.starts_with("$/") => {
            Verdict::Answer(error(answer_id, METHOD_NOT_FOUND, &format!("`{m}` is not supported")))
        }
        (Some("shutdown"), Some(_)) => Verdict::Forward { shutdown: true },
        _ => Verdict::Forward { shutdown: false },
    }
}

/// What the writer is asked.
enum Output {
    Body(Vec<u8>),
    /// Everything before was written and flushed.
    Flushed(oneshot::Sender<()>),
}

/// Writes whole frames to `out`, in the order they come: each batch of waiting frames in one
/// write. It runs on a thread of its own, so writing never waits for a thread of tokio's
/// blocking pool, which analysis work may have taken.
fn write_frames(mut out: impl Write, mut frames: mpsc::UnboundedReceiver<Output>) {
    let mut batch = Vec::new();
    while let Some(first) = frames.blocking_recv() {
        let mut next = Some(first);
        let mut flushed = Vec::new();
        while let Some(output) = next {
            match output {
                Output::Body(body) => {
                    batch.extend_from_slice(format!("Content-Length: {}\r\n\r\n", body.len()).as_bytes());
                    batch.extend_from_slice(&body);
                }
                Output::Flushed(done) => flushed.push(done),
            }
            next = frames.try_recv().ok();
        }
        if !batch.is_empty() && (out.write_all(&batch).is_err() || out.flush().is_err()) {
            return;
        }
        batch.clear();
        for done in flushed {
            let _ = done.send(());
        }
    }
}

/// Reads stdin on a thread of its own (for the same reason as [`write_frames`]) and sends what
/// it reads, chunk by chunk; the channel closes at the end of the input or on an error.
fn read_stdin(chunks: mpsc::Sender<Vec<u8>>) {
    let mut stdin = std::io::stdin().lock();
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        match stdin.read(&mut chunk) {
            Ok(0) => return,
            Ok(n) => {
                if chunks.blocking_send(chunk[..n].to_vec()).is_err() {
                    return;
                }
            }
            Err(error) if error.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(_) => return,
        }
    }
}

/// Copies the server's frames to the writer, frame by frame.
async fn pump(mut from: impl AsyncRead + Unpin, to: mpsc::UnboundedSender<Output>) {
    let mut frames = Frames::default();
    let mut chunk = vec![0u8; 1 << 16];
    loop {
        while let Some(frame) = frames.next() {
            if let Frame::Body(body) = frame {
                if to.send(Output::Body(body)).is_err() {
                    return;
                }
            }
        }
        match from.read(&mut chunk).await {
            Ok(0) | Err(_) => return,
            Ok(n) => frames.push(&chunk[..n]),
        }
    }
}

/// Serves `service` over stdin/stdout until `exit` or the end of the input.
pub(super) async fn serve(
    service: tower_lsp_server::LspService<super::server::Backend>,
    socket: tower_lsp_server::ClientSocket,
) -> ExitCode {
    let (mut to_server, server_input) = tokio::io::duplex(1 << 16);
    let (server_output, from_server) = tokio::io::duplex(1 << 16);
    tokio::spawn(tower_lsp_server::Server::new(server_input, server_output, socket).serve(service));
    let (output, frames) = mpsc::unbounded_channel();
    std::thread::spawn(move || write_frames(std::io::stdout().lock(), frames));
    tokio::spawn(pump(from_server, output.clone()));
    let (chunks, mut input) = mpsc::channel(16);
    std::thread::spawn(move || read_stdin(chunks));

    let mut frames = Frames::default();
    let mut shut_down = false;
    let exit = 'read: loop {
        while let Some(frame) = frames.next() {
            let verdict = match frame {
                Frame::Body(body) => match judge(&body) {
                    Verdict::Forward { shutdown } => {
                        shut_down |= shutdown;
                        let header = format!("Content-Length: {}\r\n\r\n", body.len());
                        let sent = to_server.write_all(header.as_bytes()).await.and(to_server.write_all(&body).await);
                        if sent.is_err() {
                            break 'read shut_down;
                        }
                        continue;
                    }
                    verdict => verdict,
                },
                Frame::Garbage => {
                    Verdict::Answer(error(Value::Null, PARSE_ERROR, "bytes that are no LSP frame were skipped"))
                }
                Frame::TooLong(length) => Verdict::Answer(error(
                    Value::Null,
                    PARSE_ERROR,
                    &format!("a message of {length} bytes, more than the {MAX_MESSAGE_BYTES} read: skipped"),
                )),
            };
            match verdict {
                Verdict::Answer(body) => {
                    let _ = output.send(Output::Body(body));
                }
                Verdict::Exit => break 'read shut_down,
                Verdict::Forward { .. } => {}
            }
        }
        match input.recv().await {
            None => {
                if frames.has_leftover() {
                    let _ =
                        output.send(Output::Body(error(Value::Null, PARSE_ERROR, "the input ended inside a frame")));
                }
                break shut_down;
            }
            Some(chunk) => frames.push(&chunk),
        }
    };
    // Write what is pending (the shutdown answer, error answers), then leave.
    let (done, flushed) = oneshot::channel();
    if output.send(Output::Flushed(done)).is_ok() {
        let _ = tokio::time::timeout(std::time::Duration::from_secs(2), flushed).await;
    }
    if exit {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(body: &str) -> Vec<u8> {
        format!("Content-Length: {}\r\n\r\n{body}", body.len()).into_bytes()
    }

    #[test]
    fn frames_split_anywhere_and_garbage_is_skipped_to_the_next_header() {
        let mut input = frame(r#"{"a":1}"#);
        input.extend_from_slice(b"junk that is no frame\r\n");
        input.extend(frame(r#"{"b":2}"#));
        input.extend_from_slice(b"content-length: 3\r\nContent-Type: x\r\n\r\n{}x");
        // Cut in two at every place, and fed byte by byte (usize::MAX).
        for cut in (1..input.len()).chain([usize::MAX]) {
            let mut frames = Frames::default();
            let mut seen = Vec::new();
            let pieces: Vec<&[u8]> =
                if cut == usize::MAX { input.chunks(1).collect() } else { vec![&input[..cut], &input[cut..]] };
            for piece in pieces {
                frames.push(piece);
                while let Some(f) = frames.next() {
                    seen.push(f);
                }
            }
            let bodies: Vec<&Frame> = seen.iter().filter(|f| matches!(f, Frame::Body(_))).collect();
            assert_eq!(
                bodies,
                [
                    &Frame::Body(br#"{"a":1}"#.to_vec()),
                    &Frame::Body(br#"{"b":2}"#.to_vec()),
                    &Frame::Body(b"{}x".to_vec())
                ],
                "cut at {cut}"
            );
            // One run of garbage is answered once, however the reads cut it.
            assert_eq!(seen.iter().filter(|f| **f == Frame::Garbage).count(), 1, "cut at {cut}");
        }
    }

    #[test]
    fn malformed_bodies_are_answered_and_good_ones_forwarded() {
        let code = |body: &[u8]| match judge(body) {
            Verdict::Answer(answer) => serde_json::from_slice::<Value>(&answer).unwrap()["error"]["code"].as_i64(),
            _ => None,
        };
        assert_eq!(code(b"{not json"), Some(PARSE_ERROR));
        assert_eq!(code(b"{\"jsonrpc\":\"2.0\",\"method\":\"x\",\"params\":\"\xff\"}"), Some(PARSE_ERROR));
        assert_eq!(code(br#"[{"jsonrpc":"2.0","id":1,"method":"shutdown"}]"#), Some(INVALID_REQUEST));
        assert_eq!(code(br#"{"jsonrpc":"1.0","id":1,"method":"shutdown"}"#), Some(INVALID_REQUEST));
        assert_eq!(code(br#"{"jsonrpc":"2.0","id":1.5,"method":"shutdown"}"#), Some(INVALID_REQUEST));
        assert_eq!(code(br#"{"jsonrpc":"2.0","id":3,"method":"$/unknown"}"#), Some(METHOD_NOT_FOUND));
        assert_eq!(
            judge(br#"{"jsonrpc":"2.0","method":"$/cancelRequest","params":{"id":1}}"#),
            Verdict::Forward { shutdown: false }
        );
        assert_eq!(judge(br#"{"jsonrpc":"2.0","id":"a","method":"shutdown"}"#), Verdict::Forward { shutdown: true });
        assert_eq!(judge(br#"{"jsonrpc":"2.0","method":"exit"}"#), Verdict::Exit);
        assert_eq!(judge(br#"{"jsonrpc":"2.0","id":7,"result":null}"#), Verdict::Forward { shutdown: false });
    }
}
