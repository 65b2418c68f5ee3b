//! `gudsl/applyGraphEdit` (`docs/protocol.md`): operations on a diagram's graph at a document
//! version. The model's operations (create, delete, rename, connect, reconnect, setProperty)
//! are answered with the text edits that make them, for the client to apply; `move` and
//! `resize` change only positions, written at once into the document's layout sidecar.

use std::sync::Mutex;

use gudsl_model::{
    graph::EdgeKind,
    ide::{GraphOp, NewKind},
    Cancellable, FileId,
};
use gudsl_render::pins::{self, Pin};
use tower_lsp_server::ls_types as lsp;

use super::{
    ext::{GraphEditAnswer, GraphEditParams, LayoutWritten, Operation, Position, Size},
    from_proto,
    graph::version,
    host::Snapshot,
    scenes::SceneCache,
    to_proto,
};
use crate::layout_file;

/// An operation as made: on the text, or on the positions.
enum Planned {
    Text(GraphOp),
    Layout { element: String, change: LayoutChange },
}

enum LayoutChange {
    Move(Option<Position>),
    Resize(Option<Size>),
}

impl Operation {
    fn plan(&self, k: usize) -> Result<Planned, String> {
        let missing = |op: &str, what: &str| format!("operation {k}: `{op}` needs `{what}` (or `null`)");
        Ok(Planned::Text(match self {
            Operation::Create { kind, name, parent, properties } => GraphOp::Create {
                kind: NewKind::from_name(kind).ok_or_else(|| {
                    let kinds: Vec<&str> = NewKind::all().map(|(_, n)| n).collect();
                    format!("operation {k}: `{kind}` is no kind of element (kinds: {})", kinds.join(", "))
                })?,
                name: name.clone(),
                parent: parent.clone(),
                properties: properties.clone(),
            },
            Operation::Delete { element } => GraphOp::Delete { element: element.clone() },
            Operation::Rename { element, name } => GraphOp::Rename { element: element.clone(), name: name.clone() },
            Operation::Connect { kind, source, target, properties } => GraphOp::Connect {
                kind: EdgeKind::from_name(kind).ok_or_else(|| {
                    let kinds: Vec<&str> = EdgeKind::ALL.iter().map(|e| e.name()).collect();
                    format!("operation {k}: `{kind}` is no kind of edge (kinds: {})", kinds.join(", "))
                })?,
                source: source.clone(),
                target: target.clone(),
                properties: properties.clone(),
            },
            Operation::Reconnect { edge, source, target } => {
                GraphOp::Reconnect { edge: edge.clone(), source: source.clone(), target: target.clone() }
            }
            Operation::SetProperty { element, property, value } => {
                GraphOp::SetProperty { element: element.clone(), property: property.clone(), value: value.clone() }
            }
            Operation::Move { element, position } => {
                let position = position.ok_or_else(|| missing("move", "position"))?;
                return Ok(Planned::Layout { element: element.clone(), change: LayoutChange::Move(position) });
            }
            Operation::Resize { element, size } => {
                let size = size.ok_or_else(|| missing("resize", "size"))?;
                return Ok(Planned::Layout { element: element.clone(), change: LayoutChange::Resize(size) });
            }
        }))
    }
}

/// `gudsl/applyGraphEdit`: the operations as text edits, and the positions written; `Err` with
/// the reason when they cannot be made (a stale version, an unknown element, a name that is no
/// name, a node moved off the canvas' range): nothing changes.
pub fn apply_graph_edit(
    snap: &Snapshot,
    params: &GraphEditParams,
    scenes: &SceneCache,
) -> Cancellable<Result<GraphEditAnswer, String>> {
    let uri = &params.text_document.uri;
    let Some(file) = snap.file(uri) else {
        return Ok(Err(format!("{} is not a document of the workspace", uri.as_str())));
    };
    if snap.is_library(uri) {
        return Ok(Err(format!("{} is part of gudsl's bundled library, which is read-only", uri.as_str())));
    }
    let current = version(snap, uri);
    if params.text_document.version != current {
        let what = |v: Option<i32>| v.map_or_else(|| "no version (not open)".to_string(), |v| format!("version {v}"));
        return Ok(Err(format!(
            "the edit is for {} of {}, the server has {}: ask for the graph again and redo the edit on it",
            what(params.text_document.version),
            uri.as_str(),
            what(current)
        )));
    }
    let planned: Result<Vec<Planned>, String> =
        params.operations.iter().enumerate().map(|(k, op)| op.plan(k)).collect();
    let planned = match planned {
        Ok(planned) => planned,
        Err(reason) => return Ok(Err(reason)),
    };
    let (mut text_ops, mut layout_ops) = (Vec::new(), Vec::new());
    for op in planned {
        match op {
            Planned::Text(op) => text_ops.push(op),
            Planned::Layout { element, change } => layout_ops.push((element, change)),
        }
    }
    let edit = if text_ops.is_empty() {
        lsp::WorkspaceEdit::default()
    } else {
        match snap.analysis.graph_edit(file, &params.diagram, &text_ops)? {
            Ok(edits) => to_proto::workspace_edit(snap, edits)?,
            Err(refused) => return Ok(Err(refused.0)),
        }
    };
    let layout = match layout_ops.is_empty() {
        true => None,
        false => match save_positions(snap, file, uri, &params.diagram, &layout_ops, scenes)? {
            Ok(written) => Some(written),
            Err(reason) => return Ok(Err(reason)),
        },
    };
    Ok(Ok(GraphEditAnswer { edit, layout }))
}

/// One sidecar change at a time: two moves at once would each write the file as read.
static SIDECAR: Mutex<()> = Mutex::new(());

/// Moves and resizes written into the document's layout sidecar (pins of nodes that no longer
/// exist dropped); `Err` with the reason, and the file untouched, when one cannot be made.
/// The layout sidecar of the model file at `uri`, where the server may write it: beside a
/// file (not an unsaved document) inside the workspace folders.
fn sidecar_of(snap: &Snapshot, uri: &lsp::Uri) -> Result<std::path::PathBuf, String> {
    let Some(model) = from_proto::file_path(uri) else {
        return Err(format!(
            "positions are kept in a layout file beside the model file, and {} is no file: save it first",
            uri.as_str()
        ));
    };
    if !snap.preparations.access().may_write_beside(&model) {
        return Err(format!(
            "{} lies outside the workspace folders: positions are saved only beside models inside them",
            model.display()
        ));
    }
    Ok(layout_file::path_for(&model))
}

/// On saving the model file at `uri`: the rows of its diagrams drawn (what their next fresh
/// layouts keep) written into its sidecar where they changed; nothing where none was drawn.
pub fn remember_rows(snap: &Snapshot, uri: &lsp::Uri, scenes: &SceneCache) -> Result<(), String> {
    let Some(file) = snap.file(uri) else { return Ok(()) };
    let drawn = scenes.rows_of(file);
    if drawn.is_empty() {
        return Ok(());
    }
    let sidecar = sidecar_of(snap, uri)?;
    let _one_at_a_time = SIDECAR.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    layout_file::remember(&sidecar, drawn).map(|_| ())
}

fn save_positions(
    snap: &Snapshot,
    file: FileId,
    uri: &lsp::Uri,
    diagram: &str,
    ops: &[(String, LayoutChange)],
    scenes: &SceneCache,
) -> Cancellable<Result<LayoutWritten, String>> {
    let sidecar = match sidecar_of(snap, uri) {
        Ok(sidecar) => sidecar,
        Err(error) => return Ok(Err(error)),
    };
    let _one_at_a_time = SIDECAR.lock().unwrap_or_else(|poisoned| poisoned.into_inner());
    let mut layout = match layout_file::read(&sidecar) {
        Ok(layout) => layout,
        Err(error) => return Ok(Err(format!("{error}: fix or delete it (it is not overwritten)"))),
    };
    let graphs = snap.analysis.graphs(file)?;
    let Some(graph) = graphs.iter().find(|g| g.id == diagram) else {
        return Ok(Err(format!("{} declares no diagram `{diagram}`", uri.as_str())));
    };
    // Where the client sees each node now.
    let scene = scenes.scene(file, &scenes.as_drawn(graph), (layout.pins(diagram), layout.rows(diagram)), false, None);
    let pins = layout.diagrams.entry(diagram.to_string()).or_default();
    for (k, (element, change)) in ops.iter().enumerate() {
        let Some(node) = scene.nodes.iter().find(|n| &n.id == element) else {
            return Ok(Err(format!(
                "operation {k}: `{element}` is no node of `{diagram}` (only nodes move and resize)"
            )));
        };
        if let (Some(parent), LayoutChange::Move(Some(_))) = (&node.parent, change) {
            return Ok(Err(format!(
                "operation {k}: `{element}` is nested in `{parent}` and moves with it: move `{parent}` instead"
            )));
        }
        let drawn = node.rect;
        let here = Pin { x: pins::rounded(drawn.x), y: pins::rounded(drawn.y), width: None, height: None };
        match *change {
            LayoutChange::Move(None) => {
                pins.remove(element);
            }
            LayoutChange::Move(Some(p)) => {
                // A node dragged past the top or left edge stops there.
                let pin = pins.entry(element.clone()).or_insert(here);
                (pin.x, pin.y) = (pins::rounded(p.x.max(0.0)), pins::rounded(p.y.max(0.0)));
            }
            LayoutChange::Resize(None) => {
                if let Some(pin) = pins.get_mut(element) {
                    (pin.width, pin.height) = (None, None);
                }
            }
            LayoutChange::Resize(Some(size)) => {
                let pin = pins.entry(element.clone()).or_insert(here);
                (pin.width, pin.height) = (Some(pins::rounded(size.width)), Some(pins::rounded(size.height)));
            }
        }
        if let Some(pin) = pins.get(element).filter(|pin| !pins::valid(pin)) {
            return Ok(Err(format!(
                "operation {k}: {element} cannot be at ({}, {}) with size {:?}: coordinates go from 0 to a million points, sizes above 0",
                pin.x,
                pin.y,
                pin.size()
            )));
        }
    }
    // Pins of nodes gone go, and rows forget nodes and edges gone.
    let exists = |g: &gudsl_model::graph::Graph, id: &str| {
        g.nodes.iter().any(|n| n.id == id) || g.edges.iter().any(|e| e.id == id)
    };
    layout.retain(|d, id| graphs.iter().any(|g| g.id == d && exists(g, id)));
    if let Err(error) = layout_file::write(&sidecar, &layout) {
        return Ok(Err(format!("the positions were not saved: {error}")));
    }
    let Some(uri) = lsp::Uri::from_file_path(&sidecar) else {
        return Ok(Err(format!("{} has no URI", sidecar.display())));
    };
    Ok(Ok(LayoutWritten { uri, diagram: diagram.to_string() }))
}
