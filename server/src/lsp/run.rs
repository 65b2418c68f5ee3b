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

use gudsl_host::run::{Observer, Prepared, RunErrorKind};
use gudsl_model::{
    hir::{DiagnosticCode, Severity},
    syntax::TextRange,
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
pub(super) const REPORT_EVERY: Duration = Duration::from_millis(100);

/// What the command asks for (`frames` and `cpu` apply to pipelines).
pub struct RunRequest {
    pub diagram: String,
    pub output: PathBuf,
    /// Run at most this many frames.
    pub frames: Option<usize>,
    /// On the CPU reference instead of the GPU.
    pub cpu: bool,
}

impl RunRequest {
    /// `name`, or `{"diagram": name, "output"?: folder, "frames"?: n, "cpu"?: bool}`, as
    /// `command` takes it.
    pub fn parse(command: &str, argument: Option<&Value>) -> Result<RunRequest, String> {
        let error = || {
            format!(
                "{command} takes a diagram's name or {{\"diagram\": name, \"output\": folder, \"frames\": n, \"cpu\": bool}}"
            )
        };
        let mut request = RunRequest { diagram: String::new(), output: PathBuf::new(), frames: None, cpu: false };
        let mut output = None;
        match argument {
            Some(Value::String(name)) => request.diagram = name.clone(),
            Some(Value::Object(fields)) => {
                for (key, value) in fields {
                    match (key.as_str(), value) {
                        ("diagram", Value::String(name)) => request.diagram = name.clone(),
                        ("output", Value::String(folder)) => output = Some(folder_path(folder)),
                        ("frames", Value::Number(n)) if n.as_u64().is_some() => {
                            request.frames = n.as_u64().map(|n| n as usize)
                        }
                        ("cpu", Value::Bool(cpu)) => request.cpu = *cpu,
                        (_, Value::Null) => {}
                        _ => return Err(error()),
                    }
                }
                if request.diagram.is_empty() {
                    return Err(error());
                }
            }
            _ => return Err(error()),
        }
        request.output = output.unwrap_or_else(|| std::env::temp_dir().join("gudsl-run").join(&request.diagram));
        Ok(request)
    }
}

/// A folder given as a path or a `file:` URI.
fn folder_path(folder: &str) -> PathBuf {
    match folder.parse::<lsp::Uri>().ok().and_then(|uri| super::from_proto::file_path(&uri)) {
        Some(path) if folder.starts_with("file:") => path,
        _ => PathBuf::from(folder),
    }
}

/// A command refused before anything ran: why, and each problem with its place.
pub struct Refusal {
    pub message: String,
    pub problems: Vec<Value>,
}

/// The files of the diagram and of those it calls as they were when the run started: run
/// errors are placed in them.
pub struct Places {
    files: Vec<(FileId, Option<lsp::Uri>, LineIndex)>,
    encoding: Encoding,
}

impl Places {
    pub fn of(snap: &Snapshot, files: impl IntoIterator<Item = FileId>) -> Cancellable<Places> {
        let mut places = Places { files: Vec::new(), encoding: snap.encoding };
        for file in files {
            places.files.push((file, snap.uri_of(file), snap.analysis.line_index(file)?.clone()));
        }
        Ok(places)
    }

    /// A range of one of the files as an LSP location.
    pub fn at(&self, file: FileId, range: TextRange) -> Option<lsp::Location> {
        let (_, uri, index) = self.files.iter().find(|(f, _, _)| *f == file)?;
        Some(lsp::Location { uri: uri.clone()?, range: to_proto::range(index, range, self.encoding) })
    }
}

/// The documents of the workspace, in the order of their URIs.
pub fn workspace_files(snap: &Snapshot) -> Vec<FileId> {
    let mut files: Vec<(&str, FileId)> = snap.documents.iter().map(|d| (d.uri.as_str(), d.file)).collect();
    files.sort_by_key(|(uri, _)| *uri);
    files.into_iter().map(|(_, file)| file).collect()
}

/// The refusal of running `name` when any document of the workspace has errors (as `gudsl run`
/// refuses), with every error's place.
pub fn model_errors(snap: &Snapshot, name: &str) -> Cancellable<Option<Refusal>> {
    let mut errors = Vec::new();
    for file in workspace_files(snap) {
        let (diagnostics, _) = snap.analysis.diagnostics(file)?;
        let found = diagnostics.iter().filter(|d| d.severity == Severity::Error);
        errors.extend(found.map(|d| (file, d.range, d.code, d.message.clone())));
    }
    let (first, problems) = placed(snap, errors)?;
    Ok(first.map(|first| Refusal {
        message: format!(
            "the model has {} error(s); `{name}` runs once they are fixed (first: {first})",
            problems.len()
        ),
        problems,
    }))
}

/// The refusal of running `name` for `problems` (placed in `file`, each with its code): "cannot
/// run", the first problem's place and message.
pub fn cannot_run(
    snap: &Snapshot,
    name: &str,
    problems: impl IntoIterator<Item = (FileId, TextRange, DiagnosticCode, String)>,
) -> Cancellable<Refusal> {
    let (first, problems) = placed(snap, problems)?;
    let first = first.unwrap_or_default();
    Ok(Refusal { message: format!("`{name}` cannot run ({} problem(s)); first: {first}", problems.len()), problems })
}

/// Each problem with its place (for a refusal's `data`), and the first as `path:line:column:
/// message`.
fn placed(
    snap: &Snapshot,
    problems: impl IntoIterator<Item = (FileId, TextRange, DiagnosticCode, String)>,
) -> Cancellable<(Option<String>, Vec<Value>)> {
    let mut placed = Vec::new();
    let mut first = None;
    for (file, range, code, message) in problems {
        let index = snap.analysis.line_index(file)?;
        first.get_or_insert_with(|| format!("{}: {message}", place(snap, file, index, range)));
        placed.push(problem(snap, file, index, range, code, &message));
    }
    Ok((first, placed))
}

/// Prepares the activity diagram named `name` to run; refused when any document of the
/// workspace has errors, when no diagram or several have the name, or when it cannot run.
pub fn prepare(snap: &Snapshot, request: &RunRequest) -> Cancellable<Result<Job, Refusal>> {
    let name = request.diagram.as_str();
    if let Some(refusal) = model_errors(snap, name)? {
        return Ok(Err(refusal));
    }
    let files = workspace_files(snap);
    let prepared = snap.analysis.with_semantics(|sema| cli::prepare_named(sema, &files, name))?;
    let errors = match prepared {
        Err(message) => return Ok(Err(Refusal { message, problems: Vec::new() })),
        Ok(Ok(prepared)) => {
            let places = Places::of(snap, prepared.files())?;
            return Ok(Ok(activity_job(prepared, places, request.output.clone())));
        }
        Ok(Err(errors)) => errors,
    };
    let placed = errors.iter().filter_map(|e| {
        let span = e.span?;
        Some((span.file, span.range, DiagnosticCode::NotRunnable, e.message.clone()))
    });
    let mut refusal = cannot_run(snap, name, placed.collect::<Vec<_>>())?;
    if refusal.problems.is_empty() {
        refusal.message = format!("`{name}` cannot run: {}", errors.first().map_or("", |e| e.message.as_str()));
    }
    Ok(Err(refusal))
}

/// The run of a prepared activity diagram: on the first wgpu adapter, `printf` output as log
/// messages, the node running as progress.
fn activity_job(prepared: Prepared, places: Places, output: PathBuf) -> Job {
    let diagram = prepared.diagram().to_string();
    let work = move |stop: Arc<AtomicBool>, events: mpsc::UnboundedSender<Event>| {
        let gpu = gudsl_runtime::Gpu::new().map_err(|error| {
            format!(
                "no GPU adapter ({error}); without a GPU, install Mesa's Vulkan driver (Debian: mesa-vulkan-drivers)"
            )
        })?;
        let mut observer = Reporter { events, stop, last: None, printed: String::new() };
        let report = prepared.run(&gpu, &output, &mut observer);
        observer.flush();
        Ok(Finished {
            summary: cli::summary(&report),
            report: cli::write_report(&report, &output),
            failure: report.outcome.err().map(|error| Failure {
                message: error.to_string(),
                cancelled: error.kind == RunErrorKind::Cancelled,
                location: error.span.and_then(|span| places.at(span.file, span.range)),
            }),
        })
    };
    Job { diagram, starting: "compiling kernels", bounded: false, work: Box::new(work) }
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
    /// Where it is (the node running, the frame done), with a percentage when known.
    Progress(String, Option<u32>),
    /// Text `printf` wrote since the last event.
    Printed(String),
}

/// Why a run stopped before its end.
pub struct Failure {
    pub message: String,
    pub cancelled: bool,
    /// Where in the model, when it happened at a place.
    pub location: Option<lsp::Location>,
}

/// How a run ended, made on the run's thread (the report itself stays there).
pub struct Finished {
    /// One line: how it ended, in how long.
    pub summary: String,
    /// `report.json` as written, or why it was not.
    pub report: Result<Value, String>,
    pub failure: Option<Failure>,
}

/// The work of a run, done on a thread of its own: it watches the flag, sends events, and
/// ends with its report (`Err`: why it could not start).
type Work = Box<dyn FnOnce(Arc<AtomicBool>, mpsc::UnboundedSender<Event>) -> Result<Finished, String> + Send>;

/// A run ready to start.
pub struct Job {
    pub diagram: String,
    /// What the progress says until the first event.
    pub starting: &'static str,
    /// Whether its progress has a percentage.
    pub bounded: bool,
    pub work: Work,
}

/// Does `work` on a thread of its own (the GPU device is made there: it cannot move between
/// threads); the answer comes once it ended.
fn spawn(
    work: Work,
    stop: Arc<AtomicBool>,
    events: mpsc::UnboundedSender<Event>,
) -> oneshot::Receiver<Result<Finished, String>> {
    let (answer, finished) = oneshot::channel();
    let thread = move || {
        let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| work(stop, events)));
        let _ = answer.send(
            outcome.unwrap_or_else(|_| Err("the run failed unexpectedly (a panic; see the server's log)".into())),
        );
    };
    let spawned = std::thread::Builder::new().name("gudsl run".into()).stack_size(16 << 20).spawn(thread);
    if let Err(error) = spawned {
        let (answer, finished) = oneshot::channel();
        let _ = answer.send(Err(format!("cannot start the run's thread: {error}")));
        return finished;
    }
    finished
}

/// An activity run's observer: events, at most one per [`REPORT_EVERY`], and the stop flag.
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
            let _ = self.events.send(Event::Progress(format!("node {name}"), None));
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

/// A run's `$/progress` under its token: cancellable, with a percentage when bounded.
struct WorkDone {
    client: Client,
    token: lsp::ProgressToken,
}

impl WorkDone {
    async fn send(&self, progress: lsp::WorkDoneProgress) {
        let params =
            lsp::ProgressParams { token: self.token.clone(), value: lsp::ProgressParamsValue::WorkDone(progress) };
        self.client.send_notification::<lsp::notification::Progress>(params).await;
    }

    async fn begin(&self, title: String, message: &str, bounded: bool) {
        let begin = lsp::WorkDoneProgressBegin {
            title,
            cancellable: Some(true),
            message: Some(message.to_string()),
            percentage: bounded.then_some(0),
        };
        self.send(lsp::WorkDoneProgress::Begin(begin)).await;
    }

    async fn report(&self, message: String, percentage: Option<u32>) {
        let report = lsp::WorkDoneProgressReport { cancellable: Some(true), message: Some(message), percentage };
        self.send(lsp::WorkDoneProgress::Report(report)).await;
    }

    async fn end(&self, message: String) {
        self.send(lsp::WorkDoneProgress::End(lsp::WorkDoneProgressEnd { message: Some(message) })).await;
    }
}

impl Backend {
    /// Prepares a run on a snapshot, runs it off the message loop with progress, and answers
    /// with the report once it ended (refused, with the problems as `data`, when it cannot
    /// start). `gudsl.run` and `gudsl.runPipeline`.
    pub(super) async fn run(
        &self,
        request: RunRequest,
        prepare: fn(&Snapshot, &RunRequest) -> Cancellable<Result<Job, Refusal>>,
        token: Option<lsp::ProgressToken>,
    ) -> jsonrpc::Result<lsp::LSPAny> {
        let output = request.output.clone();
        let job = match self.on_snapshot(move |s| prepare(s, &request)).await? {
            Ok(job) => job,
            Err(refusal) => {
                let message = format!("gudsl: {}", refusal.message);
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                let data = Some(serde_json::json!({ "problems": refusal.problems }));
                return Err(Error { data, ..request_failed(message) });
            }
        };
        let diagram = job.diagram.clone();
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
        let progress = match token.clone() {
            Some(token) => {
                let progress = WorkDone { client: self.client.clone(), token };
                progress.begin(format!("Running {diagram}"), job.starting, job.bounded).await;
                Some(progress)
            }
            None => None,
        };
        guard.reports(token.clone().filter(|_| progress.is_some()).map(|token| (self.client.clone(), token)));
        let (events, mut received) = tokio::sync::mpsc::unbounded_channel();
        let finished = spawn(job.work, guard.stop_flag(), events);
        while let Some(event) = received.recv().await {
            match event {
                Event::Progress(message, percentage) => {
                    if let Some(progress) = &progress {
                        progress.report(message, percentage).await;
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
                    progress.end(why.clone()).await;
                }
                let message = format!("gudsl: {diagram} did not run: {why}");
                self.client.show_message(lsp::MessageType::ERROR, message.clone()).await;
                return Err(request_failed(message));
            }
        };
        if let Some(progress) = progress {
            progress.end(finished.summary.clone()).await;
        }
        let location = finished.failure.as_ref().and_then(|failure| failure.location.clone());
        let mut answer = match finished.report {
            Ok(report) => report,
            Err(why) => serde_json::json!({ "diagram": diagram, "error": why }),
        };
        answer["output"] = serde_json::json!(output.display().to_string());
        answer["errorLocation"] = serde_json::to_value(&location).unwrap_or_default();
        let (kind, message) = match &finished.failure {
            None => (lsp::MessageType::INFO, format!("gudsl: {}; output in {}", finished.summary, output.display())),
            Some(failure) if failure.cancelled => (lsp::MessageType::INFO, format!("gudsl: {}", finished.summary)),
            Some(failure) => {
                let at =
                    location.map(|l| format!(" at {}:{}", l.uri.as_str(), l.range.start.line + 1)).unwrap_or_default();
                (lsp::MessageType::ERROR, format!("gudsl: {diagram} stopped{at}: {}", failure.message))
            }
        };
        self.client.show_message(kind, message).await;
        Ok(answer)
    }
}
