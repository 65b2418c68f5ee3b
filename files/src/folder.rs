//! A folder as a capability: every path opened through it resolves beneath it — `..`, an
//! absolute path or a link that leads out is refused (cap-std, openat2 `RESOLVE_BENEATH` where
//! the kernel has it) —, files are opened without blocking and read only when they are regular
//! files no longer than the caller's limit, and files are written as a temporary file in the
//! folder renamed over the name, so a write replaces a link instead of following it.

use std::{
    ffi::OsStr,
    io::{Read, Write},
    path::{Component, Path, PathBuf},
    time::SystemTime,
};

use cap_fs_ext::DirExt;
use cap_std::{
    ambient_authority,
    fs::{Dir, FileType, OpenOptions},
};

use crate::{FileError, Problem};

/// A folder gudsl may read (and, for an output folder or a document's folder, write) files in.
#[derive(Debug)]
pub struct Folder {
    pub(crate) dir: Dir,
    /// The folder's path as the user named it, made absolute (not resolved: messages show it).
    pub(crate) path: PathBuf,
}

/// A file opened for reading: a regular file, with its length when opened.
#[derive(Debug)]
pub struct Opened {
    pub file: std::fs::File,
    pub len: u64,
    /// The file as the user named it.
    pub path: PathBuf,
}

/// A file as it was: its length and modification time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stamp {
    pub len: u64,
    pub modified: Option<SystemTime>,
}

impl Folder {
    /// The folder at `path`, one the user named (the command line, the editor's workspace).
    pub fn open(path: &Path) -> Result<Folder, FileError> {
        let path = absolute(path);
        let dir = Dir::open_ambient_dir(&path, ambient_authority()).map_err(|e| FileError::io(&path, &path, &e))?;
        Ok(Folder { dir, path })
    }

    /// The folder's path, absolute.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Opens `path` (a path as std takes it: absolute, or relative to the current folder) for
    /// reading, when it lies beneath this folder — `..` is taken lexically, a link is followed
    /// only while it stays inside: refused outside the folder, when not a regular file (a FIFO
    /// or a device is never read, and opening one does not block), or when longer than `limit`.
    pub fn open_file(&self, path: &Path, limit: u64) -> Result<Opened, FileError> {
        let (inside, shown) = self.inside(path)?;
        let mut options = OpenOptions::new();
        options.read(true);
        #[cfg(unix)]
        {
            use cap_std::fs::OpenOptionsExt;
            options.custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY);
        }
        let file = self.dir.open_with(&inside, &options).map_err(|e| FileError::io(&shown, &self.path, &e))?;
        let meta = file.metadata().map_err(|e| FileError::io(&shown, &self.path, &e))?;
        if !meta.is_file() {
            return Err(FileError::new(shown, Problem::NotRegular { kind: kind_of(meta.file_type()) }));
        }
        if meta.len() > limit {
            return Err(FileError::new(shown, Problem::TooLarge { len: meta.len(), limit }));
        }
        Ok(Opened { file: file.into_std(), len: meta.len(), path: shown })
    }

    /// The contents of `path` (see [`Folder::open_file`]); never more than `limit` bytes, even
    /// when the file grows while it is read.
    pub fn read(&self, path: &Path, limit: u64) -> Result<Vec<u8>, FileError> {
        let opened = self.open_file(path, limit)?;
        let mut bytes = Vec::with_capacity(opened.len as usize);
        opened.file.take(limit).read_to_end(&mut bytes).map_err(|e| FileError::io(&opened.path, &self.path, &e))?;
        Ok(bytes)
    }

    /// The names of the regular files in the folder itself (not in its subfolders, no links),
    /// sorted; names that are not UTF-8 are left out.
    pub fn file_names(&self) -> Result<Vec<String>, FileError> {
        self.names(|kind| kind.is_file())
    }

    /// The names of the regular files in the folder at `path` beneath this one (see
    /// [`Folder::file_names`]); refused outside it like a file.
    pub fn file_names_in(&self, path: &Path) -> Result<Vec<String>, FileError> {
        let (inside, shown) = self.inside(path)?;
        let failed = |e: std::io::Error| FileError::io(&shown, &self.path, &e);
        let dir = self.dir.open_dir(&inside).map_err(failed)?;
        Folder { dir, path: self.path.join(&inside) }.file_names()
    }

    /// The names of the folders in the folder itself (no links), sorted; names that are not
    /// UTF-8 are left out.
    pub fn folder_names(&self) -> Result<Vec<String>, FileError> {
        self.names(|kind| kind.is_dir())
    }

    /// The sorted names of the entries of a `kind` (a link is none) in the folder itself.
    fn names(&self, kind: fn(&cap_std::fs::FileType) -> bool) -> Result<Vec<String>, FileError> {
        let failed = |e: std::io::Error| FileError::io(&self.path, &self.path, &e);
        let mut names = Vec::new();
        for entry in self.dir.entries().map_err(failed)? {
            let entry = entry.map_err(failed)?;
            if kind(&entry.file_type().map_err(failed)?) {
                names.extend(entry.file_name().into_string());
            }
        }
        names.sort();
        Ok(names)
    }

    /// `path`'s length and modification time (following links that stay in the folder), without
    /// opening it; `None` when it is missing, outside or unreadable.
    pub fn stamp(&self, path: &Path) -> Option<Stamp> {
        let (inside, _) = self.inside(path).ok()?;
        let meta = self.dir.metadata(inside).ok()?;
        Some(Stamp { len: meta.len(), modified: meta.modified().ok().map(|t| t.into_std()) })
    }

    /// Writes `bytes` to the file `name` (one plain name) in this folder: into a temporary file
    /// beside it, renamed over `name` once complete — an existing link named `name` is replaced,
    /// never followed, and a reader never sees half a file.
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<PathBuf, FileError> {
        let shown = self.path.join(name);
        if !is_plain(Path::new(name)) {
            return Err(FileError::new(shown, Problem::Outside { folder: self.path.clone() }));
        }
        let failed = |e: std::io::Error| FileError::io(&shown, &self.path, &e);
        let mut temporary = cap_tempfile::TempFile::new(&self.dir).map_err(failed)?;
        temporary.write_all(bytes).map_err(failed)?;
        temporary.replace(OsStr::new(name)).map_err(failed)?;
        Ok(shown)
    }

    /// Removes the file (or link) `name` in this folder; a missing one is no error.
    pub fn remove(&self, name: &str) -> Result<(), FileError> {
        match self.dir.remove_file_or_symlink(name) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
                Err(FileError::io(self.path.join(name), &self.path, &e))
            }
            _ => Ok(()),
        }
    }

    /// `path` as a path relative to this folder, and as the user is shown it (as given).
    fn inside(&self, path: &Path) -> Result<(PathBuf, PathBuf), FileError> {
        match lexical(path).strip_prefix(lexical(&self.path)) {
            Ok(inside) if inside.as_os_str().is_empty() => Ok((PathBuf::from("."), path.to_path_buf())),
            Ok(inside) => Ok((inside.to_path_buf(), path.to_path_buf())),
            Err(_) => Err(FileError::new(path, Problem::Outside { folder: self.path.clone() })),
        }
    }
}

/// What a file that is not a regular file is, as a message names it.
fn kind_of(kind: FileType) -> &'static str {
    #[cfg(unix)]
    {
        use cap_std::fs::FileTypeExt;
        if kind.is_fifo() {
            return "a FIFO";
        }
        if kind.is_char_device() || kind.is_block_device() {
            return "a device";
        }
        if kind.is_socket() {
            return "a socket";
        }
    }
    if kind.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

/// `path` made absolute against the current folder (the empty path is the current folder),
/// without resolving links.
pub(crate) fn absolute(path: &Path) -> PathBuf {
    let path = if path.as_os_str().is_empty() { Path::new(".") } else { path };
    std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf())
}

/// `path` made absolute and normalized lexically: where a user reading the path would say it
/// is (links are not resolved).
pub fn lexical(path: &Path) -> PathBuf {
    normalize(&absolute(path))
}

/// `path` with `.` dropped and each `..` taking away the component before it (lexically).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for component in path.components() {
        match component {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Whether `path` is one plain name: not empty, no separator, not `.` or `..`.
pub(crate) fn is_plain(path: &Path) -> bool {
    let mut components = path.components();
    matches!((components.next(), components.next()), (Some(Component::Normal(_)), None))
}
