//! Output folders: made beneath a folder the user chose, one component at a time, never
//! through a link, and refused while anything inside them is a link — a cloned repository may
//! commit `gudsl-out/P/Sink/distance_0000.npy -> ~/.ssh/authorized_keys`.

use std::path::{Path, PathBuf};

use cap_fs_ext::DirExt;
use cap_std::fs::Dir;

use crate::{
    folder::{absolute, is_plain},
    FileError, Folder, Problem,
};

/// How deep and how many entries an output folder is searched for links.
const LINK_SEARCH_DEPTH: usize = 16;
const LINK_SEARCH_ENTRIES: usize = 100_000;

impl Folder {
    /// The output folder `relative` beneath `anchor`: `anchor` is the user's (the current
    /// folder, a workspace folder, the parent of a folder named on the command line) and is
    /// made if missing; `relative` (plain names, no `..`) is made one folder at a time, each
    /// refused if it is a link; and the folder is refused while anything inside it is a link.
    pub fn output(anchor: &Path, relative: &Path) -> Result<Folder, FileError> {
        let anchor = absolute(anchor);
        std::fs::create_dir_all(&anchor).map_err(|e| FileError::io(&anchor, &anchor, &e))?;
        let mut folder = Folder::open(&anchor)?;
        for component in relative.components() {
            let name = component.as_os_str().to_string_lossy();
            if !is_plain(Path::new(component.as_os_str())) {
                return Err(FileError::new(anchor.join(relative), Problem::Outside { folder: anchor }));
            }
            folder = folder.subfolder(&name)?;
        }
        let links = folder.links();
        if !links.is_empty() {
            return Err(FileError::new(folder.path, Problem::Links { links }));
        }
        Ok(folder)
    }

    /// The folder `name` (one plain name) in this one, made if missing; refused if it is a link.
    pub fn subfolder(&self, name: &str) -> Result<Folder, FileError> {
        let path = self.path.join(name);
        if !is_plain(Path::new(name)) {
            return Err(FileError::new(path, Problem::Outside { folder: self.path.clone() }));
        }
        match self.dir.create_dir(name) {
            Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => {
                return Err(FileError::io(&path, &self.path, &e))
            }
            _ => {}
        }
        let meta = self.dir.symlink_metadata(name).map_err(|e| FileError::io(&path, &self.path, &e))?;
        if meta.file_type().is_symlink() {
            return Err(FileError::new(&self.path, Problem::Links { links: vec![path] }));
        }
        if !meta.is_dir() {
            return Err(FileError::new(path, Problem::Io("exists and is not a folder".to_string())));
        }
        let dir = self.dir.open_dir_nofollow(name).map_err(|e| FileError::io(&path, &self.path, &e))?;
        Ok(Folder { dir, path })
    }

    /// Every link inside this folder, however deep (up to a bound), by path.
    pub fn links(&self) -> Vec<PathBuf> {
        let mut links = Vec::new();
        let mut budget = LINK_SEARCH_ENTRIES;
        links_in(&self.dir, &self.path, LINK_SEARCH_DEPTH, &mut budget, &mut links);
        links
    }
}

fn links_in(dir: &Dir, path: &Path, depth: usize, budget: &mut usize, links: &mut Vec<PathBuf>) {
    let Ok(entries) = dir.entries() else { return };
    for entry in entries.flatten() {
        if *budget == 0 {
            return;
        }
        *budget -= 1;
        let Ok(kind) = entry.file_type() else { continue };
        let name = entry.file_name();
        if kind.is_symlink() {
            links.push(path.join(&name));
        } else if kind.is_dir() && depth > 0 {
            if let Ok(inner) = dir.open_dir_nofollow(&name) {
                links_in(&inner, &path.join(&name), depth - 1, budget, links);
            }
        }
    }
}
