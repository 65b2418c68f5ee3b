//! The layout sidecar on disk: `<model>.gudsl.layout` beside a model file (its format is
//! `gudsl_render::pins`). Read by `gudsl render` and the language server; written only by the
//! server, when a client moves or resizes a node, atomically (a temporary file in the same
//! folder renamed over it), and removed when its last pin goes.

use std::{
    io::Write,
    path::{Path, PathBuf},
};

use gudsl_render::pins::LayoutFile;

/// The sidecar of the model file at `model`.
pub fn path_for(model: &Path) -> PathBuf {
    let mut name = model.as_os_str().to_owned();
    name.push(".layout");
    PathBuf::from(name)
}

/// The sidecar at `path`: empty where there is none; `Err` says which file and why it is no
/// layout (it is then left as it is: never overwritten).
pub fn read(path: &Path) -> Result<LayoutFile, String> {
    match std::fs::read_to_string(path) {
        Ok(text) => LayoutFile::parse(&text).map_err(|e| format!("{}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(LayoutFile::default()),
        Err(e) => Err(format!("{}: {e}", path.display())),
    }
}

/// Writes `layout` to `path` (removes the file where no pin is left).
pub fn write(path: &Path, layout: &LayoutFile) -> Result<(), String> {
    let failed = |e: std::io::Error| format!("{}: {e}", path.display());
    if layout.diagrams.is_empty() {
        return match std::fs::remove_file(path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(failed(e)),
            _ => Ok(()),
        };
    }
    let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut file = tempfile::NamedTempFile::new_in(folder).map_err(failed)?;
    file.write_all(layout.to_json().as_bytes()).map_err(failed)?;
    file.persist(path).map_err(|e| failed(e.error))?;
    Ok(())
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
}
