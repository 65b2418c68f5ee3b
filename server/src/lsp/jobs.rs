//! The run machinery of the editor's commands, whatever runs: a command's request
//! ([`RunRequest`]) and its refusal, the cancellation flags of the runs under way by progress
//! token ([`Runs`], [`RunGuard`]), a prepared [`Job`] done on a thread of its own, the
//! [`Event`]s it sends as it goes, and its `$/progress` ([`WorkDone`]).

use std::{
    collections::HashMap,
    path::PathBuf,
    sync::{
        atomic::{AtomicBool, AtomicU64, Ordering},
        Arc, Mutex, OnceLock,
    },
    time::Duration,
};

use gudsl_host::output::OutputDir;
use gudsl_model::FileId;
use serde_json::Value;
use tokio::sync::{mpsc, oneshot};
use tower_lsp_server::{ls_types as lsp, Client};

use super::{host::Snapshot, lock};

/// How often a run's progress is reported at most (nodes and printed text in between are
/// gathered).
pub const REPORT_EVERY: Duration = Duration::from_millis(100);

/// What the command asks for (`frames` and `cpu` apply to pipelines).
pub struct RunRequest {
    pub diagram: String,
    /// The folder the client named for the outputs (default: see [`Destination`]).
    pub output: Option<PathBuf>,
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
        let mut request = RunRequest { diagram: String::new(), output: None, frames: None, cpu: false };
        match argument {
            Some(Value::String(name)) => request.diagram = name.clone(),
            Some(Value::Object(fields)) => {
                for (key, value) in fields {
                    match (key.as_str(), value) {
                        ("diagram", Value::String(name)) => request.diagram = name.clone(),
                        ("output", Value::String(folder)) => request.output = Some(folder_path(folder)),
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
        Ok(request)
    }
}

/// Where a run from the editor writes: the folder the client named; else
/// `gudsl-out/<diagram>` in the workspace folder that holds the model, as `gudsl run` does; else
/// (a model outside every workspace folder) in a folder of this server's own, made private
/// (`mkdtemp`, 0700) — never a predictable shared path another user could plant links in.
#[derive(Debug, Clone)]
pub struct Destination {
    named: Option<PathBuf>,
    anchor: Result<PathBuf, String>,
    diagram: String,
}

impl Destination {
    /// Where the run `request` of a diagram declared in `file` writes.
    pub fn of(snap: &Snapshot, file: FileId, request: &RunRequest) -> Destination {
        let model_dir = gudsl_host::pipeline::model_dir(&snap.analysis, file);
        let anchor = match snap.preparations.access().workspace_of(&model_dir) {
            Some(workspace) => Ok(workspace),
            None => private_folder(),
        };
        Destination { named: request.output.clone(), anchor, diagram: request.diagram.clone() }
    }

    /// The output folder, made (on the run's thread: it touches the file system).
    pub fn create(&self) -> Result<OutputDir, String> {
        let anchor = self.anchor.as_ref().map_err(|why| format!("no output folder: {why}"))?;
        OutputDir::for_run(self.named.as_deref(), anchor, &self.diagram)
            .map_err(|error| format!("not writing into the output folder: {error}"))
    }
}

/// This server's private folder for the outputs of models outside the workspace: made once,
/// readable by its user only, kept when the server stops (the outputs are the user's).
fn private_folder() -> Result<PathBuf, String> {
    static FOLDER: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    FOLDER
        .get_or_init(|| {
            let mut builder = tempfile::Builder::new();
            builder.prefix("gudsl-run-");
            #[cfg(unix)]
            builder.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o700));
            let made = builder.tempdir();
            made.map(tempfile::TempDir::keep).map_err(|e| format!("cannot make a private temporary folder: {e}"))
        })
        .clone()
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
        lock(&self.flags).insert(key.clone(), flag.clone());
        RunGuard { runs: self.clone(), key, flag, progress: None }
    }

    /// Stops the run reporting progress under `token`; false if there is none.
    pub fn cancel(&self, token: &lsp::ProgressToken) -> bool {
        let flags = lock(&self.flags);
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
    pub fn reports(&mut self, progress: Option<(Client, lsp::ProgressToken)>) {
        self.progress = progress;
    }
}

impl Drop for RunGuard {
    fn drop(&mut self) {
        self.flag.store(true, Ordering::SeqCst);
        lock(&self.runs.flags).remove(&self.key);
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
    /// The folder its outputs were written into.
    pub output: PathBuf,
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
pub fn spawn(
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

/// A run's `$/progress` under its token: cancellable, with a percentage when bounded.
pub struct WorkDone {
    pub client: Client,
    pub token: lsp::ProgressToken,
}

impl WorkDone {
    async fn send(&self, progress: lsp::WorkDoneProgress) {
        let params =
            lsp::ProgressParams { token: self.token.clone(), value: lsp::ProgressParamsValue::WorkDone(progress) };
        self.client.send_notification::<lsp::notification::Progress>(params).await;
    }

    pub async fn begin(&self, title: String, message: &str, bounded: bool) {
        let begin = lsp::WorkDoneProgressBegin {
            title,
            cancellable: Some(true),
            message: Some(message.to_string()),
            percentage: bounded.then_some(0),
        };
        self.send(lsp::WorkDoneProgress::Begin(begin)).await;
    }

    pub async fn report(&self, message: String, percentage: Option<u32>) {
        let report = lsp::WorkDoneProgressReport { cancellable: Some(true), message: Some(message), percentage };
        self.send(lsp::WorkDoneProgress::Report(report)).await;
    }

    pub async fn end(&self, message: String) {
        self.send(lsp::WorkDoneProgress::End(lsp::WorkDoneProgressEnd { message: Some(message) })).await;
    }
}
