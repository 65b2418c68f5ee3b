//! Finding and reading the GU-DSL documents of a workspace on disk — the only file reading of
//! the product. Folders are walked as ripgrep walks them (the `ignore` crate): `.gitignore`d and
//! hidden entries skipped, symbolic links followed but loops cut, each file read once however
//! many paths lead to it. Only regular files are read (a FIFO or a link to a device would hang),
//! at most [`MAX_FILE_BYTES`], and only as UTF-8: text is never guessed.

use std::{
    collections::HashSet,
    io::Read,
    path::{Path, PathBuf},
};

use gudsl_model::{AnalysisHost, FileId};

/// The largest file read (a GU-DSL document of this size is a mistake, not a model).
pub const MAX_FILE_BYTES: u64 = 16 << 20;

/// A document read from disk.
pub struct Document {
    /// The path as the user should see it (relative to where it was found).
    pub path: PathBuf,
    pub text: String,
}

/// Why a path could not be loaded.
#[derive(Debug)]
pub struct LoadError {
    pub path: PathBuf,
    pub message: String,
}

impl std::fmt::Display for LoadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

fn error(path: &Path, message: impl Into<String>) -> LoadError {
    LoadError { path: path.to_path_buf(), message: message.into() }
}

/// What loading found: the documents it read and every path it could not.
#[derive(Default)]
pub struct Loaded {
    pub documents: Vec<Document>,
    pub errors: Vec<LoadError>,
}

/// Reads every `.gudsl` file named or found under the given paths (see [`document_paths`]). A
/// path that fails is reported; the others are read.
pub fn load(paths: &[PathBuf]) -> Loaded {
    let mut loaded = Loaded::default();
    for file in document_paths(paths, &mut loaded.errors) {
        match read_text(&file) {
            Ok(text) => loaded.documents.push(Document { text, path: file }),
            Err(e) => loaded.errors.push(e),
        }
    }
    loaded
}

/// Every `.gudsl` file named or found under the given files and folders (each folder's files
/// sorted), each once however many paths lead to it (a link, `a/../a`); what cannot be walked,
/// and a named file that is not `.gudsl`, goes to `errors`. Reads no file.
pub fn document_paths(paths: &[PathBuf], errors: &mut Vec<LoadError>) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    for path in paths {
        let files = match std::fs::metadata(path) {
            Ok(meta) if meta.is_dir() => gudsl_files(path, errors),
            Ok(_) if path.extension().is_some_and(|e| e == "gudsl") => vec![path.clone()],
            Ok(_) => {
                errors.push(error(path, "not a `.gudsl` file"));
                continue;
            }
            Err(e) => {
                errors.push(error(path, e.to_string()));
                continue;
            }
        };
        for file in files {
            let identity = std::fs::canonicalize(&file).unwrap_or_else(|_| file.clone());
            if seen.insert(identity) {
                out.push(file);
            }
        }
    }
    out
}

/// A regular file's text: refused when it is not a regular file, larger than
/// [`MAX_FILE_BYTES`], or not UTF-8 (a leading byte-order mark is fine).
pub fn read_text(path: &Path) -> Result<String, LoadError> {
    let meta = std::fs::metadata(path).map_err(|e| error(path, e.to_string()))?;
    if !meta.is_file() {
        return Err(error(path, "not a regular file (a FIFO, a device or a folder): not read"));
    }
    if meta.len() > MAX_FILE_BYTES {
        return Err(error(path, format!("{} bytes: larger than the {MAX_FILE_BYTES} bytes read", meta.len())));
    }
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .and_then(|f| f.take(MAX_FILE_BYTES + 1).read_to_end(&mut bytes))
        .map_err(|e| error(path, e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let before = &e.as_bytes()[..at];
        let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
        let byte = at - before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1) + 1;
        error(
            path,
            format!("not UTF-8 (line {line}, byte {byte} of the line): GU-DSL files are UTF-8; convert it, e.g. `iconv -f latin1 -t utf-8`"),
        )
    })
}

/// Every `.gudsl` file under `dir`, sorted per folder; folders that cannot be read are reported
/// in `errors` and the walk goes on (symbolic-link loops are cut without a word).
fn gudsl_files(dir: &Path, errors: &mut Vec<LoadError>) -> Vec<PathBuf> {
    let walk = ignore::WalkBuilder::new(dir)
        .follow_links(true)
        .filter_entry(|entry| !matches!(entry.file_name().to_str(), Some("target" | "node_modules")))
        .sort_by_file_name(|a, b| a.cmp(b))
        .build();
    let mut out = Vec::new();
    for entry in walk {
        match entry {
            Ok(entry) => {
                let path = entry.path();
                if entry.file_type().is_some_and(|t| !t.is_dir()) && path.extension().is_some_and(|e| e == "gudsl") {
                    // `./a.gudsl` is shown as `a.gudsl`.
                    out.push(path.strip_prefix(".").unwrap_or(path).to_path_buf());
                }
            }
            Err(e) if is_loop(&e) => {}
            Err(e) => errors.push(error(dir, e.to_string())),
        }
    }
    out
}

fn is_loop(error: &ignore::Error) -> bool {
    match error {
        ignore::Error::Loop { .. } => true,
        ignore::Error::WithPath { err, .. } | ignore::Error::WithDepth { err, .. } => is_loop(err),
        _ => false,
    }
}

/// A host analysing the documents together, in order, each named by its path.
pub fn analysis_host(documents: &[Document]) -> (AnalysisHost, Vec<FileId>) {
    AnalysisHost::with_files(documents.iter().map(|d| (d.path.display().to_string(), d.text.clone())))
}
