//! What a pipeline run did, for people and scripts: the [`PipelineReport`] (stages' times,
//! files written, how it ended), its one-line summary, the stages' table and `report.json`,
//! which `gudsl run` and the editor's ▶ Run pipeline write alike.

use std::{
    path::{Path, PathBuf},
    time::Duration,
};

use super::{ErrorKind, OutputDir, PipelineError};

impl PipelineReport {
    /// The sinks that failed (each ran no more; the run went on).
    pub fn failed_stages(&self) -> impl Iterator<Item = &PipelineError> {
        self.stages.iter().filter_map(|s| s.failed.as_ref())
    }

    /// The dispatches of every stage over the run.
    pub fn dispatches(&self) -> usize {
        self.stages.iter().map(|s| s.dispatches).sum()
    }

    /// The command buffers submitted to the GPU over the run.
    pub fn submissions(&self) -> usize {
        self.frame_submissions.iter().sum()
    }

    /// The stages that replayed a live preview's last run instead of running (in the plan's
    /// order).
    pub fn replayed(&self) -> impl Iterator<Item = &str> {
        self.stages.iter().filter(|s| s.replayed).map(|s| s.instance.as_str())
    }
}

/// What a run did.
#[derive(Debug, Clone)]
pub struct PipelineReport {
    pub diagram: String,
    /// What it ran with, by name and value (a recording, the values of `--set` and `--sweep`);
    /// told by whoever started it.
    pub setting: Vec<(String, String)>,
    pub device: String,
    pub frames: usize,
    pub total: Duration,
    /// Of `total`, reading the components' files before the first frame.
    pub loading: Duration,
    /// Per stage, in the plan's order.
    pub stages: Vec<StageTime>,
    /// Files written, under the output folder.
    pub outputs: Vec<PathBuf>,
    /// What the stages measured over the run (an accuracy report's errors).
    pub figures: Vec<Figure>,
    /// What each binding carried, in the plan's order.
    pub flows: Vec<Flow>,
    /// Command buffers submitted to the GPU (none on the CPU reference), by the frame they
    /// were for.
    pub frame_submissions: Vec<usize>,
    /// When each frame that ran to its end began (its recording) and was done (its sinks'
    /// `finish_frame`), in order (the first compiles the kernels; a benchmark's steady state
    /// is after it).
    pub frame_spans: Vec<FrameSpan>,
    /// Whether frames overlapped: each recorded and submitted while the GPU worked on the one
    /// before (then a frame begins before the one before it is done).
    pub overlapped: bool,
    pub outcome: Result<(), PipelineError>,
}

/// When a frame began and was done, from the start of the run's first frame: where frames
/// overlap, a frame begins before the one before it is done.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameSpan {
    pub started: Duration,
    pub done: Duration,
}

/// One number a stage measured over a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub stage: String,
    /// What it is, with its unit (`Compensated mean_cm`).
    pub name: String,
    pub value: f64,
}

/// What one binding carried over a run: how many items, and what the last one was.
#[derive(Debug, Clone, PartialEq)]
pub struct Flow {
    pub provider: String,
    /// The port instance and connector, as the binding names them (`Out.frame`).
    pub provider_port: String,
    pub processor: String,
    pub processor_port: String,
    pub items: usize,
    /// `200×200 f32 depth` (`Data::describe`); `None` while nothing went through.
    pub carries: Option<String>,
}

/// The time one stage took over the run.
#[derive(Debug, Clone, PartialEq)]
pub struct StageTime {
    pub instance: String,
    pub class: String,
    /// On the CPU: processing, encoding, writing.
    pub host: Duration,
    /// Its kernels on the GPU (where the adapter has timestamp queries).
    pub device: Duration,
    /// Its kernels' dispatches (compute passes) on the GPU, timed or not (0 on the CPU).
    pub dispatches: usize,
    /// Items it processed.
    pub items: usize,
    /// Whether it is a source: it gives the frames (a camera, a recording).
    pub source: bool,
    /// Whether it runs on a thread of its own (bound through an `async` port): its host time
    /// then overlaps the others'.
    pub apart: bool,
    /// Why a sink stopped (it then ran no more, and the run went on without it).
    pub failed: Option<PipelineError>,
    /// In a preview: it gave what it gave in the last preview instead of running.
    pub replayed: bool,
    /// Its work by the frame it was for (host, device, dispatches); `host` and `device` are
    /// these and what it did before the first frame and after the last.
    pub frames: Vec<FrameWork>,
    /// The stages its kernel ran inside (`fusion.rs`), by instance: its GPU work is theirs.
    pub fused_into: Vec<String>,
}

/// A stage's work for one frame: on the host (its `process` and `finish_frame`, on a thread
/// of its own too), its kernels on the GPU, its dispatches.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct FrameWork {
    pub host: Duration,
    pub device: Duration,
    pub dispatches: usize,
}

impl StageTime {
    /// `work` added to frame `frame`'s and to the run's.
    pub(crate) fn add(&mut self, frame: usize, work: FrameWork) {
        if self.frames.len() <= frame {
            self.frames.resize(frame + 1, FrameWork::default());
        }
        let at = &mut self.frames[frame];
        at.host += work.host;
        at.device += work.device;
        at.dispatches += work.dispatches;
        self.host += work.host;
        self.device += work.device;
        self.dispatches += work.dispatches;
    }

    /// Host time `took` for frame `frame`.
    pub(crate) fn add_host(&mut self, frame: usize, took: Duration) {
        self.add(frame, FrameWork { host: took, ..FrameWork::default() });
    }
}

fn ms(duration: Duration) -> f64 {
    duration.as_secs_f64() * 1000.0
}

/// One line: how the run ended, in how long, on which device.
pub fn summary(report: &PipelineReport) -> String {
    let per_frame = ms(report.total) / report.frames.max(1) as f64;
    let failed: Vec<&str> = report.failed_stages().filter_map(|e| e.stage.as_deref()).collect();
    let ended = match &report.outcome {
        Ok(()) if !failed.is_empty() => {
            format!("ran {} ({} frames; failed: {})", report.diagram, report.frames, failed.join(", "))
        }
        Ok(()) => format!("ran {} ({} frames)", report.diagram, report.frames),
        Err(error) if error.kind == ErrorKind::Cancelled => format!("{}: {}", report.diagram, error.message),
        Err(_) => format!("{} stopped with an error", report.diagram),
    };
    format!("{ended} in {:.1} ms ({per_frame:.2} ms per frame) on {}", ms(report.total), report.device)
}

/// The stages' table: per stage its time per frame on the host and on the GPU, and its share
/// of the total; a stage on a thread of its own (`async`) is marked so, a sink that failed too,
/// a stage whose kernel ran inside others' names them.
pub fn table(report: &PipelineReport) -> String {
    let per_frame = |d: Duration| ms(d) / report.frames.max(1) as f64;
    let total: Duration = report.stages.iter().map(|s| s.host + s.device).sum();
    let class = |s: &StageTime| if s.apart { format!("{} (async)", s.class) } else { s.class.clone() };
    let width = report.stages.iter().map(|s| s.instance.len()).max().unwrap_or(5).max(5);
    let class_width = report.stages.iter().map(|s| class(s).chars().count()).max().unwrap_or(9).max(9);
    let mut table = format!(
        "{:width$}  {:class_width$}  {:>12}  {:>12}  {:>6}\n",
        "stage", "component", "host ms/fr", "GPU ms/fr", "share"
    );
    for stage in &report.stages {
        let share = (stage.host + stage.device).as_secs_f64() / total.as_secs_f64().max(1e-12) * 100.0;
        let note = match (&stage.failed, stage.fused_into.as_slice()) {
            (Some(_), _) => "  failed".to_string(),
            (None, []) => String::new(),
            (None, inside) => format!("  {}", runs_in(inside)),
        };
        table += &format!(
            "{:width$}  {:class_width$}  {:>12.3}  {:>12.3}  {:>5.1}%{note}\n",
            stage.instance,
            class(stage),
            per_frame(stage.host),
            per_frame(stage.device),
            share,
        );
    }
    if report.submissions() > 0 {
        let per_frame = |n: usize| n as f64 / report.frames.max(1) as f64;
        table += &format!(
            "GPU work per frame: {} dispatches in {} submissions; {}\n",
            per_frame(report.dispatches()),
            per_frame(report.submissions()),
            if report.overlapped { "frames overlapped" } else { "one frame at a time" }
        );
    }
    table
}

/// Where a stage's kernel ran, in words: "runs in Demod's kernel", "runs in Demod's and
/// Motion's kernels".
pub(crate) fn runs_in<S: AsRef<str>>(stages: &[S]) -> String {
    let owners: Vec<String> = stages.iter().map(|s| format!("{}'s", s.as_ref())).collect();
    match owners.as_slice() {
        [one] => format!("runs in {one} kernel"),
        [rest @ .., last] => format!("runs in {} and {last} kernels", rest.join(", ")),
        [] => String::new(),
    }
}

/// Writes `report.json` into the output folder; the report as written.
pub fn write_report(report: &PipelineReport, output: &mut OutputDir) -> Result<serde_json::Value, String> {
    let json = report_json(report);
    let text = serde_json::to_string_pretty(&json).expect("a report serialises") + "\n";
    output.write_top("report.json", text.as_bytes()).map_err(|error| error.to_string())?;
    Ok(json)
}

/// `report.json`: what the run did, for scripts; `plots` are the SVG plots among the outputs.
/// Times say what they are: over the whole run (`_total`, `total_ms`) or per frame, as the
/// printed table gives them (`_per_frame`, `ms_per_frame`).
pub fn report_json(report: &PipelineReport) -> serde_json::Value {
    let per_frame = |d: Duration| ms(d) / report.frames.max(1) as f64;
    let count = |n: usize| n as f64 / report.frames.max(1) as f64;
    let paths = |keep: fn(&Path) -> bool| {
        report.outputs.iter().filter(|p| keep(p)).map(|p| p.display().to_string()).collect::<Vec<_>>()
    };
    serde_json::json!({
        "diagram": report.diagram,
        "setting": report.setting.iter().map(|(name, value)| [name, value]).collect::<Vec<_>>(),
        "device": report.device,
        "frames": report.frames,
        "total_ms": ms(report.total),
        "loading_ms": ms(report.loading),
        "frame_ms": report.frame_spans.iter().map(|f| ms(f.done.saturating_sub(f.started))).collect::<Vec<_>>(),
        "frames_started_ms": report.frame_spans.iter().map(|f| ms(f.started)).collect::<Vec<_>>(),
        "frames_done_ms": report.frame_spans.iter().map(|f| ms(f.done)).collect::<Vec<_>>(),
        "ms_per_frame": per_frame(report.total),
        "error": report.outcome.as_ref().err().map(|e| e.to_string()),
        "dispatches_per_frame": count(report.dispatches()),
        "submissions_per_frame": count(report.submissions()),
        "submissions_frames": report.frame_submissions,
        "frames_overlapped": report.overlapped,
        "stages": report.stages.iter().map(|s| serde_json::json!({
            "instance": s.instance, "component": s.class, "items": s.items,
            "host_ms_total": ms(s.host), "device_ms_total": ms(s.device),
            "host_ms_per_frame": per_frame(s.host), "device_ms_per_frame": per_frame(s.device),
            "dispatches_per_frame": count(s.dispatches),
            "host_ms_frames": s.frames.iter().map(|f| ms(f.host)).collect::<Vec<_>>(),
            "device_ms_frames": s.frames.iter().map(|f| ms(f.device)).collect::<Vec<_>>(),
            "dispatches_frames": s.frames.iter().map(|f| f.dispatches).collect::<Vec<_>>(),
            "async": s.apart,
            "source": s.source,
            "replayed": s.replayed,
            "fused_into": s.fused_into,
            "state": if s.failed.is_some() { "failed" } else { "ok" },
            "error": s.failed.as_ref().map(|e| e.message.clone()),
        })).collect::<Vec<_>>(),
        "figures": report.figures.iter().map(|f| serde_json::json!({
            "stage": f.stage, "name": f.name, "value": f.value,
        })).collect::<Vec<_>>(),
        "bindings": report.flows.iter().map(|b| serde_json::json!({
            "provider": b.provider, "provider_port": b.provider_port,
            "processor": b.processor, "processor_port": b.processor_port,
            "items": b.items, "carries": b.carries,
        })).collect::<Vec<_>>(),
        "outputs": paths(|_| true),
        "plots": paths(|p| p.extension().is_some_and(|e| e == "svg")),
    })
}
