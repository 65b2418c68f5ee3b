//! Test fixtures for editor features: a workspace of files with `$0` marking the cursor, and
//! a text with an answer's edits made.

use crate::{
    db::{RootDatabase, SourceFile, Workspace},
    syntax::{TextRange, TextSize},
};

/// `text` with `edits` made, each range one of `text` as it is (the last first, so the others
/// stay where they are).
pub(crate) fn with_edits<'a>(text: &str, edits: impl IntoIterator<Item = (TextRange, &'a str)>) -> String {
    let mut edits: Vec<(TextRange, &str)> = edits.into_iter().collect();
    edits.sort_by_key(|(range, _)| std::cmp::Reverse(range.start()));
    let mut text = text.to_string();
    for (range, new) in edits {
        text.replace_range(std::ops::Range::<usize>::from(range), new);
    }
    text
}

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
