//! The graph view over LSP (`docs/protocol.md`): `gudsl/diagrams` lists a document's diagrams,
//! `gudsl/graph` gives one as a graph — the model's nodes, edges and groups with their stable
//! ids and source ranges, the renderer's geometry for each (boxes, edge routes, lanes), the
//! document version it describes, and the SVG of the same scene when asked;
//! `gudsl/applyGraphEdit` answers operations on a graph with the text edits that make them.

use std::{
    collections::HashMap,
    sync::{Arc, Mutex},
};

use gudsl_model::{
    graph::{EdgeEnd, EdgeKind, Graph, GraphKind},
    ide::{GraphOp, NewKind, Properties},
    syntax::TextRange,
    text::LineIndex,
    Cancellable, FileId,
};
use gudsl_render::scene::{self, Rect, Scene};
use serde::{Deserialize, Serialize};
use tower_lsp_server::ls_types as lsp;

use super::{host::Snapshot, to_proto};

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct DiagramsParams {
    pub text_document: lsp::TextDocumentIdentifier,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Diagrams {
    pub uri: lsp::Uri,
    /// The document version the list describes (`null` for a file the editor has not open).
    pub version: Option<i32>,
    pub diagrams: Vec<DiagramInfo>,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct DiagramInfo {
    /// The diagram's fully qualified name: what `gudsl/graph` takes.
    pub id: String,
    pub name: String,
    pub kind: String,
    /// The whole declaration, and its name (where to put the cursor).
    pub range: lsp::Range,
    pub selection_range: lsp::Range,
}

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphParams {
    pub text_document: lsp::TextDocumentIdentifier,
    /// A diagram's id, as `gudsl/diagrams` lists it.
    pub diagram: String,
    /// Whether to add the SVG of the scene.
    #[serde(default)]
    pub svg: bool,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphView {
    pub uri: lsp::Uri,
    pub version: Option<i32>,
    pub diagram: DiagramInfo,
    /// The scene's size; coordinates are in points, x to the right, y down.
    pub width: f64,
    pub height: f64,
    pub nodes: Vec<NodeView>,
    pub edges: Vec<EdgeView>,
    pub groups: Vec<GroupView>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub svg: Option<String>,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct NodeView {
    pub id: String,
    pub shape: String,
    pub label: String,
    pub stereotype: Option<String>,
    pub is_abstract: bool,
    pub compartments: Vec<CompartmentView>,
    pub ports: Vec<PortView>,
    pub group: Option<String>,
    pub range: lsp::Range,
    pub bounds: Option<Bounds>,
}

#[derive(Debug, Serialize)]
pub struct CompartmentView {
    pub title: Option<String>,
    pub lines: Vec<String>,
    /// The id of the element each line shows (a field, a method, …), `""` for a plain line.
    pub ids: Vec<String>,
}

#[derive(Debug, Serialize)]
pub struct PortView {
    pub id: String,
    pub label: String,
    /// `true` a provider (lollipop), `false` a processor (socket), `null` a port instance.
    pub provider: Option<bool>,
    /// Where connections meet it (just outside its symbol, right of the node's box).
    pub anchor: Option<Point>,
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct EdgeView {
    pub id: String,
    pub kind: String,
    pub source: EndView,
    pub target: EndView,
    pub label: Option<String>,
    pub source_label: Option<String>,
    pub target_label: Option<String>,
    /// The text that states it.
    pub range: lsp::Range,
    /// The route, source to target; empty where an end is not in the diagram.
    pub points: Vec<Point>,
    pub label_bounds: Option<Bounds>,
}

#[derive(Debug, Serialize)]
pub struct EndView {
    pub node: String,
    pub port: Option<String>,
}

#[derive(Debug, Serialize)]
pub struct GroupView {
    pub id: String,
    pub label: String,
    pub owner: Option<String>,
    pub bounds: Option<Bounds>,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Bounds {
    pub x: f64,
    pub y: f64,
    pub width: f64,
    pub height: f64,
}

#[derive(Debug, Clone, Copy, Serialize)]
pub struct Point {
    pub x: f64,
    pub y: f64,
}

impl From<Rect> for Bounds {
    fn from(r: Rect) -> Bounds {
        Bounds { x: r.x, y: r.y, width: r.width, height: r.height }
    }
}

/// `gudsl/diagrams`: the diagrams of a document in the order declared; `None` for a document
/// the server does not know.
pub fn diagrams(snap: &Snapshot, params: &DiagramsParams) -> Cancellable<Option<Diagrams>> {
    let uri = &params.text_document.uri;
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let diagrams = snap.analysis.graphs(file)?.iter().map(|graph| info(index, graph, snap)).collect();
    Ok(Some(Diagrams { uri: uri.clone(), version: version(snap, uri), diagrams }))
}

#[derive(Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphEditParams {
    /// The document and the version the client's graph describes: an edit against another
    /// version is refused.
    pub text_document: lsp::OptionalVersionedTextDocumentIdentifier,
    pub diagram: String,
    pub operations: Vec<Operation>,
}

/// One operation of `gudsl/applyGraphEdit`, named by `op`.
#[derive(Debug, Deserialize)]
#[serde(tag = "op", rename_all = "camelCase")]
pub enum Operation {
    /// A new node, member, port, connector or port instance (`kind`: `class`, `field`, `action`,
    /// `loopWindow`, `portInstance`, …), into `parent` (a class, swimlane, component, instance).
    #[serde(rename_all = "camelCase")]
    Create {
        kind: String,
        name: String,
        parent: Option<String>,
        #[serde(default)]
        properties: Properties,
    },
    /// An element and what dangles without it.
    Delete { element: String },
    /// A node and every reference to it, across files.
    Rename { element: String, name: String },
    /// A new edge (`kind`: `transition`, `generalization`, `realization`, `association`,
    /// `aggregation`, `composition`, `connection`, `binding`).
    Connect {
        kind: String,
        source: String,
        target: String,
        #[serde(default)]
        properties: Properties,
    },
    /// An edge's new source or target.
    Reconnect { edge: String, source: Option<String>, target: Option<String> },
    /// A property's new value; `null` removes it.
    #[serde(rename_all = "camelCase")]
    SetProperty { element: String, property: String, value: Option<String> },
}

impl Operation {
    fn to_op(&self, k: usize) -> Result<GraphOp, String> {
        Ok(match self {
            Operation::Create { kind, name, parent, properties } => GraphOp::Create {
                kind: NewKind::from_name(kind).ok_or_else(|| {
                    let kinds: Vec<&str> = NewKind::ALL.iter().map(|(_, n)| *n).collect();
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
        })
    }
}

#[derive(Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct GraphEditAnswer {
    /// The text edits that make the operations, for the client to apply.
    pub edit: lsp::WorkspaceEdit,
}

/// `gudsl/applyGraphEdit`: the operations as text edits; `Err` with the reason when they cannot
/// be made (a stale version, an unknown element, a name that is no name): nothing changes.
pub fn apply_graph_edit(snap: &Snapshot, params: &GraphEditParams) -> Cancellable<Result<GraphEditAnswer, String>> {
    let uri = &params.text_document.uri;
    let Some(file) = snap.file(uri) else {
        return Ok(Err(format!("{} is not a document of the workspace", uri.as_str())));
    };
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
    let ops: Result<Vec<GraphOp>, String> = params.operations.iter().enumerate().map(|(k, op)| op.to_op(k)).collect();
    let ops = match ops {
        Ok(ops) => ops,
        Err(reason) => return Ok(Err(reason)),
    };
    Ok(match snap.analysis.graph_edit(file, &params.diagram, &ops)? {
        Ok(edits) => Ok(GraphEditAnswer { edit: to_proto::workspace_edit(snap, edits)? }),
        Err(refused) => Err(refused.0),
    })
}

/// The scenes last laid out, by document and diagram: a diagram asked for again with nothing
/// drawn changed (its graph equal but for source ranges: an edit above it moves those) is not
/// laid out again. The layered layout of a 200-node activity diagram takes about 40 ms.
#[derive(Default)]
pub struct SceneCache(Mutex<Scenes>);

/// By document and diagram id: the graph as drawn (ranges cleared) and its scene.
type Scenes = HashMap<(FileId, String), (Graph, Arc<Scene>)>;

/// Diagrams whose scenes are kept; past it the cache starts again.
const CACHED_SCENES: usize = 64;

impl SceneCache {
    fn scene(&self, file: FileId, graph: &Graph) -> Arc<Scene> {
        let drawn = without_ranges(graph);
        let key = (file, graph.id.clone());
        let cached = self.lock().get(&key).filter(|(was, _)| *was == drawn).map(|(_, scene)| scene.clone());
        if let Some(scene) = cached {
            return scene;
        }
        let scene = Arc::new(scene::build(graph));
        let mut scenes = self.lock();
        if scenes.len() >= CACHED_SCENES {
            scenes.clear();
        }
        scenes.insert(key, (drawn, scene.clone()));
        scene
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Scenes> {
        self.0.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }
}

/// `graph` as drawn: its source ranges cleared.
fn without_ranges(graph: &Graph) -> Graph {
    let mut drawn = graph.clone();
    (drawn.range, drawn.name_range) = (TextRange::default(), None);
    for node in &mut drawn.nodes {
        node.range = TextRange::default();
    }
    for edge in &mut drawn.edges {
        edge.range = TextRange::default();
    }
    drawn
}

/// `gudsl/graph`: the diagram `params.diagram` of a document, laid out (or as `scenes` keeps
/// it); `Err` with the reason when the document or the diagram is unknown.
pub fn graph(snap: &Snapshot, params: &GraphParams, scenes: &SceneCache) -> Cancellable<Result<GraphView, String>> {
    let uri = &params.text_document.uri;
    let Some(file) = snap.file(uri) else {
        return Ok(Err(format!("{} is not a document of the workspace", uri.as_str())));
    };
    let index = snap.analysis.line_index(file)?;
    let graphs = snap.analysis.graphs(file)?;
    let Some(graph) = graphs.iter().find(|g| g.id == params.diagram) else {
        let known: Vec<&str> = graphs.iter().map(|g| g.id.as_str()).collect();
        return Ok(Err(format!(
            "{} declares no diagram `{}` (it declares: {})",
            uri.as_str(),
            params.diagram,
            if known.is_empty() { "none".to_string() } else { known.join(", ") }
        )));
    };
    let scene = scenes.scene(file, graph);
    snap.analysis.check_cancelled()?;
    Ok(Ok(view(snap, index, graph, &scene, params.svg, version(snap, uri), uri)))
}

fn version(snap: &Snapshot, uri: &lsp::Uri) -> Option<i32> {
    snap.document(uri).and_then(|d| d.version)
}

fn info(index: &LineIndex, graph: &Graph, snap: &Snapshot) -> DiagramInfo {
    let range = to_proto::range(index, graph.range, snap.encoding);
    DiagramInfo {
        id: graph.id.clone(),
        name: graph.id.rsplit('.').next().unwrap_or(&graph.id).to_string(),
        kind: match graph.kind {
            GraphKind::Class => "class",
            GraphKind::Activity => "activity",
            GraphKind::Component => "component",
            GraphKind::ComponentInstance => "componentInstance",
        }
        .to_string(),
        range,
        selection_range: graph.name_range.map_or(range, |r| to_proto::range(index, r, snap.encoding)),
    }
}

/// The graph with the scene's geometry, by id.
fn view(
    snap: &Snapshot,
    index: &LineIndex,
    graph: &Graph,
    scene: &Scene,
    svg: bool,
    version: Option<i32>,
    uri: &lsp::Uri,
) -> GraphView {
    let boxes: HashMap<&str, Rect> = scene.nodes.iter().map(|n| (n.id.as_str(), n.rect)).collect();
    let anchors: HashMap<&str, Point> = scene
        .nodes
        .iter()
        .flat_map(|n| &n.ports)
        .map(|p| (p.id.as_str(), Point { x: p.anchor.x, y: p.anchor.y }))
        .collect();
    let lanes: HashMap<&str, Rect> = scene.lanes.iter().map(|l| (l.id.as_str(), l.rect)).collect();
    let routes: HashMap<&str, &scene::SceneEdge> = scene.edges.iter().map(|e| (e.id.as_str(), e)).collect();
    let end = |end: &EdgeEnd| EndView { node: end.node.clone(), port: end.port.clone() };
    GraphView {
        uri: uri.clone(),
        version,
        diagram: info(index, graph, snap),
        width: scene.width,
        height: scene.height,
        nodes: graph
            .nodes
            .iter()
            .map(|node| NodeView {
                id: node.id.clone(),
                shape: lower_camel(&format!("{:?}", node.shape)),
                label: node.label.clone(),
                stereotype: node.stereotype.clone(),
                is_abstract: node.is_abstract,
                compartments: node
                    .compartments
                    .iter()
                    .map(|c| CompartmentView { title: c.title.clone(), lines: c.lines.clone(), ids: c.ids.clone() })
                    .collect(),
                ports: node
                    .ports
                    .iter()
                    .map(|p| PortView {
                        id: p.id.clone(),
                        label: p.label.clone(),
                        provider: p.provider,
                        anchor: anchors.get(p.id.as_str()).copied(),
                    })
                    .collect(),
                group: node.group.clone(),
                range: to_proto::range(index, node.range, snap.encoding),
                bounds: boxes.get(node.id.as_str()).map(|&r| r.into()),
            })
            .collect(),
        edges: graph
            .edges
            .iter()
            .map(|edge| {
                let routed = routes.get(edge.id.as_str());
                EdgeView {
                    id: edge.id.clone(),
                    kind: edge.kind.name().to_string(),
                    source: end(&edge.source),
                    target: end(&edge.target),
                    label: edge.label.clone(),
                    source_label: edge.source_label.clone(),
                    target_label: edge.target_label.clone(),
                    range: to_proto::range(index, edge.range, snap.encoding),
                    points: routed.map_or_else(Vec::new, |e| bends(&e.points)),
                    label_bounds: routed.and_then(|e| e.label.as_ref()).map(|l| l.rect.into()),
                }
            })
            .collect(),
        groups: graph
            .groups
            .iter()
            .map(|g| GroupView {
                id: g.id.clone(),
                label: g.label.clone(),
                owner: g.owner.clone(),
                bounds: lanes.get(g.id.as_str()).map(|&r| r.into()),
            })
            .collect(),
        svg: svg.then(|| gudsl_render::svg::write(scene)),
    }
}

/// A route's ends and the points where it turns: a point on the straight line between its
/// neighbours says nothing (a long edge's route passes every layer it crosses: up to hundreds
/// of such points in a 200-node activity diagram).
fn bends(route: &[scene::Point]) -> Vec<Point> {
    let mut kept: Vec<Point> = Vec::with_capacity(route.len());
    for (k, p) in route.iter().enumerate() {
        if let (Some(&before), Some(after)) = (kept.last(), route.get(k + 1)) {
            let cross = (p.x - before.x) * (after.y - p.y) - (p.y - before.y) * (after.x - p.x);
            let ahead = (p.x - before.x) * (after.x - p.x) + (p.y - before.y) * (after.y - p.y) >= 0.0;
            if cross.abs() < 1e-6 && ahead {
                continue;
            }
        }
        kept.push(Point { x: p.x, y: p.y });
    }
    kept
}

/// `LoopWindow` → `loopWindow`.
fn lower_camel(name: &str) -> String {
    let mut chars = name.chars();
    chars.next().map(|c| c.to_ascii_lowercase().to_string() + chars.as_str()).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use gudsl_model::AnalysisHost;

    use super::*;

    #[test]
    fn a_scene_is_laid_out_again_only_when_what_is_drawn_changes() {
        let text = "ClassDiagram Shapes\n{\n    public class Shape { }\n    public class Circle extends Shape { }\n}\n";
        let (mut host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), text.to_string())]);
        let cache = SceneCache::default();
        let scene = |host: &AnalysisHost| cache.scene(files[0], &host.analysis().graphs(files[0]).unwrap()[0]);
        let first = scene(&host);
        // Text above the diagram moves its ranges, not what is drawn.
        host.set_file_text(files[0], format!("// shapes\n\n{text}"));
        assert!(Arc::ptr_eq(&first, &scene(&host)), "laid out again for a comment");
        let grown = text
            .replace("    public class Circle", "    public class Square extends Shape { }\n    public class Circle");
        host.set_file_text(files[0], grown);
        let second = scene(&host);
        assert!(!Arc::ptr_eq(&first, &second));
        assert_eq!(second.nodes.len(), 3);
    }
}
