//! Test fixtures for editor features: a workspace of files with `$0` marking the cursor.

use crate::{
    db::{RootDatabase, SourceFile, Workspace},
    syntax::TextSize,
};

/// The files as a workspace, and the cursor offset (`$0`, removed from the text).
pub(crate) fn with_cursor(files: &[(&str, &str)]) -> (RootDatabase, Workspace, Vec<SourceFile>, TextSize) {
    let db = RootDatabase::default();
    let mut cursor = None;
    let inputs: Vec<SourceFile> = files
        .iter()
        .map(|(path, text)| {
            if let Some(at) = text.find("$0") {
                cursor = Some(TextSize::from(at as u32));
            }
            SourceFile::new(&db, path.to_string(), text.replace("$0", ""))
        })
        .collect();
    let workspace = Workspace::new(&db, inputs.clone());
    (db, workspace, inputs, cursor.expect("a $0 cursor in one of the files"))
}
