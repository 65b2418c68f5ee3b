//! Finding and reading the GU-DSL documents of a workspace on disk.

use std::path::{Path, PathBuf};

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
            collect(path, &mut files)?;
        } else {
            files.push(path.clone());
        }
    }
    files.dedup();
    files
        .into_iter()
        .map(|path| {
            let bytes = std::fs::read(&path).map_err(|e| LoadError { path: path.clone(), message: e.to_string() })?;
            // Invalid UTF-8 is replaced, not rejected: the parser reports what it cannot read.
            let text = String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
            Ok(Document { path, text })
        })
        .collect()
}

fn collect(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), LoadError> {
    let error = |e: std::io::Error| LoadError { path: dir.to_path_buf(), message: e.to_string() };
    let mut entries: Vec<PathBuf> =
        std::fs::read_dir(dir).map_err(error)?.map(|e| e.map(|e| e.path())).collect::<Result<_, _>>().map_err(error)?;
    entries.sort();
    for path in entries {
        if path.is_dir() {
            let hidden = path.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.'));
            if !hidden && path.file_name().is_none_or(|n| n != "target") {
                collect(&path, out)?;
            }
        } else if path.extension().is_some_and(|ext| ext == "gudsl") {
            out.push(path);
        }
    }
    Ok(())
}
