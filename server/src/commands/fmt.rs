//! `gudsl fmt PATH…`: formats GU-DSL files in place (or, with `--check`, lists those that are
//! not formatted). Files with syntax errors are reported and left untouched.

use std::{path::PathBuf, process::ExitCode};

use clap::Args;

use crate::workspace;

#[derive(Args)]
pub struct FmtArgs {
    /// Files or folders (searched recursively for `.gudsl` files).
    #[arg(required = true)]
    paths: Vec<PathBuf>,
    /// Change nothing; exit 1 if a file is not formatted.
    #[arg(long)]
    check: bool,
}

pub fn run(args: &FmtArgs) -> ExitCode {
    let documents = match workspace::load(&args.paths) {
        Ok(documents) => documents,
        Err(error) => {
            eprintln!("gudsl fmt: {error}");
            return ExitCode::from(2);
        }
    };
    let (host, files) = workspace::analysis_host(&documents);
    let analysis = host.analysis();
    let mut failed = false;
    for (document, &file) in documents.iter().zip(&files) {
        let (Ok(formatted), Ok(parse)) = (analysis.format(file), analysis.parse(file)) else {
            eprintln!("gudsl fmt: the analysis was cancelled");
            return ExitCode::from(2);
        };
        let Some(formatted) = formatted else {
            eprintln!(
                "{}: not formatted: it has {} syntax error(s) (`gudsl check` lists them)",
                document.path.display(),
                parse.errors().len()
            );
            failed = true;
            continue;
        };
        if formatted == document.text {
            continue;
        }
        if args.check {
            println!("{}", document.path.display());
            failed = true;
        } else if let Err(error) = std::fs::write(&document.path, formatted) {
            eprintln!("gudsl fmt: {}: {error}", document.path.display());
            return ExitCode::from(2);
        }
    }
    if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}
