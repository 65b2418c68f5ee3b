//! Why a file was not read or written: the file as the user named it and what is wrong with
//! it, in words a user can act on.

use std::{fmt, io, path::PathBuf};

/// A file that was not read or written, and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FileError {
    /// The file as the user would find it (the folder joined with the name the model gave).
    pub path: PathBuf,
    pub problem: Problem,
}

/// What is wrong with a file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Problem {
    NotFound,
    /// It lies outside the folder it must be in (through `..`, an absolute path or a link).
    Outside {
        folder: PathBuf,
    },
    /// A FIFO, a device, a socket or a folder where a file's contents were expected.
    NotRegular {
        kind: &'static str,
    },
    /// Longer than the most this kind of file is read.
    TooLarge {
        len: u64,
        limit: u64,
    },
    /// Links inside an output folder: a write could land where they point.
    Links {
        links: Vec<PathBuf>,
    },
    /// The workspace is not trusted (VS Code's Restricted Mode): no file a model names is read.
    Untrusted,
    Io(String),
}

impl FileError {
    pub fn new(path: impl Into<PathBuf>, problem: Problem) -> FileError {
        FileError { path: path.into(), problem }
    }

    /// An I/O error: "does not exist" for a missing file, an escape as [`Problem::Outside`].
    pub fn io(path: impl Into<PathBuf>, folder: &std::path::Path, error: &io::Error) -> FileError {
        let problem = match error.kind() {
            io::ErrorKind::NotFound => Problem::NotFound,
            // cap-std answers an escape through `..`, an absolute path or a link so.
            io::ErrorKind::PermissionDenied if is_escape(error) => Problem::Outside { folder: folder.to_path_buf() },
            _ => Problem::Io(without_os_code(error)),
        };
        FileError::new(path, problem)
    }
}

/// Whether cap-std refused a path for leaving its folder (it says "a path led outside of the
/// filesystem"), not the operating system for lack of permission.
fn is_escape(error: &io::Error) -> bool {
    error.raw_os_error().is_none() && error.to_string().contains("outside of the filesystem")
}

/// An I/O error's message without " (os error 13)".
fn without_os_code(error: &io::Error) -> String {
    let text = error.to_string();
    match text.rfind(" (os error") {
        Some(at) => text[..at].to_string(),
        None => text,
    }
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.problem)
    }
}

/// What is wrong, said of the file: "does not exist".
impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Problem::NotFound => write!(f, "does not exist"),
            Problem::Outside { folder } => write!(
                f,
                "lies outside {} (through `..`, an absolute path or a link): gudsl reads and writes a model's files only beneath the folder it was given",
                folder.display()
            ),
            Problem::NotRegular { kind } => write!(f, "is {kind}, not a regular file: not read"),
            Problem::TooLarge { len, limit } => write!(f, "holds {len} bytes, more than the {limit} read for a file of this kind"),
            Problem::Links { links } => write!(
                f,
                "is an output folder that holds links, which a write could follow out of it: {}; remove them (or name another folder)",
                links.iter().map(|l| l.display().to_string()).collect::<Vec<_>>().join(", ")
            ),
            Problem::Untrusted => {
                write!(f, "is not read: the workspace is not trusted (Restricted Mode), so gudsl reads no file a model names")
            }
            Problem::Io(message) => f.write_str(message),
        }
    }
}

impl std::error::Error for FileError {}
