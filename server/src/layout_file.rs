//! The layout sidecar on disk: `<model>.gudsl.layout` beside a model file (its format is
//! `gudsl_render::pins`). Read by `gudsl render` and the language server; written by the server
//! when a client moves or resizes a node or saves the model (the rows of its diagrams drawn),
//! and by `gudsl render --remember` — atomically (a temporary file in the same folder renamed
//! over it) — and removed when its last pin and rows go.

use std::path::{Path, PathBuf};

use gudsl_files::{Folder, Problem};
use gudsl_render::pins::{LayoutFile, Rows};

/// The longest sidecar read: far more than the pins of any diagram a person places.
const MAX_LAYOUT_BYTES: u64 = 16 << 20;

/// The sidecar of the model file at `model`.
pub fn path_for(model: &Path) -> PathBuf {
    let mut name = model.as_os_str().to_owned();
    name.push(".layout");
    PathBuf::from(name)
}

/// The folder a sidecar lies in (its model's), and its file name.
fn folder_of(path: &Path) -> Result<(Folder, String), String> {
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
    let name = name.ok_or_else(|| format!("{}: not a file name", path.display()))?;
    Ok((Folder::open(folder).map_err(|e| e.to_string())?, name))
}

/// The sidecar at `path`: empty where there is none; `Err` says which file and why it is no
/// layout (it is then left as it is: never overwritten). Read through its model's folder: a
/// FIFO, a device or a link out of the folder is refused at once, and at most
/// [`MAX_LAYOUT_BYTES`] are read.
pub fn read(path: &Path) -> Result<LayoutFile, String> {
    let (folder, _) = folder_of(path)?;
    match folder.read(path, MAX_LAYOUT_BYTES) {
        Ok(bytes) => {
            let text = String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8 text", path.display()))?;
            LayoutFile::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
        }
        Err(e) if e.problem == Problem::NotFound => Ok(LayoutFile::default()),
        Err(e) => Err(e.to_string()),
    }
}

/// Writes `layout` to `path` (removes the file where no pin is left): a temporary file in the
/// same folder renamed over it, so a link there is replaced, never written through.
pub fn write(path: &Path, layout: &LayoutFile) -> Result<(), String> {
    let (folder, name) = folder_of(path)?;
    let done = match layout.is_empty() {
        true => folder.remove(&name),
        false => folder.write(&name, layout.to_json().as_bytes()).map(|_| ()),
    };
    done.map_err(|e| e.to_string())
}

/// Keeps the `drawn` rows (by diagram) in the sidecar at `path`, written where they changed;
/// whether it was. A sidecar that is no layout is not overwritten: the error says which and why.
pub fn remember(path: &Path, drawn: Vec<(String, Rows)>) -> Result<bool, String> {
    let mut layout = read(path).map_err(|error| format!("{error}: fix or delete it (it is not overwritten)"))?;
    let changed = layout.remember(drawn);
    if changed {
        write(path, &layout)?;
    }
    Ok(changed)
}

#[cfg(test)]
mod tests {
    use gudsl_render::pins::Pin;

    use super::*;

    #[test]
    fn written_atomically_beside_the_model_read_back_and_removed_when_empty() {
        let folder = tempfile::tempdir().unwrap();
        let model = folder.path().join("shapes.gudsl");
        let path = path_for(&model);
        assert_eq!(path.file_name().unwrap(), "shapes.gudsl.layout");
        assert_eq!(read(&path), Ok(LayoutFile::default()), "no sidecar: no pins");
        let mut layout = LayoutFile::default();
        layout
            .diagrams
            .entry("S".into())
            .or_default()
            .insert("S.A".into(), Pin { x: 1.0, y: 2.0, width: None, height: None });
        write(&path, &layout).unwrap();
        assert_eq!(read(&path), Ok(layout.clone()));
        // Only the sidecar is in the folder: no temporary file left behind.
        assert_eq!(std::fs::read_dir(folder.path()).unwrap().count(), 1);
        layout.diagrams.clear();
        write(&path, &layout).unwrap();
        assert!(!path.exists());
        write(&path, &layout).unwrap();
    }

    #[test]
    fn a_file_that_is_no_layout_is_named_in_the_error() {
        let folder = tempfile::tempdir().unwrap();
        let path = folder.path().join("a.gudsl.layout");
        std::fs::write(&path, "{ not json").unwrap();
        let error = read(&path).unwrap_err();
        assert!(error.starts_with(&path.display().to_string()) && error.contains("line 1"), "{error}");
    }

    #[test]
    fn a_fifo_a_device_or_a_link_out_as_sidecar_is_refused_at_once_and_never_written_through() {
        let folder = tempfile::tempdir().unwrap();
        let elsewhere = tempfile::tempdir().unwrap();
        let fifo = folder.path().join("f.gudsl.layout");
        assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
        let zero = folder.path().join("z.gudsl.layout");
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        let kept = elsewhere.path().join("kept");
        std::fs::write(&kept, "the user's").unwrap();
        let out = folder.path().join("o.gudsl.layout");
        std::os::unix::fs::symlink(&kept, &out).unwrap();

        let started = std::time::Instant::now();
        assert!(read(&fifo).unwrap_err().contains("is a FIFO"));
        assert!(read(&zero).unwrap_err().contains("lies outside"));
        assert!(read(&out).unwrap_err().contains("lies outside"));
        assert!(started.elapsed().as_secs() < 1, "nothing blocks");

        let mut layout = LayoutFile::default();
        let pin = Pin { x: 1.0, y: 2.0, width: None, height: None };
        layout.diagrams.entry("S".into()).or_default().insert("S.A".into(), pin);
        write(&out, &layout).unwrap();
        assert_eq!(std::fs::read_to_string(&kept).unwrap(), "the user's", "the link is replaced, not followed");
        assert_eq!(read(&out), Ok(layout));
    }
}
