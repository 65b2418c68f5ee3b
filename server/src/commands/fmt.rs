//! `gudsl fmt PATH…`: formats GU-DSL files in place (or, with `--check`, lists those that are
//! not formatted). Files with syntax errors are reported and left untouched; files that are not
//! UTF-8 are refused, never rewritten. A file is replaced atomically (written beside it, then
//! renamed over it), so a full disk or a crash leaves the original whole.

use std::{
    io::{self, Write},
    path::{Path, PathBuf},
    process::ExitCode,
};

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
    let loaded = workspace::load(&args.paths);
    let mut unwritable = !loaded.errors.is_empty();
    for error in &loaded.errors {
        eprintln!("gudsl fmt: {error}");
    }
    let (host, files) = workspace::analysis_host(&loaded.documents);
    let analysis = host.analysis();
    let mut unformatted = false;
    for (document, &file) in loaded.documents.iter().zip(&files) {
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
            unformatted = true;
            continue;
        };
        if formatted == document.text {
            continue;
        }
        if args.check {
            println!("{}", document.path.display());
            unformatted = true;
        } else if let Err(error) = replace_file(&document.path, formatted.as_bytes()) {
            eprintln!("gudsl fmt: {}: {error} (the file is unchanged)", document.path.display());
            unwritable = true;
        }
    }
    if unwritable {
        ExitCode::from(2)
    } else if unformatted {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    }
}

/// Replaces the file `path` leads to (through symbolic links) with `contents`: written to a
/// temporary file in the same folder, flushed to disk, given the original's permissions, then
/// renamed over it. On any failure the original is untouched and the temporary file removed.
fn replace_file(path: &Path, contents: &[u8]) -> io::Result<()> {
    let target = std::fs::canonicalize(path)?;
    let folder = target.parent().unwrap_or(Path::new("."));
    let mut temporary = tempfile::Builder::new().prefix(".gudsl-fmt-").suffix(".tmp").tempfile_in(folder)?;
    temporary.write_all(contents)?;
    temporary.as_file().set_permissions(std::fs::metadata(&target)?.permissions())?;
    temporary.as_file().sync_all()?;
    temporary.persist(&target).map_err(|error| error.error)?;
    Ok(())
}
