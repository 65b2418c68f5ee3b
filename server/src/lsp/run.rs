//! ▶ Run in the editor: `gudsl.run` prepares a host diagram on a snapshot — refused, with every
//! problem's place, when the model has errors or the diagram cannot run (E0302) — and runs it
//! on a thread of its own with the snapshot released, so editing goes on meanwhile. Nodes are
//! reported as `$/progress`, `printf` output as log messages; the run stops between nodes when
//! the client cancels the progress (`window/workDoneProgress/cancel`) or the request
//! (`$/cancelRequest`). Viewer images and `report.json` go to the folder the command names, by
//! default `<temp>/gudsl-run/<diagram>`.

use std::{
    collections::HashMap,
    path::PathBuf,
    sync::{
        atomic::{AtomicBool, AtomicU64, Ordering},
        Arc, Mutex,
    },
    time::{Duration, Instant},
};

use gudsl_host::run::{Observer, Prepared, RunError, RunErrorKind};
use gudsl_model::{
    hir::{DiagnosticCode, Severity},
    text::LineIndex,
    Cancellable, FileId,
};
use serde_json::{json, Value};
use tokio::sync::{mpsc, oneshot};
use tower_lsp_server::{ls_types as lsp, Client};

use tower_lsp_server::jsonrpc::{self, Error};

use super::{
    capabilities::Encoding,
    host::Snapshot,
    server::{request_failed, Backend, CLIENT_ANSWER},
    to_proto,
};
use crate::commands::run as cli;

/// The command that runs a diagram: its name (simple or fully qualified), or
/// `{"diagram": name, "output": folder}`.
pub const RUN: &str = "gudsl.run";

/// How often a run's progress is reported at most (nodes and printed text in between are
/// gathered).
const REPORT_EVERY: Duration = Duration::from_millis(100);

/// What the command asks for.
pub struct RunRequest {
    pub diagram: String,
    pub output: PathBuf,
}

impl RunRequest {
    pub fn parse(argument: Option<&Value>) -> Result<RunRequest, String> {
        let (diagram, output) = match argument {
            Some(Value::String(name)) => (name.clone(), None),
            Some(Value::Object(fields)) => match (fields.get("diagram"), fields.get("output")) {
                (Some(Value::String(name)), None | Some(Value::Null)) => (name.clone(), None),
                (Some(Value::String(name)), Some(Value::String(folder))) => (name.clone(), Some(folder_path(folder))),
                _ => return Err(argument_error()),
            },
            _ => return Err(argument_error()),
        };
        let output = output.unwrap_or_else(|| std::env::temp_dir().join("gudsl-run").join(&diagram));
        Ok(RunRequest { diagram, output })
    }
}

/// A folder given as a path or a `file:` URI.
fn folder_path(folder: &str) -> PathBuf {
    match folder.parse::<lsp::Uri>().ok().and_then(|uri| uri.to_file_path().map(|p| p.into_owned())) {
        Some(path) if folder.starts_with("file:") => path,
        _ => PathBuf::from(folder),
    }
}

fn argument_error() -> String {
    format!("{RUN} takes a diagram's name or {{\"diagram\": name, \"output\": folder}}")
}

/// A command refused before anything ran: why, and each problem with its place.
pub struct Refusal {
    pub message: String,
    pub problems: Vec<Value>,
}

/// A diagram ready to run, and where its errors are placed afterwards.
pub struct Ready {
    pub prepared: Prepared,
    pub places: Places,
}

/// The files of the diagram and of those it calls as they were when the run started: run
/// errors are placed in them.
pub struct Places {
    files: Vec<(FileId, Option<lsp::Uri>, LineIndex)>,
    encoding: Encoding,
}

/// Prepares the diagram named `name`; refused when any document of the workspace has errors
/// (as `gudsl run` refuses), when no diagram or several have the name, or when it cannot run.
pub fn prepare(snap: &Snapshot, name: &str) -> Cancellable<Result<Ready, Refusal>> {
    let mut files: Vec<(&str, FileId)> = snap.documents.iter().map(|d| (d.uri.as_str(), d.file)).collect();
    files.sort_by_key(|(uri, _)| *uri);
    let files: Vec<FileId> = files.into_iter().map(|(_, file)| file).collect();
    let mut problems = Vec::new();
    let mut first = None;
    for &file in &files {
        let (diagnostics, index) = snap.analysis.diagnostics(file)?;
        for d in diagnostics.iter().filter(|d| d.severity == Severity::Error) {
            first.get_or_insert_with(|| format!("{}: {}", place(snap, file, index, d.range), d.message));
            problems.push(problem(snap, file, index, d.range, d.code, &d.message));
        }
    }
    if let Some(first) = first {
        let message =
            format!("the model has {} error(s); `{name}` runs once they are fixed (first: {first})", problems.len());
        return Ok(Err(Refusal { message, problems }));
    }
    let prepared = snap.analysis.with_semantics(|sema| cli::prepare_named(sema, &files, name))?;
    let errors = match prepared {
        Err(message) => return Ok(Err(Refusal { message, problems: Vec::new() })),
        Ok(Ok(prepared)) => {
            let mut places = Places { files: Vec::new(), encoding: snap.encoding };
            for file in prepared.files() {
                places.files.push((file, snap.uri_of(file), snap.analysis.line_index(file)?.clone()));
            }
            return Ok(Ok(Ready { prepared, places }));
        }
        Ok(Err(errors)) => errors,
    };
    let mut first = None;
    for error in &errors {
        let Some(span) = error.span else { continue };
        let index = snap.analysis.line_index(span.file)?;
        first.get_or_insert_with(|| format!("{}: {}", place(snap, span.file, index, span.range), error.message));
        problems.push(problem(snap, span.file, index, span.range, DiagnosticCode::NotRunnable, &error.message));
    }
    let first = first.unwrap_or_else(|| errors.first().map(|e| e.message.clone()).unwrap_or_default());
    let message = format!("`{name}` cannot run ({} problem(s)); first: {first}", errors.len());
    Ok(Err(Refusal { message, problems }))
}

/// `path:line:column` of a range's start, for messages.
fn place(snap: &Snapshot, file: FileId, index: &LineIndex, range: gudsl_model::syntax::TextRange) -> String {
    to_proto::place(snap.analysis.file_path(file), index, range, snap.encoding)
}

fn problem(
    snap: &Snapshot,
    file: FileId,
    index: &LineIndex,
    range: gudsl_model::syntax::TextRange,
    code: DiagnosticCode,
    message: &str,
) -> Value {
    json!({
        "uri": snap.uri_of(file).map(|uri| uri.as_str().to_string()),
        "range": to_proto::range(index, range, snap.encoding),
        "code": code.as_str(),
        "message": message,
    })
}

/// The cancellation flags of the runs under way, by progress token.
#[derive(Default)]
pub struct Runs {
    flags: Mutex<HashMap<String, Arc<AtomicBool>>>,
    next: AtomicU64,
}

impl Runs {
    /// A fresh token for a run the client gave none for.
    pub fn new_token(&self) -> lsp::ProgressToken {
        lsp::ProgressToken::String(format!("gudsl/run/{}", self.next.fetch_add(1, Ordering::SeqCst) + 1))
    }

    /// Registers a run under `token`; its flag is set by [`Runs::cancel`] or when the returned
    /// guard is dropped (the request was cancelled, or finished).
    pub fn start(self: &Arc<Self>, token: &lsp::ProgressToken) -> RunGuard {
        let flag = Arc::new(AtomicBool::new(false));
        let key = token_key(token);
        super::server::lock(&self.flags).insert(key.clone(), flag.clone());
        RunGuard { runs: self.clone(), key, flag, progress: None }
    }

    /// Stops the run reporting progress under `token`; false if there is none.
    pub fn cancel(&self, token: &lsp::ProgressToken) -> bool {
        let flags = super::server::lock(&self.flags);
        let flag = flags.get(&token_key(token));
        flag.inspect(|flag| flag.store(true, Ordering::SeqCst)).is_some()
    }
}

fn token_key(token: &lsp::ProgressToken) -> String {
    match token {
        lsp::ProgressToken::Number(n) => format!("#{n}"),
        lsp::ProgressToken::String(s) => s.clone(),
    }
}

/// A run under way: stops it when dropped, and ends its progress if the request was dropped
/// before it could (`$/cancelRequest`), so no client shows a run that no longer goes on.
pub struct RunGuard {
    runs: Arc<Runs>,
    key: String,
    flag: Arc<AtomicBool>,
    progress: Option<(Client, lsp::ProgressToken)>,
}

impl RunGuard {
    /// The flag the run watches.
    pub fn stop_flag(&self) -> Arc<AtomicBool> {
        self.flag.clone()
    }

    /// The run reports progress under `token` (`None`: it reports none, or it ended it itself).
    fn reports(&mut self, progress: Option<(Client, lsp::ProgressToken)>) {
        self.progress = progress;
    }
}

impl Drop for RunGuard {
    fn drop(&mut self) {
        self.flag.store(true, Ordering::SeqCst);
        super::server::lock(&self.runs.flags).remove(&self.key);
        let Some((client, token)) = self.progress.take() else { return };
        let Ok(runtime) = tokio::runtime::Handle::try_current() else { return };
        let end = lsp::WorkDoneProgressEnd { message: Some("cancelled".into()) };
        let params =
            lsp::ProgressParams { token, value: lsp::ProgressParamsValue::WorkDone(lsp::WorkDoneProgress::End(end)) };
        runtime.spawn(async move { client.send_notification::<lsp::notification::Progress>(params).await });
    }
}

/// What a run tells the editor as it goes.
pub enum Event {
    /// The node running now.
    Node(String),
    /// Text `printf` wrote since the last event.
    Printed(String),
}

/// How a run ended, made on the run's thread (the report itself stays there).
pub struct Finished {
    /// One line: how it ended, in how long.
    pub summary: String,
    /// `report.json` as written, or why it was not.
    pub report: Result<Value, String>,
    pub error: Option<RunError>,
}

/// Runs `prepared` on a thread of its own (the GPU device is made there: it cannot move between
/// threads), sending events as it goes; the answer comes once it ended.
pub fn spawn(
    prepared: Prepared,
    output: PathBuf,
    stop: Arc<AtomicBool>,
    events: mpsc::UnboundedSender<Event>,
) -> oneshot::Receiver<Result<Finished, String>> {
    let (answer, finished) = oneshot::channel();
    let work = move || {
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            let gpu = gudsl_runtime::Gpu::new().map_err(|error| {
                format!("no GPU adapter ({error}); without a GPU, install Mesa's Vulkan driver (Debian: mesa-vulkan-drivers)")
            })?;
            let mut observer = Reporter { events, stop, last: None, printed: String::new() };
            let report = prepared.run(&gpu, &output, &mut observer);
            observer.flush();
            Ok(Finished {
                summary: cli::summary(&report),
                report: cli::write_report(&report, &output),
                error: report.outcome.err(),
            })
        }));
        let _ = answer.send(
            outcome.unwrap_or_else(|_| Err("the run failed unexpectedly (a panic; see the server's log)".into())),
        );
    };
    let spawned = std::thread::Builder::new().name("gudsl run".into()).stack_size(16 << 20).spawn(work);
    if let Err(error) = spawned {
        let (answer, finished) = oneshot::channel();
        let _ = answer.send(Err(format!("cannot start the run's thread: {error}")));
        return finished;
    }
    finished
}

/// The run's observer: events, at most one per [`REPORT_EVERY`], and the stop flag.
struct Reporter {
    events: mpsc::UnboundedSender<Event>,
    stop: Arc<AtomicBool>,
    last: Option<Instant>,
    printed: String,
}

impl Reporter {
    fn due(&mut self) -> bool {
        let due = self.last.is_none_or(|last| last.elapsed() >= REPORT_EVERY);
        if due {
            self.last = Some(Instant::now());
        }
        due
    }

    fn flush(&mut self) {
        if !self.printed.is_empty() {
            let _ = self.events.send(Event::Printed(std::mem::take(&mut self.printed)));
        }
    }
}

impl Observer for Reporter {
    fn node(&mut self, name: &str) {
        if self.due() {
            self.flush();
            let _ = self.events.send(Event::Node(name.to_string()));
        }
    }

    fn printed(&mut self, text: &str) {
        self.printed.push_str(text);
        if self.due() {
            self.flush();
        }
    }

    fn cancelled(&mut self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

impl Places {
    /// Where a run error happened, as an LSP location.
    pub fn location(&self, error: &RunError) -> Option<lsp::Location> {
        let span = error.span?;
        let (_, uri, index) = self.files.iter().find(|(file, _, _)| *file == span.file)?;
        Some(lsp::Location { uri: uri.clone()?, range: to_proto::range(index, span.range, self.encoding) })
    }
}

/// Whether a run error is a cancellation.
pub fn is_cancellation(error: &RunError) -> bool {
    error.kind == RunErrorKind::Cancelled
}

impl Backend {
    /// `gudsl.run`: prepares the diagram on a snapshot, runs it off the message loop with
    /// progress, and answers with the report once it ended (refused, with the problems as
    /// `data`, when it cannot start).
    pub(super) async fn run(
        &self,
        request: RunRequest,
        token: Option<lsp::ProgressToken>,
    ) -> jsonrpc::Result<lsp::LSPAny> {
        let name = request.diagram.clone();
        let ready = match self.on_snapshot(move |s| prepare(s, &name)).await? {
            Ok(ready) => ready,
            Err(refusal) => {
                let message = format!("gudsl: {}", refusal.message);
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                let data = Some(serde_json::json!({ "problems": refusal.problems }));
                return Err(Error { data, ..request_failed(message) });
            }
        };
        let Ready { prepared, places } = ready;
        let diagram = prepared.diagram().to_string();
        let token = match token {
            Some(token) => Some(token),
            None if self.progress_supported.load(Ordering::SeqCst) => {
                let token = self.runs.new_token();
                let created =
                    tokio::time::timeout(CLIENT_ANSWER, self.client.create_work_done_progress(token.clone())).await;
                created.is_ok_and(|answer| answer.is_ok()).then_some(token)
            }
            None => None,
        };
        // Dropped when the request is cancelled ($/cancelRequest drops this future) or answered:
        // either way the run stops.
        let mut guard = self.runs.start(&token.clone().unwrap_or_else(|| self.runs.new_token()));
        let progress = match &token {
            Some(token) => Some(
                self.client
                    .progress(token.clone(), format!("Running {diagram}"))
                    .with_cancel_button()
                    .with_message("compiling kernels")
                    .begin()
                    .await,
            ),
            None => None,
        };
        guard.reports(token.clone().filter(|_| progress.is_some()).map(|token| (self.client.clone(), token)));
        let (events, mut received) = tokio::sync::mpsc::unbounded_channel();
        let finished = spawn(prepared, request.output.clone(), guard.stop_flag(), events);
        while let Some(event) = received.recv().await {
            match event {
                Event::Node(node) => {
                    if let Some(progress) = &progress {
                        progress.report_with_message(format!("node {node}"), None).await;
                    }
                }
                Event::Printed(text) => self.client.log_message(lsp::MessageType::INFO, text).await,
            }
        }
        let finished = finished.await.unwrap_or_else(|_| Err("the run's thread ended without an answer".into()));
        guard.reports(None);
        drop(guard);
        let finished = match finished {
            Ok(finished) => finished,
            Err(why) => {
                if let Some(progress) = progress {
                    progress.finish_with_message(why.clone()).await;
                }
                let message = format!("gudsl: {diagram} did not run: {why}");
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                return Err(request_failed(message));
            }
        };
        if let Some(progress) = progress {
            progress.finish_with_message(finished.summary.clone()).await;
        }
        let location = finished.error.as_ref().and_then(|error| places.location(error));
        let mut answer = match finished.report {
            Ok(report) => report,
            Err(why) => serde_json::json!({ "diagram": diagram, "error": why }),
        };
        answer["output"] = serde_json::json!(request.output.display().to_string());
        answer["errorLocation"] = serde_json::to_value(&location).unwrap_or_default();
        let (kind, message) = match &finished.error {
            None => {
                (lsp::MessageType::INFO, format!("gudsl: {}; output in {}", finished.summary, request.output.display()))
            }
            Some(error) if is_cancellation(error) => (lsp::MessageType::INFO, format!("gudsl: {}", finished.summary)),
            Some(error) => {
                let at =
                    location.map(|l| format!(" at {}:{}", l.uri.as_str(), l.range.start.line + 1)).unwrap_or_default();
                (lsp::MessageType::ERROR, format!("gudsl: {diagram} stopped{at}: {error}"))
            }
        };
        self.client.show_message(kind, message).await;
        Ok(answer)
    }
}
