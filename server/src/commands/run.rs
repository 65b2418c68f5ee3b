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
use gudsl_host::{
    named::{self, Runnable},
    output::OutputDir,
    run::{summary, write_report, Observer, Report, RunError, RunErrorKind},
};
use gudsl_model::{
    analysis::FileId,
    hir::{DiagnosticCode, Severity},
};

use super::Checked;
use crate::report::{self, Finding};

#[derive(Args)]
pub struct RunArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    pub(super) paths: Vec<PathBuf>,
    /// The diagram to run (simple or fully qualified name): a component-instance diagram (a
    /// ToF pipeline) or a host activity diagram such as `Main`; optional when the files have
    /// one diagram that can run.
    #[arg(long)]
    pub(super) diagram: Option<String>,
    /// Write the outputs and `report.json` into this folder (created if missing; refused while
    /// it holds a link; default: `gudsl-out/<diagram>/`).
    #[arg(short = 'o', long = "output")]
    pub(super) output: Option<PathBuf>,
    /// Read the files models name only beneath this folder (default: the current folder; a
    /// model outside it reads beneath its own folder).
    #[arg(long, value_name = "DIR")]
    pub(super) root: Option<PathBuf>,
    /// Run at most this many frames of a pipeline.
    #[arg(long)]
    pub(super) frames: Option<usize>,
    /// Run a pipeline on the CPU reference instead of the GPU.
    #[arg(long)]
    pub(super) cpu: bool,
    /// Run a pipeline's frames one after another on the GPU: the next frame is not recorded
    /// while the GPU works on one (the same results, slower; for comparing).
    #[arg(long)]
    pub(super) one_frame_at_a_time: bool,
    /// Run each stage of a pipeline with its own kernels, none inside the kernels of the stages
    /// it feeds (the same results, more dispatches; for comparing).
    #[arg(long)]
    pub(super) unfused: bool,
    /// Run a pipeline with a parameter set as written in the model, without editing it (as
    /// `Motion.windowSize=7`; checked as if typed). Repeatable.
    #[arg(long = "set", value_name = "INSTANCE.PARAMETER=VALUE", value_parser = super::settings::assignment)]
    pub(super) sets: Vec<super::settings::Assignment>,
    /// A parameter study: run the pipeline at each value (as `Motion.threshold=0,1,5`); several
    /// sweeps run every combination, each setting into a folder of its own, with a table,
    /// `study.csv` and a plot of every figure per setting. Repeatable.
    #[arg(long = "sweep", value_name = "INSTANCE.PARAMETER=V1,V2,…", value_parser = super::settings::sweep)]
    pub(super) sweeps: Vec<super::settings::Sweep>,
    /// Many recordings: run the pipeline once for each file or folder the glob names (relative
    /// to the current folder; `@FILE`: a manifest, one path a line), its path in place of
    /// `{recording}` in the values of --set and --sweep, into `<output>/<recording's name>/`;
    /// then `summary.csv` of them all.
    #[arg(long, value_name = "GLOB|@FILE")]
    pub(super) inputs: Option<String>,
    /// Run only shard K of N of the recordings (K from 0; every N-th from the K-th); unset,
    /// from JOB_COMPLETION_INDEX/JOB_COMPLETION_COUNT (Kubernetes) or
    /// SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT (Slurm). `gudsl summarize` merges the shards.
    #[arg(long, value_name = "K/N", value_parser = super::batch::shard)]
    pub(super) shard: Option<super::batch::Shard>,
    /// Skip the recordings whose runs all ended well before (each wrote its `report.json`).
    #[arg(long)]
    pub(super) resume: bool,
}

pub fn run(args: &RunArgs) -> ExitCode {
    let Checked { mut host, files, report: mut checked, preparations } = match super::checked_model_but_inputs(
        &args.paths,
        args.root.as_deref(),
        "run",
        !args.sets.is_empty() || !args.sweeps.is_empty() || args.inputs.is_some(),
    ) {
        Ok(checked) => checked,
        Err(code) => return code,
    };
    let analysis = host.analysis();
    let chosen = analysis.with_semantics(|sema| named::runnable(sema, &files, args.diagram.as_deref()));
    let diagram = match answered(chosen) {
        Err(code) => return code,
        Ok(Runnable::Pipeline(fqn)) => {
            let pipeline = super::pipeline::PipelineArgs {
                diagram: &fqn,
                frames: args.frames,
                cpu: args.cpu,
                one_frame_at_a_time: args.one_frame_at_a_time,
                unfused: args.unfused,
                output: args.output.as_deref(),
                sets: &args.sets,
                sweeps: &args.sweeps,
                inputs: args.inputs.as_deref(),
                shard: args.shard,
                resume: args.resume,
            };
            drop(analysis);
            return super::pipeline::run(&mut host, &files, &preparations, checked, &pipeline);
        }
        Ok(Runnable::Activity(fqn)) => fqn,
    };
    let prepared = analysis.with_semantics(|sema| {
        named::activity_named(sema, &files, &diagram)
            .map(|def| gudsl_host::run::prepare(sema, def, &preparations.access()))
    });
    let prepared = match answered(prepared) {
        Err(code) => return code,
        Ok(Err(errors)) => {
            add_findings(&mut checked, &files, &errors, DiagnosticCode::NotRunnable);
            eprintln!("gudsl run: `{diagram}` cannot run");
            return super::refuse(&checked, 1);
        }
        Ok(Ok(prepared)) => prepared,
    };
    let gpu = match gudsl_host::run::gpu() {
        Ok(gpu) => gpu,
        Err(why) => {
            eprintln!("gudsl run: {why}");
            return ExitCode::from(2);
        }
    };
    let mut output = match OutputDir::for_run(args.output.as_deref(), Path::new("."), &diagram) {
        Ok(output) => output,
        Err(error) => {
            eprintln!("gudsl run: not writing into the output folder: {error}");
            return ExitCode::from(2);
        }
    };
    eprintln!("running {} on {}", prepared.diagram(), gpu.describe());
    let mut progress = Progress { terminal: std::io::stderr().is_terminal(), rewritten: None, written: HashSet::new() };
    let report = prepared.run(&gpu, &mut output, &mut progress);
    progress.done();
    print_report(&report);
    if let Err(error) = write_report(&report, &mut output) {
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
