//! ▶ Run in the editor: `gudsl.run` prepares a host diagram on a snapshot — refused, with every
//! problem's place, when the model has errors or the diagram cannot run (E0302) — and runs it
//! on a thread of its own with the snapshot released, so editing goes on meanwhile. Nodes are
//! reported as `$/progress`, `printf` output as log messages; the run stops between nodes when
//! the client cancels the progress (`window/workDoneProgress/cancel`) or the request
//! (`$/cancelRequest`). Viewer images and `report.json` go to the folder the command names, by
//! default `gudsl-out/<diagram>` in the model's workspace folder (`jobs::Destination`).

use std::{
    sync::{
        atomic::{AtomicBool, Ordering},
        Arc,
    },
    time::Instant,
};

use gudsl_host::{
    diagnostics::file_diagnostics,
    named,
    run::{summary, write_report, Observer, PreparedRun, RunErrorKind},
};
use gudsl_model::{
    hir::{DiagnosticCode, Severity},
    syntax::TextRange,
    text::LineIndex,
    Cancellable, FileId,
};
use serde_json::{json, Value};
use tokio::sync::mpsc;
use tower_lsp_server::ls_types as lsp;

use super::{
    capabilities::Encoding,
    host::Snapshot,
    jobs::{Destination, Event, Failure, Finished, Job, Refusal, RunRequest, REPORT_EVERY},
    to_proto,
};

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
/// refuses: the same diagnostics), with every error's place.
pub fn model_errors(snap: &Snapshot, name: &str) -> Cancellable<Option<Refusal>> {
    let mut errors = Vec::new();
    for file in workspace_files(snap) {
        let diagnostics = file_diagnostics(&snap.analysis, file, &snap.preparations)?;
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
    let prepared = snap.analysis.with_semantics(|sema| {
        named::activity_named(sema, &files, name)
            .map(|def| gudsl_host::run::prepare(sema, def, &snap.preparations.access()))
    })?;
    let errors = match prepared {
        Err(message) => return Ok(Err(Refusal { message, problems: Vec::new() })),
        Ok(Ok(prepared)) => {
            let places = Places::of(snap, prepared.files())?;
            let destination = Destination::of(snap, prepared.files()[0], request);
            return Ok(Ok(activity_job(prepared, places, destination)));
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
fn activity_job(prepared: PreparedRun, places: Places, destination: Destination) -> Job {
    let diagram = prepared.diagram().to_string();
    let work = move |stop: Arc<AtomicBool>, events: mpsc::UnboundedSender<Event>| {
        let gpu = gudsl_host::run::gpu()?;
        let mut output = destination.create()?;
        let mut observer = Reporter { events, stop, last: None, printed: String::new() };
        let report = prepared.run(&gpu, &mut output, &mut observer);
        observer.flush();
        Ok(Finished {
            summary: summary(&report),
            report: write_report(&report, &mut output),
            output: output.path().to_path_buf(),
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
fn place(snap: &Snapshot, file: FileId, index: &LineIndex, range: TextRange) -> String {
    to_proto::place(snap.analysis.file_path(file), index, range, snap.encoding)
}

fn problem(
    snap: &Snapshot,
    file: FileId,
    index: &LineIndex,
    range: TextRange,
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
