//! `gudsl`: the GU-DSL command-line tools and language server.

// Proving the server's futures `Send` walks down into wgpu's types (a live preview's kept
// items hold device buffers), deeper than the default 128.
#![recursion_limit = "256"]

mod commands;
mod layout_file;
mod lsp;
mod report;
mod workspace;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(name = "gudsl", version, about = "GU-DSL language tools")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Check GU-DSL files or folders and report every problem found.
    Check(commands::check::CheckArgs),
    /// Format GU-DSL files in place (`--check`: only report unformatted files).
    Fmt(commands::fmt::FmtArgs),
    /// Draw diagrams as SVG or PNG (or their geometry as JSON).
    Render(commands::render::RenderArgs),
    /// Print or write the WGSL generated from the device diagrams (activity diagrams of OpenCL classes).
    Wgsl(commands::wgsl::WgslArgs),
    /// Run a host activity diagram (e.g. `Main`): its calc nodes' kernels on the GPU (lavapipe without one).
    Run(commands::run::RunArgs),
    /// Merge the runs of many recordings (every shard's) under an output folder into one summary table.
    Summarize(SummarizeArgs),
    /// Fit chapter 4's phase-normalization calibration on the simulated camera and write it as .npy.
    CalibratePhases(commands::calibrate_phases::CalibratePhasesArgs),
    /// Run the language server on stdin/stdout (for editors).
    Lsp(LspArgs),
}

/// `gudsl summarize DIR`: the summary `gudsl run --inputs` writes when it ran every recording,
/// of what every shard wrote under `DIR`.
#[derive(clap::Args)]
struct SummarizeArgs {
    /// The output folder of `gudsl run --inputs` (its `-o`).
    folder: std::path::PathBuf,
}

/// `gudsl lsp`'s flags: stdio is its only transport, and `--stdio` (which clients such as
/// vscode-languageclient append) says so.
#[derive(clap::Args)]
struct LspArgs {
    /// Talk over stdin/stdout (the default and only transport).
    #[arg(long)]
    stdio: bool,
}

fn main() -> ExitCode {
    gudsl_runtime::gpu::quiet_headless_adapters();
    let cli = Cli::parse();
    match cli.command {
        Command::Check(args) => commands::check::run(&args),
        Command::Fmt(args) => commands::fmt::run(&args),
        Command::Render(args) => commands::render::run(&args),
        Command::Wgsl(args) => commands::wgsl::run(&args),
        Command::CalibratePhases(args) => commands::calibrate_phases::run(&args),
        Command::Run(args) => commands::run::run(&args),
        Command::Summarize(args) => match gudsl_host::output::OutputDir::named(&args.folder) {
            Ok(mut folder) => ExitCode::from(commands::pipeline::summarize(&mut folder)),
            Err(error) => {
                eprintln!("gudsl summarize: {error}");
                ExitCode::from(2)
            }
        },
        Command::Lsp(LspArgs { stdio: _ }) => lsp::run(),
    }
}
