//! The live preview (`gudsl.preview`, `gudsl/preview`): while a pipeline is live, each edit
//! that changes what its stages run with — a parameter, a binding, a file it reads, a kernel —
//! runs it again on its first frames and sends the results; an edit that changes nothing of it
//! (a comment, a layout) runs nothing. A newer preview cancels the one under way; model errors
//! stop the preview (the notification places them) until the model is clean. It is prepared
//! on a snapshot as ▶ Run pipeline is (`pipeline::ready`, a pipeline of its own so the
//! check's stays) and runs on one thread that keeps the device and what the stages gave
//! between previews (`gudsl_host::pipeline::Preview`), holding no snapshot.

use std::{
    sync::{
        atomic::{AtomicBool, AtomicU64, Ordering},
        mpsc, Arc, Mutex,
    },
    time::Instant,
};

use gudsl_host::pipeline::{self as host_pipeline, report_json, summary, Preparations, Preview, StageKey};
use serde_json::Value;
use tower_lsp_server::{ls_types as lsp, Client};

use super::{
    capabilities::Encoding,
    ext::{self, GraphChangedNotification, PreviewNotification, PreviewState, PreviewTimings},
    host::Host,
    jobs::{Refusal, RunRequest},
    lock, panic_text,
    pipeline::{ready, Ready},
    scenes::SceneCache,
};

/// The frames a preview runs when the command names none: the first.
const DEFAULT_FRAMES: usize = 1;

/// The live preview: which pipeline, what was last handed to its thread, the thread.
#[derive(Default)]
pub struct Previews {
    state: Mutex<State>,
    /// Numbers the edits followed; a preview of an older edit is never handed on after a newer.
    tickets: AtomicU64,
}

#[derive(Default)]
struct State {
    live: Option<Live>,
    /// The newest edit whose preview was handed on or stopped.
    ticket: u64,
    /// What the last preview handed on ran with: an edit that leaves it so runs nothing.
    last: Option<Vec<StageKey>>,
    /// The preview under way's cancellation.
    running: Option<Arc<AtomicBool>>,
    /// Why the preview stopped, as last told (each keystroke while the model has the same
    /// errors tells nothing new).
    stopped: Option<String>,
    sequence: u64,
    worker: Option<mpsc::Sender<Box<Work>>>,
}

/// The pipeline that is live, as the command asked.
#[derive(Clone)]
struct Live {
    diagram: String,
    frames: usize,
    cpu: bool,
}

/// A preview for the thread.
struct Work {
    ready: Ready,
    live: Live,
    cancel: Arc<AtomicBool>,
    sequence: u64,
    uri: Option<lsp::Uri>,
    version: Option<i32>,
    received: Instant,
    prepare_ms: f64,
}

impl Previews {
    /// `gudsl.preview`'s argument applied: a name toggles, `{"diagram", "live", "frames",
    /// "cpu"}` sets; whether a preview should run now.
    pub fn command(&self, argument: Option<&Value>) -> Result<(PreviewState, bool), String> {
        let (argument, live) = match argument {
            Some(Value::Object(fields)) => {
                let mut fields = fields.clone();
                let live = match fields.remove("live") {
                    None | Some(Value::Null) => None,
                    Some(Value::Bool(live)) => Some(live),
                    Some(_) => return Err(format!("{}: `live` is true or false", ext::PREVIEW)),
                };
                (Some(Value::Object(fields)), live)
            }
            other => (other.cloned(), None),
        };
        let request = RunRequest::parse(ext::PREVIEW, argument.as_ref())?;
        let mut state = lock(&self.state);
        let is_live = state.live.as_ref().is_some_and(|l| l.diagram == request.diagram);
        let frames = request.frames.unwrap_or(DEFAULT_FRAMES).max(1);
        if let Some(running) = state.running.take() {
            running.store(true, Ordering::Relaxed);
        }
        (state.last, state.stopped) = (None, None);
        if live.unwrap_or(!is_live) {
            state.live = Some(Live { diagram: request.diagram.clone(), frames, cpu: request.cpu });
            Ok((PreviewState { diagram: Some(request.diagram), live: true, frames }, true))
        } else {
            state.live = None;
            Ok((PreviewState { diagram: None, live: false, frames }, false))
        }
    }

    /// Whether a pipeline is live.
    pub fn is_live(&self) -> bool {
        lock(&self.state).live.is_some()
    }
}

/// What following an edit needs of the server.
#[derive(Clone)]
pub struct Follower {
    pub previews: Arc<Previews>,
    pub host: Arc<Mutex<Host>>,
    pub client: Client,
    pub encoding: Encoding,
    pub scenes: Arc<SceneCache>,
}

/// What the preview thread needs to draw a preview's report on its diagram.
#[derive(Clone)]
struct Drawn {
    scenes: Arc<SceneCache>,
    host: Arc<Mutex<Host>>,
    encoding: Encoding,
}

impl Follower {
    /// After an edit (received at `received`): the live pipeline prepared on a snapshot and
    /// handed to the preview thread when what it runs with changed, or stopped with the
    /// model's errors.
    pub async fn follow(self, received: Instant) {
        let Follower { previews, host, client, encoding, scenes } = self;
        let Some(live) = lock(&previews.state).live.clone() else { return };
        let ticket = previews.tickets.fetch_add(1, Ordering::SeqCst) + 1;
        let snapshot = lock(&host).snapshot(encoding);
        let request = RunRequest { diagram: live.diagram.clone(), output: None, frames: None, cpu: live.cpu };
        let prepared = tokio::task::spawn_blocking(move || {
            let ready = ready(&snapshot, &request, Preparations::prepare_apart)?;
            let document = ready.as_ref().ok().and_then(|r| snapshot.uri_of(r.file));
            let version = document.as_ref().and_then(|uri| snapshot.document(uri)?.version);
            gudsl_model::Cancellable::Ok((ready, document, version))
        })
        .await;
        // Cancelled by a newer edit, which follows with its own.
        let Ok(Ok((ready, uri, version))) = prepared else { return };
        let prepare_ms = received.elapsed().as_secs_f64() * 1000.0;
        let mut state = lock(&previews.state);
        if state.ticket > ticket || state.live.as_ref().is_none_or(|l| l.diagram != live.diagram) {
            return;
        }
        state.ticket = ticket;
        let ready = match ready {
            Ok(ready) => ready,
            Err(refusal) => return stop(&mut state, &client, &live, refusal, prepare_ms),
        };
        if state.last.as_deref() == Some(ready.prepared.keys()) {
            return;
        }
        if let Some(running) = state.running.take() {
            running.store(true, Ordering::Relaxed);
        }
        state.stopped = None;
        let cancel = Arc::new(AtomicBool::new(false));
        state.running = Some(cancel.clone());
        state.last = Some(ready.prepared.keys().to_vec());
        state.sequence += 1;
        let work = Box::new(Work { ready, live, cancel, sequence: state.sequence, uri, version, received, prepare_ms });
        let drawn = Drawn { scenes, host, encoding };
        let worker = state.worker.get_or_insert_with(|| spawn_worker(client.clone(), drawn.clone()));
        if let Err(mpsc::SendError(work)) = worker.send(work) {
            // The thread ended (a panic): a new one takes the preview.
            state.worker = Some(spawn_worker(client, drawn));
            let _ = state.worker.as_ref().map(|worker| worker.send(work));
        }
    }
}

/// The model has errors, or the pipeline cannot run: the preview under way stops, and the
/// client is told where the problems are.
fn stop(state: &mut State, client: &Client, live: &Live, refusal: Refusal, prepare_ms: f64) {
    if let Some(running) = state.running.take() {
        running.store(true, Ordering::Relaxed);
    }
    state.last = None;
    if state.stopped.as_deref() == Some(refusal.message.as_str()) {
        return;
    }
    state.stopped = Some(refusal.message.clone());
    state.sequence += 1;
    let notification = ext::Preview {
        diagram: live.diagram.clone(),
        uri: None,
        version: None,
        sequence: state.sequence,
        state: "stopped".to_string(),
        message: refusal.message,
        report: None,
        replayed: Vec::new(),
        problems: refusal.problems,
        output: None,
        timings: PreviewTimings { prepare_ms, total_ms: prepare_ms, ..PreviewTimings::default() },
    };
    let client = client.clone();
    tokio::spawn(async move { client.send_notification::<PreviewNotification>(notification).await });
}

/// The preview thread: the newest preview handed to it, run on the device it keeps (made at the
/// first preview, and again when the CPU reference is asked for or no longer).
fn spawn_worker(client: Client, drawn: Drawn) -> mpsc::Sender<Box<Work>> {
    let (sender, receiver) = mpsc::channel::<Box<Work>>();
    let runtime = tokio::runtime::Handle::current();
    std::thread::spawn(move || {
        let mut preview: Option<(bool, Preview)> = None;
        while let Ok(mut work) = receiver.recv() {
            while let Ok(newer) = receiver.try_recv() {
                work = newer;
            }
            if work.cancel.load(Ordering::Relaxed) {
                continue;
            }
            if preview.as_ref().is_none_or(|(cpu, _)| *cpu != work.live.cpu) {
                preview = Some((work.live.cpu, Preview::new(host_pipeline::gpu(work.live.cpu, |_| {}))));
            }
            let Some((_, live)) = preview.as_mut() else { continue };
            let (diagram, sequence) = (work.ready.diagram.clone(), work.sequence);
            let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run(live, work)));
            let ran = ran.unwrap_or_else(|panic| {
                // What it kept may be half made: the next preview starts afresh.
                preview = None;
                Some(panicked(diagram, sequence, &*panic))
            });
            if let Some(notification) = ran {
                // Its diagram drawn with the preview's times and flows, where a client has it.
                let snap = lock(&drawn.host).snapshot(drawn.encoding);
                let changed = notification.report.as_ref().map(|r| drawn.scenes.ran(r, &snap)).unwrap_or_default();
                drop(snap);
                let client = client.clone();
                runtime.spawn(async move {
                    client.send_notification::<PreviewNotification>(notification).await;
                    for changed in changed {
                        client.send_notification::<GraphChangedNotification>(changed).await;
                    }
                });
            }
        }
    });
    sender
}

/// One preview run into `gudsl-out/<diagram>/preview`; nothing to tell when it was cancelled
/// (a newer one follows).
fn run(preview: &mut Preview, work: Box<Work>) -> Option<ext::Preview> {
    let queued_ms = work.received.elapsed().as_secs_f64() * 1000.0 - work.prepare_ms;
    let started = Instant::now();
    let Work { ready, live, cancel, sequence, uri, version, received, prepare_ms } = *work;
    let mut notification = ext::Preview {
        diagram: ready.diagram.clone(),
        uri,
        version,
        sequence,
        state: "failed".to_string(),
        message: String::new(),
        report: None,
        replayed: Vec::new(),
        problems: Vec::new(),
        output: None,
        timings: PreviewTimings { prepare_ms, queued_ms, ..PreviewTimings::default() },
    };
    let output = ready.destination.create().and_then(|folder| folder.nested("preview"));
    let mut output = match output {
        Ok(output) => output,
        Err(why) => {
            notification.message = format!("{} was not previewed: {why}", ready.diagram);
            return Some(finished(notification, received, started));
        }
    };
    let report = preview.run(ready.prepared, live.frames, &mut output, &cancel);
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let failure = report.outcome.as_ref().err().or_else(|| report.failed_stages().next());
    if let Some(error) = failure {
        let location = error.range.and_then(|range| ready.places.at(ready.file, range));
        let problem =
            serde_json::json!({ "location": location, "code": error.code().as_str(), "message": error.message });
        notification.problems.push(problem);
    }
    notification.state = if report.outcome.is_ok() { "ran" } else { "failed" }.to_string();
    notification.message = summary(&report);
    notification.report = Some(report_json(&report));
    notification.replayed = report.replayed().map(str::to_string).collect();
    notification.output = Some(output.path().display().to_string());
    Some(finished(notification, received, started))
}

/// A preview whose run panicked, said so (a bug: the message is the panic's).
fn panicked(diagram: String, sequence: u64, panic: &(dyn std::any::Any + Send)) -> ext::Preview {
    ext::Preview {
        message: format!("{diagram} was not previewed: its run panicked: {}", panic_text(panic)),
        diagram,
        uri: None,
        version: None,
        sequence,
        state: "failed".to_string(),
        report: None,
        replayed: Vec::new(),
        problems: Vec::new(),
        output: None,
        timings: PreviewTimings::default(),
    }
}

/// `notification` with its run's and its total time.
fn finished(mut notification: ext::Preview, received: Instant, started: Instant) -> ext::Preview {
    notification.timings.run_ms = started.elapsed().as_secs_f64() * 1000.0;
    notification.timings.total_ms = received.elapsed().as_secs_f64() * 1000.0;
    notification
}
