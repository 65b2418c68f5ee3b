//! The graph view over LSP (`docs/protocol.md`): `gudsl/diagrams` lists a document's diagrams,
//! `gudsl/graph` gives one as a graph — the model's nodes, edges and groups with their stable
//! ids and source ranges, the renderer's geometry for each (boxes, edge routes, lanes), the
//! document version it describes, which nodes are pinned, and the SVG of the same scene when
//! asked. Scenes come from `scenes` (laid out around the pins and the scene drawn before).

use std::collections::HashMap;

use base64::Engine as _;

use gudsl_model::{
    graph::{EdgeEnd, Graph, GraphKind},
    text::LineIndex,
    Cancellable,
};
use gudsl_render::{
    layout::Page,
    pins::Pins,
    scene::{self, Rect, Scene},
};
use tower_lsp_server::ls_types as lsp;

use super::{
    ext::{
        CompartmentView, ControlView, DiagramInfo, Diagrams, DiagramsParams, EdgeView, EndView, GraphParams, GraphView,
        GroupView, NodeView, Point, PortView,
    },
    host::Snapshot,
    scenes::{layout_of, SceneCache},
    to_proto,
};

/// `gudsl/diagrams`: the diagrams of a document in the order declared; `None` for a document
/// the server does not know.
pub fn diagrams(snap: &Snapshot, params: &DiagramsParams) -> Cancellable<Option<Diagrams>> {
    let uri = &params.text_document.uri;
    let Some(file) = snap.file(uri) else { return Ok(None) };
    let index = snap.analysis.line_index(file)?;
    let diagrams = snap.analysis.graphs(file)?.iter().map(|graph| info(index, graph, snap)).collect();
    Ok(Some(Diagrams { uri: uri.clone(), version: version(snap, uri), diagrams }))
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
    let (layout, layout_error) = match layout_of(uri) {
        Ok(layout) => (layout, None),
        Err(error) => (Default::default(), Some(error)),
    };
    let pins = layout.pins(&graph.id);
    let graph = &scenes.as_drawn(graph);
    let page = params.page.as_ref().and_then(|p| Page::of_size(p.width, p.height));
    let scene = scenes.scene(file, graph, (pins, layout.rows(&graph.id)), params.relayout, page);
    snap.analysis.check_cancelled()?;
    let mut view = view(snap, index, graph, &scene, pins, version(snap, uri), uri);
    if params.svg || params.png {
        let svg = gudsl_render::svg::write(&scene);
        if params.png {
            match gudsl_render::png::to_png(&svg, gudsl_render::png::EXPORT_SCALE) {
                Ok(png) => view.png = Some(base64::engine::general_purpose::STANDARD.encode(png)),
                Err(error) => return Ok(Err(format!("`{}` cannot be drawn as PNG: {error}", params.diagram))),
            }
        }
        view.svg = params.svg.then_some(svg);
    }
    view.layout_error = layout_error;
    Ok(Ok(view))
}

pub(super) fn version(snap: &Snapshot, uri: &lsp::Uri) -> Option<i32> {
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
    pins: Option<&Pins>,
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
                    .map(|c| CompartmentView {
                        title: c.title.clone(),
                        lines: c.lines.clone(),
                        ids: c.ids.clone(),
                        statics: c.statics.clone(),
                    })
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
                parent: node.parent.clone(),
                range: to_proto::range(index, node.range, snap.encoding),
                bounds: boxes.get(node.id.as_str()).map(|&r| r.into()),
                pinned: pins.is_some_and(|p| p.contains_key(&node.id)),
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
                    points: routed.map_or_else(Vec::new, |e| bends(&through_controls(e, &routes, &boxes))),
                    label_bounds: routed.and_then(|e| e.label.as_ref()).map(|l| l.rect.into()),
                    source_label_bounds: routed.and_then(|e| e.tail_label.as_ref()).map(|l| l.rect.into()),
                    target_label_bounds: routed.and_then(|e| e.head_label.as_ref()).map(|l| l.rect.into()),
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
        controls: scene
            .nodes
            .iter()
            .filter_map(|n| {
                let (node, kind) = n.id.rsplit_once('#').filter(|(_, k)| matches!(*k, "decision" | "merge"))?;
                Some(ControlView { id: n.id.clone(), kind: kind.into(), node: node.into(), bounds: n.rect.into() })
            })
            .collect(),
        svg: None,
        png: None,
        layout_error: None,
    }
}

/// A transition's whole route: from its node through the decision it leaves by (or the merge it
/// enters by), the diamond's centre, to its other node.
fn through_controls(
    edge: &scene::SceneEdge,
    routes: &HashMap<&str, &scene::SceneEdge>,
    boxes: &HashMap<&str, Rect>,
) -> Vec<scene::Point> {
    let centre = |id: &str| boxes.get(id).map(|r| scene::Point { x: r.x + r.width / 2.0, y: r.y + r.height / 2.0 });
    let mut points = Vec::new();
    if let (Some(trunk), Some(c)) = (routes.get(edge.source.as_str()), centre(&edge.source)) {
        points.extend(&trunk.points);
        points.push(c);
    }
    points.extend(&edge.points);
    if let (Some(tail), Some(c)) = (routes.get(edge.target.as_str()), centre(&edge.target)) {
        points.push(c);
        points.extend(&tail.points);
    }
    points
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
