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
    let mut failed = false;
    for document in &documents {
        let parse = gudsl_model::parse(&document.text);
        let Some(formatted) = gudsl_model::format::format(&parse) else {
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
