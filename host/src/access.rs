//! Which files a model may have read on its behalf, decided once: a model's files are read
//! beneath the workspace folder that holds it (the folders the editor opened, the current
//! folder of `gudsl check` and `gudsl run`), else beneath its own folder; and not at all while
//! the workspace is not trusted (VS Code's Restricted Mode, `trusted: false`).

use std::{
    path::{Path, PathBuf},
    sync::Arc,
};

use gudsl_files::{FileError, Folder, Problem};

/// The workspace folders and whether their models' files may be read.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Access {
    roots: Vec<PathBuf>,
    trusted: bool,
}

/// The folder a model's files are read from, and the model's folder its paths are relative to.
#[derive(Debug, Clone)]
pub struct ModelFiles {
    /// Why nothing is read: the workspace is not trusted, or its folder cannot be opened.
    folder: Result<Arc<Folder>, Problem>,
    model_dir: PathBuf,
}

impl Default for Access {
    /// The current folder, trusted: what a command run in a folder may read.
    fn default() -> Access {
        Access::new(vec![PathBuf::from(".")], true)
    }
}

impl Access {
    pub fn new(roots: Vec<PathBuf>, trusted: bool) -> Access {
        let roots = roots.iter().map(|root| gudsl_files::lexical(root)).collect();
        Access { roots, trusted }
    }

    pub fn trusted(&self) -> bool {
        self.trusted
    }

    /// The workspace folder that holds `model_dir`, if one does.
    pub fn workspace_of(&self, model_dir: &Path) -> Option<PathBuf> {
        let model_dir = gudsl_files::lexical(model_dir);
        self.roots.iter().find(|root| model_dir.starts_with(root)).cloned()
    }

    /// Whether a file may be written beside the file at `path` (a layout sidecar): beneath a
    /// workspace folder, or anywhere when no folder was opened (the user opened the file).
    pub fn may_write_beside(&self, path: &Path) -> bool {
        self.roots.is_empty() || path.parent().is_some_and(|dir| self.workspace_of(dir).is_some())
    }

    /// The folder a model in `model_dir` reads beneath: its workspace folder, else its own.
    pub fn root_of(&self, model_dir: &Path) -> PathBuf {
        self.workspace_of(model_dir).unwrap_or_else(|| gudsl_files::lexical(model_dir))
    }

    /// What a model in `model_dir` may read.
    pub fn files(&self, model_dir: &Path) -> ModelFiles {
        let folder = match self.trusted {
            true => Folder::open(&self.root_of(model_dir)).map(Arc::new).map_err(|e| e.problem),
            false => Err(Problem::Untrusted),
        };
        ModelFiles { folder, model_dir: model_dir.to_path_buf() }
    }
}

impl ModelFiles {
    /// The file a model names by `text` (relative to the model's folder).
    pub fn path(&self, text: &str) -> PathBuf {
        self.model_dir.join(text)
    }

    /// The folder `path` is read beneath (an `Arc`: what reads later, a run's frames, keeps
    /// it); an error naming `path` while nothing may be read.
    pub fn folder(&self, path: &Path) -> Result<&Arc<Folder>, FileError> {
        self.folder.as_ref().map_err(|problem| FileError::new(path, problem.clone()))
    }

    /// `path`'s length and modification time (`None`: missing, outside or not to be read).
    pub fn stamp(&self, path: &Path) -> Option<gudsl_files::Stamp> {
        self.folder.as_ref().ok()?.stamp(path)
    }
}
