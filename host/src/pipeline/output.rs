//! The one folder a pipeline writes into: sinks ask for a file by a name of their own, get a
//! path inside the folder (the name reduced to a plain file name, so nothing lands outside it),
//! and every file written is listed for the report.

use std::{
    fs, io,
    path::{Path, PathBuf},
};

/// The output folder of a run and the files written into it.
pub struct OutputDir {
    root: PathBuf,
    written: Vec<PathBuf>,
}

impl OutputDir {
    /// The folder `root`, created (with its parents) if missing.
    pub fn create(root: &Path) -> io::Result<OutputDir> {
        fs::create_dir_all(root)?;
        if !root.is_dir() {
            return Err(io::Error::new(io::ErrorKind::AlreadyExists, format!("{} is not a folder", root.display())));
        }
        Ok(OutputDir { root: root.to_path_buf(), written: Vec::new() })
    }

    /// Writes `bytes` to the file `name` in the folder `sink` (an instance's name) of the
    /// output folder; both reduced to plain names (no separators, no `..`).
    pub fn write(&mut self, sink: &str, name: &str, bytes: &[u8]) -> Result<PathBuf, String> {
        self.write_in(self.root.join(plain(sink)), name, bytes)
    }

    /// Writes `bytes` to the file `name` (a plain name) at the top of the output folder.
    pub fn write_top(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, String> {
        self.write_in(self.root.clone(), name, bytes)
    }

    fn write_in(&mut self, folder: PathBuf, name: &str, bytes: &[u8]) -> Result<PathBuf, String> {
        let path = folder.join(plain(name));
        fs::create_dir_all(&folder)
            .and_then(|()| fs::write(&path, bytes))
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        if !self.written.contains(&path) {
            self.written.push(path.clone());
        }
        Ok(path)
    }

    /// The same folder for a writer on another thread: its files listed apart until
    /// [`OutputDir::absorb`] takes them.
    pub fn fork(&self) -> OutputDir {
        OutputDir { root: self.root.clone(), written: Vec::new() }
    }

    /// The files a fork wrote, listed here.
    pub fn absorb(&mut self, fork: OutputDir) {
        for path in fork.written {
            if !self.written.contains(&path) {
                self.written.push(path);
            }
        }
    }

    /// The files written so far, in the order first written.
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }
}

/// `name` as one plain path component: separators and leading dots replaced.
fn plain(name: &str) -> String {
    let cleaned: String =
        name.chars().map(|c| if c == '/' || c == '\\' || c == ':' || c.is_control() { '_' } else { c }).collect();
    let cleaned = cleaned.trim_start_matches('.');
    if cleaned.is_empty() {
        "_".to_string()
    } else {
        cleaned.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::plain;

    #[test]
    fn names_stay_inside_the_folder() {
        assert_eq!(plain("distance_0001.npy"), "distance_0001.npy");
        assert_eq!(plain("../../etc/passwd"), "_.._etc_passwd");
        assert_eq!(plain(".."), "_");
        assert_eq!(plain("C:\\x"), "C__x");
    }
}
