//! Where names are written: per file, the segments of every qualified name by their text; per
//! workspace, the files that write each name. Find references and rename read these instead of
//! walking every file's tree, so they resolve only the places spelled like the declaration.

use std::collections::{BTreeSet, HashMap};

use crate::{
    ast::{self, AstNode},
    db::{parse, Db, SourceFile, Workspace},
    syntax::TextRange,
};

/// The ranges of the path segments of one file, by the segment's text, in order.
#[salsa::tracked(returns(ref))]
pub fn file_name_uses(db: &dyn Db, file: SourceFile) -> HashMap<String, Vec<TextRange>> {
    let mut uses: HashMap<String, Vec<TextRange>> = HashMap::new();
    for path in parse(db, file).syntax_node().descendants().filter_map(ast::Path::cast) {
        for segment in path.segments() {
            uses.entry(segment.text()).or_default().push(segment.syntax().text_range());
        }
    }
    uses
}

/// The names one file writes in paths: equal, so backdated, unless a name is added or removed
/// (typing that only moves names does not rebuild the workspace's index).
#[salsa::tracked(returns(ref))]
pub fn file_names_used(db: &dyn Db, file: SourceFile) -> BTreeSet<String> {
    file_name_uses(db, file).keys().cloned().collect()
}

/// The files that write each name in a path, in workspace order.
#[salsa::tracked(returns(ref))]
pub fn name_index(db: &dyn Db, workspace: Workspace) -> HashMap<String, Vec<SourceFile>> {
    let mut index: HashMap<String, Vec<SourceFile>> = HashMap::new();
    for &file in workspace.files(db) {
        for name in file_names_used(db, file) {
            index.entry(name.clone()).or_default().push(file);
        }
    }
    index
}

/// Every path segment of the workspace spelled `name`: its file and range.
pub fn segments_named(db: &dyn Db, workspace: Workspace, name: &str) -> Vec<(SourceFile, TextRange)> {
    let files = name_index(db, workspace).get(name).map_or(&[][..], |files| files.as_slice());
    files
        .iter()
        .flat_map(|&file| {
            let ranges = file_name_uses(db, file).get(name).map_or(&[][..], |r| r.as_slice());
            ranges.iter().map(move |&range| (file, range))
        })
        .collect()
}
