//! ▶ Run pipeline in the editor: `gudsl.runPipeline` runs a component-instance diagram as a ToF
//! pipeline as `gudsl run` does — refused, with every problem's place, when the model has
//! errors, when its plan has problems (E0401–E0403) or when its files and components do not fit
//! (E0404, E0405) — on a thread of its own, reporting "frame k of N" as `$/progress`, stopping
//! between frames when cancelled, and answering with `report.json` and the stages' table. The
//! outputs go to the folder the command names, by default `gudsl-out/<diagram>` in the model's
//! workspace folder (`jobs::Destination`). What
//! runs is the pipeline the diagnostics prepared (`Preparations`), when nothing changed since.

use std::{
    sync::{atomic::AtomicBool, Arc},
    time::Instant,
};

use gudsl_host::{
    named::pipeline_named,
    pipeline::{
        self, summary, table, write_report, ErrorKind, PipelineError, PipelineObserver, Preparations, PreparedPipeline,
    },
};
use gudsl_model::{hir::pipeline::PipelinePlan, Analysis, Cancellable, FileId};
use tokio::sync::mpsc;

use super::{
    host::Snapshot,
    jobs::{Destination, Event, Failure, Finished, Job, Refusal, RunRequest, REPORT_EVERY},
    run::{self, Places},
};

/// Prepares the pipeline the request names; refused when any document of the workspace has
/// errors, when no component-instance diagram or several have the name, or when it cannot run.
pub fn prepare(snap: &Snapshot, request: &RunRequest) -> Cancellable<Result<Job, Refusal>> {
    let ready = ready(snap, request, Preparations::take_for)?;
    Ok(ready.map(|ready| job(ready.prepared, ready.diagram, ready.file, ready.places, ready.destination, request)))
}

/// A pipeline prepared to run, and what its run needs of the model.
pub struct Ready {
    pub prepared: PreparedPipeline,
    /// Its diagram, fully qualified.
    pub diagram: String,
    pub file: FileId,
    /// Where its errors are placed.
    pub places: Places,
    pub destination: Destination,
}

/// How a pipeline is prepared: the check's taken ([`Preparations::take_for`]) or one of its own.
pub type HowPrepared =
    fn(&Preparations, &Analysis, &PipelinePlan) -> Cancellable<Result<PreparedPipeline, Vec<PipelineError>>>;

/// The pipeline the request names, prepared `how`; refused when any document of the workspace
/// has errors, when no component-instance diagram or several have the name, or when it cannot
/// run — with every problem's place.
pub fn ready(snap: &Snapshot, request: &RunRequest, how: HowPrepared) -> Cancellable<Result<Ready, Refusal>> {
    let name = request.diagram.as_str();
    if let Some(refusal) = run::model_errors(snap, name)? {
        return Ok(Err(refusal));
    }
    let files = run::workspace_files(snap);
    let fqn = match snap.analysis.with_semantics(|sema| pipeline_named(sema, &files, name))? {
        Ok(fqn) => fqn,
        Err(message) => return Ok(Err(Refusal { message, problems: Vec::new() })),
    };
    let Some(plan) = snap.analysis.pipeline_plan(&fqn)? else {
        return Ok(Err(Refusal { message: format!("`{fqn}` is not a pipeline"), problems: Vec::new() }));
    };
    if !plan.diagnostics.is_empty() {
        let problems = plan.diagnostics.iter().map(|d| (plan.file, d.range, d.code, d.message.clone()));
        return Ok(Err(run::cannot_run(snap, name, problems.collect::<Vec<_>>())?));
    }
    let prepared = match how(&snap.preparations, &snap.analysis, &plan)? {
        Ok(prepared) => prepared,
        Err(errors) => {
            let problems =
                errors.iter().map(|e| (plan.file, e.range.unwrap_or(plan.name_range), e.code(), e.to_string()));
            return Ok(Err(run::cannot_run(snap, name, problems.collect::<Vec<_>>())?));
        }
    };
    let places = Places::of(snap, [plan.file])?;
    let destination = Destination::of(snap, plan.file, request);
    Ok(Ok(Ready { prepared, diagram: fqn, file: plan.file, places, destination }))
}

/// The run of a prepared pipeline: on the first wgpu adapter with timestamp queries (the CPU
/// reference with `cpu`, or when there is none), its outputs under the request's folder.
fn job(
    mut prepared: PreparedPipeline,
    diagram: String,
    file: FileId,
    places: Places,
    destination: Destination,
    request: &RunRequest,
) -> Job {
    let (frames, cpu) = (request.frames, request.cpu);
    let work = move |stop: Arc<AtomicBool>, events: mpsc::UnboundedSender<Event>| {
        let gpu = pipeline::gpu(cpu, |error| {
            let _ =
                events.send(Event::Printed(format!("gudsl: no GPU adapter ({error}); running on the CPU reference")));
        });
        let mut output_dir = destination.create()?;
        let mut observer = Frames { events, last: None };
        let report = prepared.run(gpu.as_ref(), &mut output_dir, frames, &mut observer, &stop);
        let report_json = write_report(&report, &mut output_dir).map(|mut json| {
            json["table"] = table(&report).into();
            json
        });
        Ok(Finished {
            summary: summary(&report),
            output: output_dir.path().to_path_buf(),
            report: report_json,
            // A run that stopped, or else the first sink that failed alone (the rest is in the
            // report's stages).
            failure: report.outcome.clone().err().or_else(|| report.failed_stages().next().cloned()).map(|error| {
                Failure {
                    message: error.to_string(),
                    cancelled: error.kind == ErrorKind::Cancelled,
                    location: error.range.and_then(|range| places.at(file, range)),
                }
            }),
        })
    };
    Job { diagram, starting: "preparing the first frame", bounded: true, work: Box::new(work) }
}

/// A pipeline's observer: "frame k of N" with its percentage, at most one per
/// [`REPORT_EVERY`] (the last frame always).
struct Frames {
    events: mpsc::UnboundedSender<Event>,
    last: Option<Instant>,
}

impl PipelineObserver for Frames {
    fn frame(&mut self, index: usize, frames: usize) {
        let last_frame = index + 1 == frames;
        if last_frame || self.last.is_none_or(|last| last.elapsed() >= REPORT_EVERY) {
            self.last = Some(Instant::now());
            let percentage = ((index + 1) * 100 / frames.max(1)) as u32;
            let _ = self.events.send(Event::Progress(format!("frame {} of {frames}", index + 1), Some(percentage)));
        }
    }
}
