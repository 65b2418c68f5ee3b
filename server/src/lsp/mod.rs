//! `gudsl lsp`: the language server over stdio (tower-lsp-server on tokio).
//!
//! The analysis host (a salsa database) applies edits; every request runs on a snapshot in a
//! blocking task, so the message loop never waits for analysis and a newer edit cancels stale
//! work. See DESIGN.md, "Server conventions".

mod convert;
mod handlers;
mod host;
mod server;

use std::process::ExitCode;

/// Serves LSP on stdin/stdout until the client exits.
pub fn run() -> ExitCode {
    let runtime = match tokio::runtime::Builder::new_multi_thread().enable_all().build() {
        Ok(runtime) => runtime,
        Err(error) => {
            eprintln!("gudsl lsp: cannot start the async runtime: {error}");
            return ExitCode::from(2);
        }
    };
    runtime.block_on(async {
        let (service, socket) = tower_lsp_server::LspService::new(server::Backend::new);
        tower_lsp_server::Server::new(tokio::io::stdin(), tokio::io::stdout(), socket).serve(service).await;
    });
    ExitCode::SUCCESS
}
