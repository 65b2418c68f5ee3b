//! The bundled library: declarations every workspace has, shipped inside the binary and
//! read-only — the generator's attributes (`Generator.Attributes`), the GPGPU extension's
//! `OpenCL` interface with the OpenCL C built-ins (`OpenCL.GPU`, as the dissertation's listings
//! import it), the C++ framework types models use (`Framework.*`), and the ToF component
//! library (`ToF.*`: the sources, filters and sinks that `gudsl run` runs as pipelines).
//!
//! Library files are ordinary `SourceFile`s with paths under [`LIBRARY_PREFIX`] (a URI a client
//! can show as a read-only virtual document) and the highest salsa durability: they never
//! change, so no edit re-verifies what reads only them. A workspace type with the same simple
//! name as a library type is the one an unqualified name means (`Semantics::resolve`).

use salsa::Durability;

use crate::db::{Db, SourceFile};

/// The prefix of every library file's path: `gudsl:/lib/opencl.gudsl`.
pub const LIBRARY_PREFIX: &str = "gudsl:/lib/";

/// The library's files: path and text.
pub const LIBRARY: &[(&str, &str)] = &[
    ("gudsl:/lib/generator.gudsl", include_str!("../lib/generator.gudsl")),
    ("gudsl:/lib/opencl.gudsl", include_str!("../lib/opencl.gudsl")),
    ("gudsl:/lib/framework.gudsl", include_str!("../lib/framework.gudsl")),
    ("gudsl:/lib/tof.gudsl", include_str!("../lib/tof.gudsl")),
];

/// The interface every component class implements without saying so: `init()`, `process()`
/// and `cleanup()` (Sec. 11.3.5).
pub const COMPONENT_BASE: &str = "Framework.CBSE.Component";

/// The interface a GPU class implements, with the OpenCL built-ins (Listing 14).
pub const OPENCL_INTERFACE: &str = "OpenCL.GPU.OpenCL";

/// Whether a file path names a library file.
pub fn is_library_path(path: &str) -> bool {
    path.starts_with(LIBRARY_PREFIX)
}

/// Whether `file` is a library file.
pub fn is_library(db: &dyn Db, file: SourceFile) -> bool {
    is_library_path(file.path(db))
}

/// New inputs for the library's files, in [`LIBRARY`] order (a workspace lists them first).
pub fn library_files(db: &dyn Db) -> Vec<SourceFile> {
    LIBRARY
        .iter()
        .map(|(path, text)| {
            SourceFile::builder(path.to_string(), text.to_string()).durability(Durability::HIGH).new(db)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use crate::{analysis::InvalidEdit, AnalysisHost, LineColEdit};

    #[test]
    fn the_library_checks_clean_on_its_own() {
        let host = AnalysisHost::default();
        let analysis = host.analysis();
        assert_eq!(host.library_files().len(), super::LIBRARY.len());
        for &file in host.library_files() {
            let (diagnostics, _) = analysis.diagnostics(file).unwrap();
            assert!(diagnostics.is_empty(), "{}: {diagnostics:#?}", analysis.file_path(file));
        }
    }

    #[test]
    fn library_files_are_read_only() {
        let mut host = AnalysisHost::default();
        let file = host.library_files()[1];
        let before = host.file_text(file).to_string();
        let edit = LineColEdit { range: None, text: "garbage".into() };
        let refused = host.edit_file(file, vec![edit], crate::text::ColumnUnit::Utf8);
        assert_eq!(refused, Err(InvalidEdit::ReadOnly { path: "gudsl:/lib/opencl.gudsl".into() }));
        host.set_file_text(file, "garbage".into());
        assert_eq!(host.file_text(file), before);
    }
}
