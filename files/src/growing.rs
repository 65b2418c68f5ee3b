//! A file written a piece at a time (a recording a run appends to frame by frame): a temporary
//! file in its folder, renamed over its name when committed — like [`Folder::write`], a link
//! of that name is replaced, never followed, and a reader never sees half a file; dropped
//! uncommitted, the temporary file is removed.

use std::{
    io::{self, Seek, SeekFrom, Write},
    path::{Path, PathBuf},
    sync::atomic::{AtomicU64, Ordering},
};

use cap_std::fs::{Dir, OpenOptions};

use crate::{folder::is_plain, FileError, Folder, Problem};

/// A file being written into a folder; `commit` gives it its name.
#[derive(Debug)]
pub struct Growing {
    dir: Dir,
    temporary: String,
    name: String,
    file: std::fs::File,
    /// The file as the user is shown it (the folder's path and the name).
    shown: PathBuf,
    committed: bool,
}

impl Folder {
    /// Starts writing the file `name` (one plain name) in this folder.
    pub fn create(&self, name: &str) -> Result<Growing, FileError> {
        let shown = self.path.join(name);
        if !is_plain(Path::new(name)) {
            return Err(FileError::new(shown, Problem::Outside { folder: self.path.clone() }));
        }
        let failed = |e: io::Error| FileError::io(&shown, &self.path, &e);
        static NEXT: AtomicU64 = AtomicU64::new(0);
        let temporary = format!(".{name}.{}-{}.part", std::process::id(), NEXT.fetch_add(1, Ordering::Relaxed));
        let mut options = OpenOptions::new();
        options.write(true).create_new(true);
        let file = self.dir.open_with(&temporary, &options).map_err(failed)?;
        let dir = self.dir.try_clone().map_err(failed)?;
        Ok(Growing { dir, temporary, name: name.to_string(), file: file.into_std(), shown, committed: false })
    }
}

impl Growing {
    /// Gives the file its name (replacing what had it) once everything is written.
    pub fn commit(mut self) -> Result<PathBuf, FileError> {
        let failed = |e: io::Error| FileError::io(&self.shown, self.shown.parent().unwrap_or(&self.shown), &e);
        self.file.sync_all().map_err(failed)?;
        self.dir.rename(&self.temporary, &self.dir, &self.name).map_err(failed)?;
        self.committed = true;
        Ok(self.shown.clone())
    }

    /// The file as the user is shown it once committed.
    pub fn path(&self) -> &Path {
        &self.shown
    }
}

impl Write for Growing {
    fn write(&mut self, bytes: &[u8]) -> io::Result<usize> {
        self.file.write(bytes)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.file.flush()
    }
}

impl Seek for Growing {
    fn seek(&mut self, to: SeekFrom) -> io::Result<u64> {
        self.file.seek(to)
    }
}

impl Drop for Growing {
    fn drop(&mut self) {
        if !self.committed {
            let _ = self.dir.remove_file(&self.temporary);
        }
    }
}
