//! `gudsl lsp`: the language server over stdio (tower-lsp-server on tokio, behind our own
//! transport: `transport.rs`).
//!
//! The model's analysis host applies edits; every request runs on a snapshot in a blocking task,
//! so the message loop never waits for analysis and a newer edit cancels stale work. Positions
//! are converted only in `from_proto` and `to_proto`. See ARCHITECTURE.md, "The language server".

mod capabilities;
mod execute;
mod ext;
mod extensions;
mod from_proto;
mod graph;
mod graph_edit;
mod handlers;
mod host;
mod jobs;
mod parameters;
mod pipeline;
mod preview;
mod run;
mod scenes;
mod server;
mod to_proto;
mod transport;
mod wgsl;

#[cfg(test)]
mod tests;

use std::{process::ExitCode, sync::Mutex, time::Duration};

use tower_lsp_server::jsonrpc::{Error, ErrorCode};

/// The fewest threads requests and diagnostics run on (a slow request, the diagnostics of an
/// edit and a hover at once, and one to spare). Stdin and stdout have threads of their own.
const BLOCKING_THREADS: usize = 4;

/// How long the server waits for the client's answer to a request of its own before going on
/// without (progress reporting); a client that never answers must not stall the server.
const CLIENT_ANSWER: Duration = Duration::from_secs(2);

fn lock<T>(mutex: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    mutex.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

/// What a caught panic said (its message, when it has one).
fn panic_text(panic: &(dyn std::any::Any + Send)) -> String {
    panic
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into())
}

/// A request the server understood but cannot do (a rename it refuses), with the reason for
/// the user: LSP's RequestFailed.
fn request_failed(message: String) -> Error {
    Error { code: ErrorCode::ServerError(-32803), message: message.into(), data: None }
}

/// A request whose parameters are wrong.
fn invalid_params(message: String) -> Error {
    Error { code: ErrorCode::InvalidParams, message: message.into(), data: None }
}

/// Serves LSP on stdin/stdout until the client exits.
pub fn run() -> ExitCode {
    // Analysis recursion is bounded by the parser's depth limit; the stacks leave room to spare.
    // The blocking pool is bounded: every thread that allocates gets its own glibc malloc arena,
    // which keeps what was freed in it, so an unbounded pool grew the resident set while typing
    // (bench.py linked: +11 % after 200 keystrokes).
    let threads = std::thread::available_parallelism().map_or(BLOCKING_THREADS, |n| n.get().max(BLOCKING_THREADS));
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .max_blocking_threads(threads)
        .thread_stack_size(16 << 20)
        .enable_all()
        .build();
    let runtime = match runtime {
        Ok(runtime) => runtime,
        Err(error) => {
            eprintln!("gudsl lsp: cannot start the async runtime: {error}");
            return ExitCode::from(2);
        }
    };
    let code = runtime.block_on(async {
        let (service, socket) = tower_lsp_server::LspService::build(server::Backend::new)
            .custom_method("gudsl/viewFileText", server::Backend::view_file_text)
            .custom_method("gudsl/diagrams", server::Backend::diagrams)
            .custom_method("gudsl/graph", server::Backend::graph)
            .custom_method("gudsl/applyGraphEdit", server::Backend::apply_graph_edit)
            .custom_method("gudsl/parameters", server::Backend::parameters)
            .custom_method("gudsl/setParameter", server::Backend::set_parameter)
            .custom_method("window/workDoneProgress/cancel", server::Backend::work_done_progress_cancel)
            .finish();
        transport::serve(service, socket).await
    });
    // Requests still running and the blocked read of stdin are not waited for.
    runtime.shutdown_background();
    code
}
