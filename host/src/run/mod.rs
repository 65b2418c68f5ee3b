//! Running host activity diagrams (chapter 10.3): `Main` and any other diagram without
//! parameters. [`prepare`] lowers the diagram (everything that cannot run is an error with its
//! range, before anything runs) and generates the kernels its calc nodes launch; [`PreparedRun::run`]
//! then runs it on a wgpu device without the model — viewer images go to the output folder, and
//! the [`Report`] says how the run ended, what each calc node took and what was printed.

mod arith;
mod compile;
mod device;
mod exec;
mod framework;
mod ir;
mod lower;
mod machine;
mod native;
mod printf;
mod report;
mod value;

use std::{
    fmt,
    path::{Path, PathBuf},
    time::{Duration, Instant},
};

use gudsl_codegen::Kernel;
use gudsl_model::{
    db::SourceFile,
    hir::{Definition, Semantics},
};
use gudsl_runtime::Gpu;

pub use ir::Span;
pub use report::{summary, write_report};
pub use value::Value;

use crate::{
    access::{Access, ModelFiles},
    launch::Launcher,
    output::OutputDir,
};

/// A diagram ready to run: lowered, its kernels generated.
pub struct PreparedRun {
    program: ir::Program,
    kernels: Vec<Kernel>,
    /// The file the diagram is declared in.
    file: SourceFile,
    /// What the diagram may read: relative file names (`image.load("x.png")`) from the diagram
    /// file's folder.
    files: ModelFiles,
    /// Whether loops of numbers run as machine code (`native/`); else every loop is closures.
    native_loops: bool,
}

/// Lowers the activity diagram `def` and generates its kernels, to read files as `access`
/// allows; or every construct that cannot run.
pub fn prepare(sema: &Semantics<'_>, def: &Definition, access: &Access) -> Result<PreparedRun, Vec<RunError>> {
    let lowered = lower::lower(sema, def)?;
    let path = def.file.path(sema.db());
    let files = access.files(Path::new(path).parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new(".")));
    Ok(PreparedRun { program: lowered.program, kernels: lowered.kernels, file: def.file, files, native_loops: true })
}

/// The GPU a host run launches its kernels on: the first wgpu adapter; else what to install.
pub fn gpu() -> Result<Gpu, String> {
    Gpu::new().map_err(|error| {
        format!("no GPU adapter ({error}); without a GPU, install Mesa's Vulkan driver (Debian: mesa-vulkan-drivers)")
    })
}

/// What a run tells as it goes, and how it is stopped.
pub trait Observer {
    /// A node is about to run.
    fn node(&mut self, _name: &str) {}
    /// `printf` wrote `text`.
    fn printed(&mut self, _text: &str) {}
    /// A calc node's kernel ran for `device` on the device.
    fn launched(&mut self, _node: &str, _kernel: &str, _device: Duration) {}
    /// Whether to stop (asked between nodes, and every 65 536 loop iterations).
    fn cancelled(&mut self) -> bool {
        false
    }
}

/// An observer that is told nothing and never stops a run.
impl Observer for () {}

/// What a run did.
#[derive(Debug)]
pub struct Report {
    pub diagram: String,
    /// How the run ended: at a node, or with an error (what was done until then is reported).
    pub outcome: Result<Ending, RunError>,
    pub device: String,
    pub nodes_run: u64,
    /// How often a loop ran as machine code (`native/`) rather than as closures.
    pub native_loops: u64,
    /// Each node that ran, in the order they first ran.
    pub nodes: Vec<NodeReport>,
    /// Each calc node's launches, in the order they first ran.
    pub calcs: Vec<CalcReport>,
    /// The viewer's images, as written.
    pub images: Vec<PathBuf>,
    pub printed: Vec<String>,
    /// Compiling the kernels for the device.
    pub compile: Duration,
    /// The whole run, compilation included.
    pub total: Duration,
    /// The diagram's variables when the run ended.
    pub variables: Vec<(String, Value)>,
}

/// Where a run ended.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Ending {
    /// At this final node.
    Final(String),
    /// At this node: none of its transitions could be taken.
    NoTransition(String),
}

/// How often a node ran and how long it took in all (its statements; the transitions out of
/// it not included).
#[derive(Debug, Clone, PartialEq)]
pub struct NodeReport {
    pub name: String,
    pub runs: u32,
    pub wall: Duration,
}

/// The launches of one kernel by one calc node.
#[derive(Debug, Clone, PartialEq)]
pub struct CalcReport {
    pub node: String,
    pub kernel: String,
    pub launches: u32,
    /// Submission to completion on the device.
    pub device: Duration,
    /// On the host, arguments and synchronisation included.
    pub wall: Duration,
}

/// Why a diagram did not run, or stopped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunError {
    pub kind: RunErrorKind,
    /// Where: the construct, the node, or nothing (the device, the output folder).
    pub span: Option<Span>,
    pub message: String,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunErrorKind {
    /// The construct cannot run on the host (found before the run).
    NotRunnable,
    /// The run stopped here (a file that cannot be read, an index out of range, a kernel
    /// that cannot be launched).
    Failed,
    /// Stopped on request, before this node.
    Cancelled,
}

impl RunError {
    fn not_runnable(span: Option<Span>, message: String) -> RunError {
        RunError { kind: RunErrorKind::NotRunnable, span, message }
    }

    fn failed(span: Option<Span>, message: String) -> RunError {
        RunError { kind: RunErrorKind::Failed, span, message }
    }

    fn cancelled(node: &str) -> RunError {
        RunError { kind: RunErrorKind::Cancelled, span: None, message: format!("cancelled before node `{node}`") }
    }
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for RunError {}

impl PreparedRun {
    pub fn diagram(&self) -> &str {
        &self.program.diagram
    }

    /// The files of the diagram and of the diagrams it calls (where the errors of its run are).
    pub fn files(&self) -> Vec<SourceFile> {
        let mut files = vec![self.file];
        for node in &self.program.nodes {
            if !files.contains(&node.span.file) {
                files.push(node.span.file);
            }
        }
        files
    }

    /// Whether loops of numbers run as machine code (the default) or as closures like the rest
    /// (to compare the two).
    pub fn set_native_loops(&mut self, native: bool) {
        self.native_loops = native;
    }

    /// The kernels the calc nodes launch.
    pub fn kernels(&self) -> &[Kernel] {
        &self.kernels
    }

    /// Runs the diagram on `gpu`; the viewer's images are written into `out_dir` (made if
    /// missing) when the run ends, however it ends.
    pub fn run(&self, gpu: &Gpu, output: &mut OutputDir, observer: &mut dyn Observer) -> Report {
        let started = Instant::now();
        let mut report = Report {
            diagram: self.program.diagram.clone(),
            outcome: Ok(Ending::Final(String::new())),
            device: gpu.describe(),
            nodes_run: 0,
            native_loops: 0,
            nodes: Vec::new(),
            calcs: Vec::new(),
            images: Vec::new(),
            printed: Vec::new(),
            compile: Duration::ZERO,
            total: Duration::ZERO,
            variables: Vec::new(),
        };
        let launchers: Result<Vec<Launcher>, RunError> = self
            .kernels
            .iter()
            .map(|kernel| {
                Launcher::new(gpu, kernel).map_err(|e| {
                    RunError::failed(
                        None,
                        format!("the kernel of `{}` does not compile on this device: {e}", kernel.diagram),
                    )
                })
            })
            .collect();
        report.compile = started.elapsed();
        let launchers = match launchers {
            Ok(launchers) => launchers,
            Err(error) => {
                report.outcome = Err(error);
                report.total = started.elapsed();
                return report;
            }
        };
        let framework = framework::Framework::new(gpu, self.files.clone());
        let mut machine = machine::Machine::new(&self.program, framework, &launchers, observer, self.native_loops);
        report.outcome = machine.run().map_err(|error| {
            let mut error = *error;
            // An error without a place of its own is placed on the node that was running.
            if error.span.is_none() && error.kind == RunErrorKind::Failed {
                error.span = Some(self.program.nodes[machine.node].span);
            }
            error
        });
        report.nodes_run = machine.nodes_run;
        report.native_loops = machine.native_loops;
        let mut ran: Vec<(usize, NodeReport)> = (machine.times.iter().zip(&self.program.nodes))
            .filter(|((runs, _, _), _)| *runs > 0)
            .map(|(&(runs, wall, first), node)| (first, NodeReport { name: node.name.clone(), runs, wall }))
            .collect();
        ran.sort_by_key(|(first, _)| *first);
        report.nodes = ran.into_iter().map(|(_, node)| node).collect();
        report.calcs = std::mem::take(&mut machine.calcs);
        report.printed = std::mem::take(&mut machine.framework.printed);
        report.variables =
            self.program.variables.iter().map(|(name, slot)| (name.clone(), machine.frame[*slot].clone())).collect();
        let written = machine.framework.write_viewers(output);
        match written {
            Ok(images) => report.images = images,
            Err(message) if report.outcome.is_ok() => {
                report.outcome = Err(RunError::failed(None, format!("the viewer's images were not written: {message}")))
            }
            Err(_) => {}
        }
        report.total = started.elapsed();
        report
    }
}
