//! `gudsl wgsl PATH… [--diagram NAME] [-o DIR]`: the WGSL the code generator makes of the device
//! diagrams (activity diagrams owned by an `OpenCL` class) of the given files, checked together
//! as one workspace; printed, or written as `DIR/<diagram>.wgsl`. A model with errors is refused
//! with its diagnostics, and so is a construct the generator cannot generate (E0301). Exit code:
//! 0 generated, 1 errors in the model or nothing to generate, 2 a path could not be read or an
//! output not written.

use gudsl_host::output::OutputDir;
use std::{io::Write, path::PathBuf, process::ExitCode};

use clap::Args;
use gudsl_host::named::names_diagram;

#[derive(Args)]
pub struct WgslArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Only the diagram with this name (simple or fully qualified).
    #[arg(long)]
    diagram: Option<String>,
    /// Write `<diagram>.wgsl` files into this folder (created if missing) instead of printing.
    #[arg(short = 'o', long = "output")]
    output: Option<PathBuf>,
}

pub fn run(args: &WgslArgs) -> ExitCode {
    // The check reports what cannot be generated (E0301) with the model's other problems.
    let checked = match super::checked_model(&args.paths, None, "wgsl") {
        Ok(checked) => checked,
        Err(code) => return code,
    };
    let generated = checked.host.analysis().with_semantics(|sema| {
        gudsl_codegen::device_diagrams(sema)
            .into_iter()
            .filter(|def| args.diagram.as_deref().is_none_or(|wanted| names_diagram(wanted, &def.fqn)))
            .map(|def| gudsl_codegen::generate(sema, def).map_err(|errors| (def.fqn.clone(), errors.len())))
            .collect::<Result<Vec<_>, _>>()
    });
    let kernels = match generated {
        Err(_) => return cancelled(),
        Ok(Err((diagram, problems))) => {
            eprintln!("gudsl wgsl: `{diagram}` cannot be generated ({problems} problem(s); `gudsl check` lists them)");
            return ExitCode::from(1);
        }
        Ok(Ok(kernels)) if kernels.is_empty() => {
            match &args.diagram {
                Some(name) => eprintln!(
                    "gudsl wgsl: no device diagram named `{name}` (an activity diagram owned by an OpenCL class)"
                ),
                None => eprintln!(
                    "gudsl wgsl: no device diagrams (activity diagrams owned by a class that implements OpenCL)"
                ),
            }
            return ExitCode::from(1);
        }
        Ok(Ok(kernels)) => kernels,
    };
    match &args.output {
        None => {
            let mut stdout = std::io::stdout().lock();
            for kernel in &kernels {
                if writeln!(stdout, "{}", kernel.wgsl).is_err() {
                    return ExitCode::from(2);
                }
            }
        }
        Some(folder) => {
            let mut output = match OutputDir::named(folder) {
                Ok(output) => output,
                Err(error) => {
                    eprintln!("gudsl wgsl: not writing into the output folder: {error}");
                    return ExitCode::from(2);
                }
            };
            for kernel in &kernels {
                if let Err(error) = output.write_top(&format!("{}.wgsl", kernel.diagram), kernel.wgsl.as_bytes()) {
                    eprintln!("gudsl wgsl: {error}");
                    return ExitCode::from(2);
                }
            }
            eprintln!("wrote {} kernel(s) to {}", kernels.len(), folder.display());
        }
    }
    ExitCode::SUCCESS
}

fn cancelled() -> ExitCode {
    eprintln!("gudsl wgsl: the analysis was cancelled");
    ExitCode::from(2)
}
