//! Graph edits as text edits (the graph view's `gudsl/applyGraphEdit`): operations on a
//! diagram's graph, naming its elements by the ids of `graph/`, answered with the edits of the
//! text that make them, through the same machinery as the text's own requests (a rename is
//! [`rename`]), so the text stays the one truth and the graph follows it.

use crate::{
    ast::{self, AstNode},
    db::{parse, Db, SourceFile, Workspace},
    graph::file_graphs,
    syntax::TextRange,
};

use super::{rename, FileRange};

/// One operation on a diagram's graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GraphOp {
    /// Renames a node (a class, an interface, an enum, an activity node, a component instance)
    /// and every reference to it, across files.
    Rename { element: String, name: String },
}

/// Why a batch of operations cannot be made: nothing is changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GraphEditError(pub String);

/// The text edits that make `ops` on the diagram `diagram` of `file`, all computed on the
/// text as it is (a batch whose operations would edit the same text is refused).
pub fn graph_edit(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    diagram: &str,
    ops: &[GraphOp],
) -> Result<Vec<(FileRange, String)>, GraphEditError> {
    let graphs = file_graphs(db, workspace, file);
    let Some(graph) = graphs.iter().find(|g| g.id == diagram) else {
        let known: Vec<&str> = graphs.iter().map(|g| g.id.as_str()).collect();
        let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
        return Err(GraphEditError(format!(
            "{} declares no diagram `{diagram}` (it declares: {known})",
            file.path(db)
        )));
    };
    let mut edits: Vec<(usize, FileRange, String)> = Vec::new();
    for (k, op) in ops.iter().enumerate() {
        let made = match op {
            GraphOp::Rename { element, name } => {
                let Some(node) = graph.nodes.iter().find(|n| &n.id == element) else {
                    return Err(GraphEditError(format!("operation {k}: `{diagram}` has no node `{element}`")));
                };
                let Some(at) = declared_name(db, file, node.range) else {
                    return Err(GraphEditError(format!(
                        "operation {k}: `{element}` is not declared in this file: rename it where it is"
                    )));
                };
                rename(db, workspace, file, at.start(), name)
                    .map_err(|e| GraphEditError(format!("operation {k}: {}", e.0)))?
            }
        };
        for (range, text) in made {
            if let Some((j, _, _)) =
                edits.iter().find(|(_, r, _)| r.file == range.file && overlap(r.range, range.range))
            {
                if *j != k {
                    return Err(GraphEditError(format!(
                        "operations {j} and {k} edit the same text: send them in separate batches"
                    )));
                }
                continue; // a reference reached twice
            }
            edits.push((k, range, text));
        }
    }
    Ok(edits.into_iter().map(|(_, range, text)| (range, text)).collect())
}

/// The name of the declaration at `range` of `file` (a node's range).
fn declared_name(db: &dyn Db, file: SourceFile, range: TextRange) -> Option<TextRange> {
    if range.is_empty() {
        return None; // drawn for an edge that leaves the diagram: declared elsewhere
    }
    let root = parse(db, file).syntax_node();
    let declaration = root.covering_element(range).into_node()?;
    let declaration = declaration.ancestors().find(|n| n.text_range() == range)?;
    declaration.children().find_map(ast::Name::cast).map(|name| name.syntax().text_range())
}

fn overlap(a: TextRange, b: TextRange) -> bool {
    a.start() < b.end() && b.start() < a.end() || a == b
}

#[cfg(test)]
mod tests;
