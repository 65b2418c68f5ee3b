//! `gudsl run PATH… [--diagram NAME] [-o DIR]`: runs a component-instance diagram as a ToF
//! pipeline (`pipeline.rs`) or a host activity diagram without parameters
//! (`Main`) of the given files, checked together as one workspace: its calc nodes' kernels on
//! the first wgpu adapter (Mesa's lavapipe without a GPU). Nodes are shown on stderr as they
//! start, `printf` output on stdout as it is written; then a report — how the run ended, what
//! each calc node and the slowest nodes took — on stdout, and as `DIR/report.json` beside the
//! viewer's images. A model with errors is refused with its diagnostics, and so is a diagram
//! with constructs that cannot run (E0302); an error during the run is shown where it happened
//! (E0303). Exit code: 0 the run reached a final node, 1 errors in the model or the run, 2 a path
//! could not be read, no device, or the output not written.

use std::{
    collections::HashSet,
    io::{IsTerminal, Write},
    path::{Path, PathBuf},
    process::ExitCode,
    time::{Duration, Instant},
};

use clap::Args;
use gudsl_host::run::{Ending, Observer, Prepared, Report, RunError, RunErrorKind};
use gudsl_model::{
    analysis::FileId,
    hir::{DefKind, Definition, DiagnosticCode, Semantics, Severity},
};

use crate::report::{self, Finding};

#[derive(Args)]
pub struct RunArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// The diagram to run (simple or fully qualified name): a component-instance diagram (a
    /// ToF pipeline) or a host activity diagram such as `Main`; optional when the files have
    /// one diagram that can run.
    #[arg(long)]
    diagram: Option<String>,
    /// Write the outputs and `report.json` into this folder (created if missing; default: for
    /// a pipeline `gudsl-out/<diagram>/`, for an activity diagram the current folder).
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
    /// Run at most this many frames of a pipeline.
    #[arg(long)]
    frames: Option<usize>,
    /// Run a pipeline on the CPU reference instead of the GPU.
    #[arg(long)]
    cpu: bool,
}

pub fn run(args: &RunArgs) -> ExitCode {
    let (host, files, mut checked) = match super::checked_model(&args.paths, "run") {
        Ok(checked) => checked,
        Err(code) => return code,
    };
    let analysis = host.analysis();
    let chosen = analysis.with_semantics(|sema| choose(sema, &files, args.diagram.as_deref()));
    let diagram = match answered(chosen) {
        Err(code) => return code,
        Ok(Chosen::Pipeline(fqn)) => {
            let pipeline = super::pipeline::PipelineArgs {
                diagram: &fqn,
                frames: args.frames,
                cpu: args.cpu,
                output: args.output.as_deref(),
            };
            return super::pipeline::run(&analysis, &files, checked, &pipeline);
        }
        Ok(Chosen::Activity(fqn)) => fqn,
    };
    let output = args.output.clone().unwrap_or_else(|| PathBuf::from("."));
    let prepared = analysis.with_semantics(|sema| prepare_named(sema, &files, &diagram));
    let prepared = match answered(prepared) {
        Err(code) => return code,
        Ok(Err(errors)) => {
            add_findings(&mut checked, &files, &errors, DiagnosticCode::NotRunnable);
            eprintln!("gudsl run: `{diagram}` cannot run");
            return super::refuse(&checked, 1);
        }
        Ok(Ok(prepared)) => prepared,
    };
    let gpu = match gudsl_runtime::Gpu::new() {
        Ok(gpu) => gpu,
        Err(error) => {
            eprintln!(
                "gudsl run: no GPU adapter ({error}); without a GPU, install Mesa's Vulkan driver (Debian: mesa-vulkan-drivers)"
            );
            return ExitCode::from(2);
        }
    };
    eprintln!("running {} on {}", prepared.diagram(), gpu.describe());
    let mut progress = Progress { terminal: std::io::stderr().is_terminal(), rewritten: None, written: HashSet::new() };
    let report = prepared.run(&gpu, &output, &mut progress);
    progress.done();
    print_report(&report);
    if let Err(error) = write_report(&report, &output) {
        eprintln!("gudsl run: {error}");
        return ExitCode::from(2);
    }
    match &report.outcome {
        Ok(_) => ExitCode::SUCCESS,
        Err(error) => {
            let placed = error.span.is_some_and(|s| files.contains(&s.file));
            if placed {
                checked.findings.clear();
                add_findings(&mut checked, &files, std::slice::from_ref(error), DiagnosticCode::RunFailed);
                let _ = report::write(&checked, report::Format::Human, report::Color::Auto);
            } else {
                eprintln!("error: {error}");
            }
            ExitCode::from(if error.kind == RunErrorKind::Failed && !placed { 2 } else { 1 })
        }
    }
}

/// An answer of the model, or the exit code after saying why there is none: 2 when the
/// analysis was cancelled, 1 when the answer is why no diagram is meant.
fn answered<T>(answer: Result<Result<T, String>, gudsl_model::Cancelled>) -> Result<T, ExitCode> {
    match answer {
        Ok(Ok(value)) => Ok(value),
        Ok(Err(message)) => {
            eprintln!("gudsl run: {message}");
            Err(ExitCode::from(1))
        }
        Err(_) => {
            eprintln!("gudsl run: the analysis was cancelled");
            Err(ExitCode::from(2))
        }
    }
}

/// The kind of diagram `run` runs.
enum Chosen {
    Pipeline(String),
    Activity(String),
}

/// The diagram of `files` that `--diagram` names (simple or fully qualified), or without it the
/// one diagram that can run: a component-instance diagram or a host activity diagram without
/// parameters; `Err` says why none is meant, listing those that can run.
fn choose(sema: &Semantics<'_>, files: &[FileId], name: Option<&str>) -> Result<Chosen, String> {
    let mut runnable: Vec<(&str, bool)> = sema
        .def_map()
        .definitions
        .values()
        .flatten()
        .filter(|def| files.contains(&def.file))
        .filter_map(|def| match def.kind {
            DefKind::ComponentInstanceDiagram => Some((def.fqn.as_str(), true)),
            _ if is_runnable(sema, def) => Some((def.fqn.as_str(), false)),
            _ => None,
        })
        .collect();
    runnable.sort();
    runnable.dedup();
    let listed = || {
        let names: Vec<&str> = runnable.iter().map(|(fqn, _)| *fqn).collect();
        if names.is_empty() {
            "none".to_string()
        } else {
            names.join(", ")
        }
    };
    let Some(name) = name else {
        return match runnable[..] {
            [(fqn, true)] => Ok(Chosen::Pipeline(fqn.to_string())),
            [(fqn, false)] => Ok(Chosen::Activity(fqn.to_string())),
            [] => Err("the files have no diagram that can run (a component-instance diagram, or an activity diagram without parameters)".into()),
            _ => Err(format!("name the diagram to run with --diagram: {}", listed())),
        };
    };
    let pipelines: Vec<&str> =
        runnable.iter().filter(|(fqn, is)| *is && super::names_diagram(name, fqn)).map(|(f, _)| *f).collect();
    match pipelines[..] {
        [fqn] => Ok(Chosen::Pipeline(fqn.to_string())),
        [] => Ok(Chosen::Activity(name.to_string())),
        _ => Err(format!(
            "several component-instance diagrams are named `{name}`: {}; name one fully qualified",
            pipelines.join(", ")
        )),
    }
}

/// The fully qualified name of the component-instance diagram of `files` named `name` (simple
/// or fully qualified); `Err` says why none is meant, listing the pipelines there are.
pub fn pipeline_named(sema: &Semantics<'_>, files: &[FileId], name: &str) -> Result<String, String> {
    let mut pipelines: Vec<&str> = sema
        .def_map()
        .definitions
        .values()
        .flatten()
        .filter(|def| matches!(def.kind, DefKind::ComponentInstanceDiagram) && files.contains(&def.file))
        .map(|def| def.fqn.as_str())
        .collect();
    pipelines.sort();
    pipelines.dedup();
    let named: Vec<&str> = pipelines.iter().copied().filter(|fqn| super::names_diagram(name, fqn)).collect();
    match named[..] {
        [fqn] => Ok(fqn.to_string()),
        [] => Err(format!(
            "no component-instance diagram named `{name}`; pipelines: {}",
            if pipelines.is_empty() { "none".to_string() } else { pipelines.join(", ") }
        )),
        _ => Err(format!(
            "several component-instance diagrams are named `{name}`: {}; name one fully qualified",
            named.join(", ")
        )),
    }
}

/// The activity diagram of `files` named `name` (simple or fully qualified), prepared to run;
/// `Err` says why no diagram is meant (none or several have the name, listing those that can
/// run), `Ok(Err)` what in the diagram cannot run.
pub fn prepare_named(
    sema: &Semantics<'_>,
    files: &[FileId],
    name: &str,
) -> Result<Result<Prepared, Vec<RunError>>, String> {
    let candidates: Vec<_> = sema
        .def_map()
        .definitions
        .values()
        .flatten()
        .filter(|def| matches!(def.kind, DefKind::Activity(_)) && files.contains(&def.file))
        .collect();
    let named: Vec<_> = candidates.iter().filter(|def| super::names_diagram(name, &def.fqn)).collect();
    match named[..] {
        [def] => Ok(gudsl_host::run::prepare(sema, def)),
        [] => {
            let mut runnable: Vec<&str> =
                candidates.iter().filter(|def| is_runnable(sema, def)).map(|def| def.fqn.as_str()).collect();
            runnable.sort();
            Err(format!(
                "no activity diagram named `{name}`; diagrams that can run: {}",
                if runnable.is_empty() { "none".to_string() } else { runnable.join(", ") }
            ))
        }
        _ => Err(format!(
            "several activity diagrams are named `{name}`: {}; name one fully qualified",
            named.iter().map(|d| d.fqn.as_str()).collect::<Vec<_>>().join(", ")
        )),
    }
}

/// Whether `def` is a host activity diagram without parameters (what `run` offers to run).
pub fn is_runnable(sema: &Semantics<'_>, def: &Definition) -> bool {
    matches!(&def.kind, DefKind::Activity(a) if a.params.is_empty()) && !gudsl_codegen::is_device_diagram(sema, def)
}

/// Writes `report.json` into `output` (created if missing); the report as written.
pub fn write_report(report: &Report, output: &Path) -> Result<serde_json::Value, String> {
    let json = report_json(report);
    let text = serde_json::to_string_pretty(&json).expect("a report serialises");
    let path = output.join("report.json");
    match std::fs::create_dir_all(output).and_then(|()| std::fs::write(&path, text + "\n")) {
        Ok(()) => Ok(json),
        Err(error) => Err(format!("{}: {error}", path.display())),
    }
}

/// The run's errors as findings of the report `gudsl check` writes.
fn add_findings(report: &mut report::Report, files: &[FileId], errors: &[RunError], code: DiagnosticCode) {
    for error in errors {
        let Some(span) = error.span else {
            eprintln!("error: {error}");
            continue;
        };
        let Some(file) = files.iter().position(|f| *f == span.file) else {
            eprintln!("error: {error}");
            continue;
        };
        report.findings.push(Finding {
            file,
            severity: Severity::Error,
            code,
            message: error.message.clone(),
            range: span.range,
            related: Vec::new(),
        });
    }
    report.findings.sort_by_key(|f| (f.file, f.range.start()));
}

/// Nodes on stderr as they start — on a terminal, one line rewritten for a node that runs
/// for the first time, else at most every [`REWRITE_INTERVAL`]; in a log, a line for each node
/// the first time it runs (loops over nodes and called diagrams run nodes by the thousand) —
/// and `printf` output on stdout.
struct Progress {
    terminal: bool,
    /// When the terminal's line was last rewritten.
    rewritten: Option<Instant>,
    /// The nodes that ran.
    written: HashSet<String>,
}

/// How often a terminal's progress line is rewritten at most.
const REWRITE_INTERVAL: Duration = Duration::from_millis(50);

impl Observer for Progress {
    fn node(&mut self, name: &str) {
        let first = !self.written.contains(name);
        if first {
            self.written.insert(name.to_string());
        }
        if !self.terminal {
            if first {
                eprintln!("  node {name}");
            }
        } else if first || self.rewritten.is_none_or(|at| at.elapsed() >= REWRITE_INTERVAL) {
            eprint!("\r\x1b[2K  node {name}");
            self.rewritten = Some(Instant::now());
        }
    }

    fn printed(&mut self, text: &str) {
        self.done();
        let mut stdout = std::io::stdout().lock();
        let _ = stdout.write_all(text.as_bytes());
        let _ = stdout.flush();
    }
}

impl Progress {
    /// Ends the rewritten line on a terminal.
    fn done(&mut self) {
        if self.terminal {
            eprint!("\r\x1b[2K");
        }
    }
}

/// One line: how the run ended, in how long, on which device.
pub fn summary(report: &Report) -> String {
    let ended = match &report.outcome {
        Ok(Ending::Final(node)) => format!("ran {} to final node `{node}`", report.diagram),
        Ok(Ending::NoTransition(node)) => {
            format!("ran {} until `{node}`, which has no transition whose guard holds", report.diagram)
        }
        Err(error) if error.kind == RunErrorKind::Cancelled => format!("{}: {error}", report.diagram),
        Err(_) => format!("{} stopped with an error", report.diagram),
    };
    format!(
        "{ended} in {} ({} nodes; kernels compiled in {}) on {}",
        ms(report.total),
        report.nodes_run,
        ms(report.compile),
        report.device
    )
}

fn print_report(report: &Report) {
    println!("{}", summary(report));
    if !report.calcs.is_empty() {
        let node_width = report.calcs.iter().map(|c| c.node.len()).max().unwrap_or(0).max(9);
        let kernel_width = report.calcs.iter().map(|c| c.kernel.len()).max().unwrap_or(0).max(6);
        println!("{:node_width$}  {:kernel_width$}  launches  {:>10}  {:>10}", "calc node", "kernel", "device", "wall");
        for calc in &report.calcs {
            println!(
                "{:node_width$}  {:kernel_width$}  {:>8}  {:>10}  {:>10}",
                calc.node,
                calc.kernel,
                calc.launches,
                ms(calc.device),
                ms(calc.wall)
            );
        }
    }
    let mut slowest: Vec<_> = report.nodes.iter().filter(|n| !n.wall.is_zero()).collect();
    slowest.sort_by_key(|n| std::cmp::Reverse(n.wall));
    let slowest: Vec<String> = slowest.iter().take(3).map(|n| format!("{} {}", n.name, ms(n.wall))).collect();
    if !slowest.is_empty() {
        println!("slowest nodes: {}", slowest.join(", "));
    }
    for image in &report.images {
        println!("wrote {}", image.display());
    }
}

fn ms(duration: Duration) -> String {
    format!("{:.1} ms", duration.as_secs_f64() * 1000.0)
}

/// `report.json`: what the run did, for scripts.
fn report_json(report: &Report) -> serde_json::Value {
    let millis = |d: Duration| d.as_secs_f64() * 1000.0;
    let (ended_at, error) = match &report.outcome {
        Ok(Ending::Final(node)) | Ok(Ending::NoTransition(node)) => (Some(node.clone()), None),
        Err(error) => (None, Some(error.message.clone())),
    };
    serde_json::json!({
        "diagram": report.diagram,
        "device": report.device,
        "ended_at": ended_at,
        "reached_final_node": matches!(report.outcome, Ok(Ending::Final(_))),
        "error": error,
        "nodes_run": report.nodes_run,
        "compile_ms": millis(report.compile),
        "total_ms": millis(report.total),
        "nodes": report.nodes.iter().map(|n| serde_json::json!({
            "name": n.name, "runs": n.runs, "wall_ms": millis(n.wall),
        })).collect::<Vec<_>>(),
        "calcs": report.calcs.iter().map(|c| serde_json::json!({
            "node": c.node, "kernel": c.kernel, "launches": c.launches,
            "device_ms": millis(c.device), "wall_ms": millis(c.wall),
        })).collect::<Vec<_>>(),
        "images": report.images.iter().map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned())).collect::<Vec<_>>(),
        "printed": report.printed,
    })
}
