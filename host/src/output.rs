//! The one folder a run writes into, and the one place that decides where it is: the folder
//! the user named, else `gudsl-out/<diagram>` beneath the folder the run was started from (the
//! current folder, the editor's workspace folder). It is made without following a link and
//! refused while it holds one (`gudsl_files::Folder::output`); sinks ask for a file by a name
//! of their own, reduced to a plain file name, and each file is written as a temporary file
//! renamed over the name — a link a repository committed there is replaced, never written
//! through. Every file written is listed for the report.

use std::{
    path::{Path, PathBuf},
    sync::Arc,
};

use gudsl_files::{FileError, Folder, Growing};

/// The folder outputs go to when the user names none: `gudsl-out/<diagram's simple name>`.
pub const DEFAULT_FOLDER: &str = "gudsl-out";

/// The output folder of a run and the files written into it.
pub struct OutputDir {
    root: Arc<Folder>,
    written: Vec<PathBuf>,
}

impl OutputDir {
    /// The output folder of a run of `diagram`: `named` when the user named one (made beneath
    /// its parent), else `gudsl-out/<diagram's simple name>` beneath `anchor`.
    pub fn for_run(named: Option<&Path>, anchor: &Path, diagram: &str) -> Result<OutputDir, FileError> {
        if let Some(path) = named {
            return OutputDir::named(path);
        }
        let simple = diagram.rsplit('.').next().unwrap_or(diagram);
        let root = Folder::output(anchor, &Path::new(DEFAULT_FOLDER).join(plain(simple)))?;
        Ok(OutputDir { root: Arc::new(root), written: Vec::new() })
    }

    /// The folder at `path`, one the user named (`-o`): made beneath its parent, which is the
    /// user's and made if missing.
    pub fn named(path: &Path) -> Result<OutputDir, FileError> {
        Ok(OutputDir { root: Arc::new(named_folder(path)?), written: Vec::new() })
    }

    /// The folder `name` (reduced to a plain name) in it, as the output folder of a run of its
    /// own: a setting of a parameter study.
    pub fn nested(&self, name: &str) -> Result<OutputDir, String> {
        let folder = self.root.subfolder(&plain(name)).map_err(|e| format!("cannot write into {e}"))?;
        Ok(OutputDir { root: Arc::new(folder), written: Vec::new() })
    }

    /// The `report.json` of every run beneath it, up to `depth` folders down (a recording's
    /// folder, a setting's in it), with the folder each is in (relative, `/`-separated), in
    /// the order of their folders' names.
    pub fn reports(&self, depth: usize) -> Result<Vec<(String, Vec<u8>)>, String> {
        let mut found = Vec::new();
        reports_in(&self.root, "", depth, &mut found).map_err(|e| format!("cannot read {e}"))?;
        Ok(found)
    }

    /// The folder's path.
    pub fn path(&self) -> &Path {
        self.root.path()
    }

    /// Writes `bytes` to the file `name` in the folder `sink` (an instance's name) of the
    /// output folder; both reduced to plain names (no separators, no `..`).
    pub fn write(&mut self, sink: &str, name: &str, bytes: &[u8]) -> Result<PathBuf, String> {
        let folder = self.root.subfolder(&plain(sink)).map_err(|e| format!("cannot write into {e}"))?;
        let path = folder.write(&plain(name), bytes).map_err(|e| format!("cannot write {e}"))?;
        Ok(self.listed(path))
    }

    /// Starts the file `name` in the folder `sink` (both reduced to plain names) that a sink
    /// writes a piece at a time (a recording): it appears, whole, when [`OutputDir::commit`]ted.
    pub fn create(&mut self, sink: &str, name: &str) -> Result<Growing, String> {
        let folder = self.root.subfolder(&plain(sink)).map_err(|e| format!("cannot write into {e}"))?;
        folder.create(&plain(name)).map_err(|e| format!("cannot write {e}"))
    }

    /// Gives a file [`OutputDir::create`] started its name, and lists it.
    pub fn commit(&mut self, file: Growing) -> Result<PathBuf, String> {
        let path = file.commit().map_err(|e| format!("cannot write {e}"))?;
        Ok(self.listed(path))
    }

    /// Writes `bytes` to the file `name` (reduced to a plain name) at the top of the folder.
    pub fn write_top(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, String> {
        let path = self.root.write(&plain(name), bytes).map_err(|e| format!("cannot write {e}"))?;
        Ok(self.listed(path))
    }

    fn listed(&mut self, path: PathBuf) -> PathBuf {
        if !self.written.contains(&path) {
            self.written.push(path.clone());
        }
        path
    }

    /// The same folder for a writer on another thread: its files listed apart until
    /// [`OutputDir::absorb`] takes them.
    pub fn fork(&self) -> OutputDir {
        OutputDir { root: self.root.clone(), written: Vec::new() }
    }

    /// The files a fork wrote, listed here.
    pub fn absorb(&mut self, fork: OutputDir) {
        for path in fork.written {
            self.listed(path);
        }
    }

    /// The files written so far, in the order first written.
    pub fn written(&self) -> &[PathBuf] {
        &self.written
    }
}

/// Limits a run's `report.json` (they are small: a stage a line).
const REPORT_LIMIT: u64 = 16 << 20;

fn reports_in(folder: &Folder, at: &str, depth: usize, found: &mut Vec<(String, Vec<u8>)>) -> Result<(), FileError> {
    if depth == 0 {
        return Ok(());
    }
    for name in folder.folder_names()? {
        let inner = folder.subfolder(&name)?;
        let relative = if at.is_empty() { name.clone() } else { format!("{at}/{name}") };
        if inner.file_names()?.iter().any(|f| f == "report.json") {
            found.push((relative.clone(), inner.read(&inner.path().join("report.json"), REPORT_LIMIT)?));
        }
        reports_in(&inner, &relative, depth - 1, found)?;
    }
    Ok(())
}

/// A folder the user named: made beneath its parent (which is the user's and made if missing).
fn named_folder(path: &Path) -> Result<Folder, FileError> {
    match (path.parent(), path.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
            Folder::output(parent, Path::new(name))
        }
        _ => Folder::output(path, Path::new("")),
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
    use std::{fs, os::unix::fs::symlink};

    use super::*;

    #[test]
    fn names_stay_inside_the_folder() {
        assert_eq!(plain("distance_0001.npy"), "distance_0001.npy");
        assert_eq!(plain("../../etc/passwd"), "_.._etc_passwd");
        assert_eq!(plain(".."), "_");
        assert_eq!(plain("C:\\x"), "C__x");
    }

    #[test]
    fn a_run_writes_into_gudsl_out_or_the_named_folder_and_never_through_a_link() {
        let anchor = tempfile::tempdir().unwrap();
        let mut output = OutputDir::for_run(None, anchor.path(), "Samples.Depth").unwrap();
        assert_eq!(output.path(), anchor.path().join("gudsl-out/Depth"));
        let written = output.write("Sink", "d.npy", b"x").unwrap();
        assert_eq!(written, anchor.path().join("gudsl-out/Depth/Sink/d.npy"));
        assert_eq!(output.written(), [written]);

        let named = anchor.path().join("elsewhere/out");
        assert_eq!(OutputDir::for_run(Some(&named), anchor.path(), "P").unwrap().path(), named);

        let victim = anchor.path().join("victim");
        fs::write(&victim, b"mine").unwrap();
        fs::create_dir_all(anchor.path().join("gudsl-out/Depth/Sink")).unwrap();
        symlink(&victim, anchor.path().join("gudsl-out/Depth/Sink/e.npy")).unwrap();
        let refused = OutputDir::for_run(None, anchor.path(), "Depth").err().unwrap();
        assert!(refused.to_string().contains("holds links"), "{refused}");
        assert_eq!(fs::read(&victim).unwrap(), b"mine");
    }
}
