//! Finding and reading the GU-DSL documents of a workspace on disk.

use std::path::{Path, PathBuf};

use gudsl_model::{AnalysisHost, FileId};

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

/// Reads every `.gudsl` file named or found (recursively, sorted) under the given paths.
/// A file named explicitly is read whatever its extension.
pub fn load(paths: &[PathBuf]) -> Result<Vec<Document>, LoadError> {
    let mut files = Vec::new();
    for path in paths {
        let meta = std::fs::metadata(path).map_err(|e| LoadError { path: path.clone(), message: e.to_string() })?;
        if meta.is_dir() {
            let mut errors = Vec::new();
            files.extend(gudsl_files(path, &mut errors));
            if let Some(error) = errors.into_iter().next() {
                return Err(error);
            }
        } else {
            files.push(path.clone());
        }
    }
    files.dedup();
    files.into_iter().map(|path| Ok(Document { text: read_text(&path)?, path })).collect()
}

/// A host analysing the documents together, in order, each named by its path.
pub fn analysis_host(documents: &[Document]) -> (AnalysisHost, Vec<FileId>) {
    AnalysisHost::with_files(documents.iter().map(|d| (d.path.display().to_string(), d.text.clone())))
}

/// A file's text. Invalid UTF-8 is replaced, not rejected: the parser reports what it cannot read.
pub fn read_text(path: &Path) -> Result<String, LoadError> {
    let bytes = std::fs::read(path).map_err(|e| LoadError { path: path.to_path_buf(), message: e.to_string() })?;
    Ok(String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned()))
}

/// Every `.gudsl` file under `dir`, recursively, each folder's entries in sorted order. Hidden
/// folders, `target` and `node_modules` are skipped; a folder that cannot be read is reported
/// in `errors` and the walk goes on.
pub fn gudsl_files(dir: &Path, errors: &mut Vec<LoadError>) -> Vec<PathBuf> {
    let mut out = Vec::new();
    collect(dir, &mut out, errors);
    out
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>, errors: &mut Vec<LoadError>) {
    let entries: std::io::Result<Vec<PathBuf>> =
        std::fs::read_dir(dir).and_then(|entries| entries.map(|e| e.map(|e| e.path())).collect());
    let mut entries = match entries {
        Ok(entries) => entries,
        Err(e) => {
            errors.push(LoadError { path: dir.to_path_buf(), message: e.to_string() });
            return;
        }
    };
    entries.sort();
    for path in entries {
        if path.is_dir() {
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            if !name.starts_with('.') && name != "target" && name != "node_modules" {
                collect(&path, out, errors);
            }
        } else if path.extension().is_some_and(|ext| ext == "gudsl") {
            out.push(path);
        }
    }
}
