//! [`build`], stage by stage: measure the nodes and their edges' texts, lay the graph out
//! (layers, or nested components), arrange it around what the user pinned and what was drawn
//! before, route connections port to port, place the edge labels, fit the swimlanes and the
//! frame around it all, and assemble the scene.

use std::collections::HashMap;

use gudsl_model::graph::{EdgeEnd, EdgeKind, Graph, GraphEdge, GraphKind, NodeShape};

use super::{
    arrange, channels, connections, edge_label, frame, labels, lane_of, lane_span,
    measure::{content, label_size, port_anchors, Content},
    nesting::Nesting,
    notation, port_reach, scene_node, Hints, Point, Rect, Scene, SceneEdge, BODY_INSET,
};
use crate::layout::{
    layered, layered_left_to_right, Entry, Layout, LayoutInput, LayoutNode, Page, Remembered, RowEntry, Spacing,
};
use crate::pins::{read_row_entry, row_entry, Rows, BAND_MARK, COLUMN_MARK};

/// A graph's edge with both ends found: node indices, and port indices on them.
struct ResolvedEdge<'g> {
    edge: &'g GraphEdge,
    from: (usize, Option<usize>),
    to: (usize, Option<usize>),
}

/// What the stages share: the graph, its edges with both ends found and their texts, each
/// node's measured content and the room its port symbols take beside it.
struct Parts<'g> {
    graph: &'g Graph,
    edges: Vec<ResolvedEdge<'g>>,
    texts: Vec<labels::EdgeTexts>,
    contents: Vec<Content>,
    reaches: Vec<(f64, f64)>,
}

/// Measures and lays out a graph, around the nodes `hints` pins or keeps where they were.
pub fn build(graph: &Graph, hints: Hints) -> Scene {
    let graph = &*notation::with_control_nodes(graph);
    let mut nesting = Nesting::of(graph);
    let pinned = graph.nodes.iter().any(|node| hints.pins.is_some_and(|pins| pins.get(&node.id).is_some()));
    // Nested components and nodes around pins are connected by the router around the boxes: it
    // runs their tracks beside the boxes.
    let mut parts = measure(graph, hints, !nesting.is_flat() || pinned);
    let input = LayoutInput { remembered: remembered(&parts, hints.rows), ..layout_input(&parts) };
    // The frame's heading comes first; the diagram is laid out below it.
    let heading = frame::Heading::measure(graph);
    let mut layout = lay_out(&mut parts, &input, &mut nesting, heading.body_offset(), (hints.page, pinned));
    let id = |&(entry, x, y): &RowEntry| {
        let id = match entry {
            Entry::Box(v) => &graph.nodes[v].id,
            Entry::Edge(e) => &parts.edges[e].edge.id,
            Entry::Band => BAND_MARK,
            Entry::Column => COLUMN_MARK,
        };
        row_entry(id, x, y)
    };
    let rows = layout.rows.iter().map(|row| row.iter().map(id).collect()).collect();
    let arranged = arrange_nodes(&parts, &input, &nesting, &mut layout, hints, heading.body_offset());
    let boxes: Vec<Rect> = layout
        .positions
        .iter()
        .zip(&parts.contents)
        .map(|(p, c)| Rect { x: p.x, y: p.y, width: c.width, height: c.height })
        .collect();
    // A nested component's parent is in the way of what runs outside it, its text (header and
    // port rows) in the way of everything.
    let text_areas = (0..boxes.len())
        .filter(|&i| parts.contents[i].nested > 0.0)
        .map(|i| Rect { height: boxes[i].height - parts.contents[i].nested, ..boxes[i] });
    let obstacles: Vec<Rect> = boxes.iter().copied().chain(text_areas).collect();
    route_connections(&parts, &nesting, &mut layout, arranged, (&boxes, &obstacles));
    let corner = Point { x: BODY_INSET, y: heading.body_top() };
    let shared: Vec<Vec<usize>> = parts.edges.iter().map(|e| nesting.holding_both(e.from.0, e.to.0)).collect();
    let labels =
        labels::place_all(&parts.texts, &layout.edges, &layout.labels, &layout.end_labels, &obstacles, &shared, corner);
    let (width, height, lanes) = fit_lanes(&parts, &layout, &boxes, &labels);
    let (min_width, min_height) = heading.min_size();
    let (width, height) = (width.max(min_width), height.max(min_height));
    let frame = heading.place(width, height);
    // Lanes fill the frame's body, from under the heading to the frame's bottom.
    let body_top = heading.body_top();
    let body = Rect {
        x: BODY_INSET,
        y: body_top,
        width: frame.rect.width - 8.0,
        height: frame.rect.y + frame.rect.height - 4.0 - body_top,
    };
    let lanes = graph.groups.iter().zip(lanes).filter_map(|(group, span)| Some(lane_of(group, span?, body))).collect();
    let texts = std::mem::take(&mut parts.texts);
    let edges = scene_edges(&parts, texts, layout.edges, labels);
    let nodes = graph
        .nodes
        .iter()
        .zip(&parts.contents)
        .zip(&boxes)
        .map(|((node, content), rect)| scene_node(node, content, *rect))
        .collect();
    Scene { id: graph.id.clone(), width, height, frame, lanes, edges, nodes, rows }
}

/// Where each node and edge sat in `rows` (a fresh layout's before, by id); nothing without
/// rows. Ids no longer in the graph are left out.
fn remembered(parts: &Parts, rows: Option<&Rows>) -> Remembered {
    let Some(rows) = rows else { return Remembered::default() };
    let nodes = parts.graph.nodes.iter().enumerate().map(|(i, n)| (n.id.as_str(), Entry::Box(i)));
    let edges = parts.edges.iter().enumerate().map(|(k, e)| (e.edge.id.as_str(), Entry::Edge(k)));
    let by_id: HashMap<&str, Entry> = nodes.chain(edges).collect();
    let entry = |text: &String| {
        let (id, x, y) = read_row_entry(text);
        let entry = match id {
            BAND_MARK => Entry::Band,
            COLUMN_MARK => Entry::Column,
            _ => *by_id.get(id)?,
        };
        Some((entry, x, y))
    };
    // A row's index becomes a rank, and a sidecar is untrusted input: a million rows must not
    // make a million ranks. As a layout writes them, every row holds a box and every box is in
    // one row: a box named again is left out, and a row left without a box goes.
    let mut seen = vec![false; parts.graph.nodes.len()];
    let mut first_time = |e: &RowEntry| match e.0 {
        Entry::Box(v) => !std::mem::replace(&mut seen[v], true),
        Entry::Edge(_) | Entry::Band | Entry::Column => true,
    };
    let entries: Vec<Vec<RowEntry>> = rows
        .iter()
        .map(|row| row.iter().filter_map(entry).filter(|e| first_time(e)).collect::<Vec<_>>())
        .filter(|row| row.iter().any(|e| matches!(e.0, Entry::Box(_))))
        .collect();
    Remembered::of_rows(&entries, parts.graph.nodes.len(), parts.edges.len())
}

/// Each node measured (a node the user resized at that size, never smaller than its text),
/// the edges whose ends are both in the graph (dangling ones are not drawn), their texts, the
/// room beside each box for its port symbols (and their tracks, where `tracks_beside`).
fn measure<'g>(graph: &'g Graph, hints: Hints, tracks_beside: bool) -> Parts<'g> {
    let mut contents: Vec<Content> = graph.nodes.iter().map(content).collect();
    for (node, content) in graph.nodes.iter().zip(&mut contents) {
        if let Some((width, height)) = hints.pins.and_then(|p| p.get(&node.id)).and_then(|pin| pin.size()) {
            content.width = content.width.max(width);
            content.height = content.height.max(height);
        }
    }
    let by_id: HashMap<&str, usize> = graph.nodes.iter().enumerate().map(|(i, n)| (n.id.as_str(), i)).collect();
    let resolve = |end: &EdgeEnd| {
        let node = *by_id.get(end.node.as_str())?;
        let port = end.port.as_ref().and_then(|id| graph.nodes[node].ports.iter().position(|p| &p.id == id));
        Some((node, port))
    };
    let edges: Vec<ResolvedEdge> = graph
        .edges
        .iter()
        .filter_map(|edge| Some(ResolvedEdge { edge, from: resolve(&edge.source)?, to: resolve(&edge.target)? }))
        .collect();
    let texts = edges.iter().map(|e| labels::texts(e.edge)).collect();
    let reaches = graph.nodes.iter().map(|node| port_reach(node, tracks_beside)).collect();
    Parts { graph, edges, texts, contents, reaches }
}

/// Whether an edge points upwards in UML (generalization, realization): laid out parent first,
/// drawn from the child to the parent.
fn upwards(edge: &GraphEdge) -> bool {
    matches!(edge.kind, EdgeKind::Generalization | EdgeKind::Realization)
}

/// The layout's input: each node with the room its port symbols take beside it, the edges
/// (upward ones reversed and firm), groups, and the room of the labels of the edges the layout
/// routes (not port to port).
fn layout_input(parts: &Parts) -> LayoutInput {
    let graph = parts.graph;
    let mut input = LayoutInput {
        nodes: parts
            .contents
            .iter()
            .zip(&parts.reaches)
            .map(|(c, reach)| LayoutNode { width: reach.0 + c.width + reach.1, height: c.height })
            .collect(),
        edges: Vec::new(),
        groups: graph
            .nodes
            .iter()
            .map(|n| n.group.as_ref().and_then(|g| graph.groups.iter().position(|group| &group.id == g)))
            .collect(),
        labels: Vec::new(),
        flow: graph.kind != GraphKind::Class,
        firm: Vec::new(),
        end_labels: Vec::new(),
        remembered: Remembered::default(),
        ports: Vec::new(),
    };
    // A port's place down its box: where a connection meets it.
    let port_place = |(node, port): (usize, Option<usize>)| {
        let content = &parts.contents[node];
        Some(port_anchors(&graph.nodes[node], content, Point::default())[port?].y)
    };
    for (e, texts) in parts.edges.iter().zip(&parts.texts) {
        let upwards = upwards(e.edge);
        input.edges.push(if upwards { (e.to.0, e.from.0) } else { (e.from.0, e.to.0) });
        input.firm.push(upwards);
        let routed_by_layout = !(e.from.1.is_some() && e.to.1.is_some());
        if !routed_by_layout {
            input.ports.resize(input.edges.len() - 1, [None; 2]);
            let (from, to) = (port_place(e.from), port_place(e.to));
            input.ports.push(if upwards { [to, from] } else { [from, to] });
        }
        let middle = Some(&texts.middle).filter(|m| routed_by_layout && !m.is_empty());
        input.labels.push(middle.map(|m| label_size(m)));
        let end =
            |lines: &Vec<String>| Some(lines).filter(|l| routed_by_layout && !l.is_empty()).map(|l| label_size(l));
        let (tail, head) = (end(&texts.tail), end(&texts.head));
        input.end_labels.push(if upwards { [head, tail] } else { [tail, head] });
    }
    input
}

/// The layout below the heading (`body`: the body's corner): dataflow left to right (sources,
/// filters, sinks; between the columns the ports' symbols and tracks), class and activity
/// diagrams top down; nested components inside their parents. Upward edges drawn from the
/// child to the parent. Fitted to `page`, except a dataflow diagram with nodes the user
/// `pinned`.
fn lay_out(
    parts: &mut Parts,
    input: &LayoutInput,
    nesting: &mut Nesting,
    (body_x, body_y): (f64, f64),
    (page, pinned): (Page, bool),
) -> Layout {
    let spacing = Spacing { page, ..Spacing::default() };
    let mut layout = match parts.graph.kind {
        GraphKind::Component | GraphKind::ComponentInstance => {
            // Fitted to the page unless the user pinned nodes: around nodes the user moved,
            // the connection router can run a connection between wrapped rows through a box.
            let page = if pinned { Page::UNBOUNDED } else { page };
            let spacing = Spacing { rank_gap: 24.0, node_gap: 20.0, page, ..spacing };
            if nesting.is_flat() {
                layered_left_to_right(input, spacing)
            } else {
                nesting.layout(input, &mut parts.contents, &parts.reaches, spacing, layered_left_to_right)
            }
        }
        GraphKind::Activity if !nesting.is_flat() => {
            nesting.layout(input, &mut parts.contents, &parts.reaches, spacing, layered)
        }
        GraphKind::Class | GraphKind::Activity => layered(input, spacing),
    };
    for (at, reach) in layout.positions.iter_mut().zip(&parts.reaches) {
        at.x += reach.0;
    }
    // The layout starts at its margin; the frame's body starts below the heading.
    let margin = Spacing::default().margin;
    layout.translate(body_x - margin, body_y - margin);
    for ((route, ends), e) in layout.edges.iter_mut().zip(&mut layout.end_labels).zip(&parts.edges) {
        if upwards(e.edge) {
            route.reverse();
            ends.swap(0, 1);
        }
    }
    layout
}

/// The layout arranged around the nodes the user pinned and where the scene before had them
/// (`arrange`); nested components follow their parents wherever those went.
fn arrange_nodes(
    parts: &Parts,
    input: &LayoutInput,
    nesting: &Nesting,
    layout: &mut Layout,
    hints: Hints,
    (body_x, body_y): (f64, f64),
) -> arrange::Arranged {
    let to_place: Vec<arrange::Node> = parts
        .graph
        .nodes
        .iter()
        .zip(&parts.contents)
        .zip(&parts.reaches)
        .enumerate()
        .map(|(i, ((n, c), reach))| arrange::Node {
            id: &n.id,
            width: c.width,
            height: c.height,
            reach: *reach,
            held: nesting.is_nested(i),
        })
        .collect();
    let to_route: Vec<arrange::Edge> = parts
        .edges
        .iter()
        .zip(&input.end_labels)
        .map(|(e, ends)| arrange::Edge {
            id: &e.edge.id,
            source: e.edge.source.id(),
            target: e.edge.target.id(),
            from: e.from.0,
            to: e.to.0,
            end_label_width: ends.iter().flatten().map(|size| size.0).fold(0.0, f64::max),
        })
        .collect();
    let arranged = arrange::arrange(layout, &to_place, &to_route, hints, Point { x: body_x, y: body_y });
    nesting.follow(&mut layout.positions);
    arranged
}

/// Connections and bindings routed between ports, orthogonally: in a fresh layout of a flat
/// diagram along the layout's routes (`channels`); where arranging kept a route, that one; the
/// others around `obstacles` (`connections`). The drawing grown to hold every route; edges
/// ended on a diamond's outline.
fn route_connections(
    parts: &Parts,
    nesting: &Nesting,
    layout: &mut Layout,
    arranged: arrange::Arranged,
    (boxes, obstacles): (&[Rect], &[Rect]),
) {
    let graph = parts.graph;
    let anchors: Vec<Vec<Point>> = graph
        .nodes
        .iter()
        .zip(&parts.contents)
        .zip(&layout.positions)
        .map(|((node, content), at)| port_anchors(node, content, *at))
        .collect();
    let (wired, wires): (Vec<usize>, Vec<connections::Connection>) = parts
        .edges
        .iter()
        .enumerate()
        .filter_map(|(k, e)| {
            let (from_port, to_port) = (e.from.1?, e.to.1?);
            let (from, to) = (anchors[e.from.0][from_port], anchors[e.to.0][to_port]);
            let faces = |node: usize, at: Point| if at.x < boxes[node].x { -1.0 } else { 1.0 };
            Some((
                k,
                connections::Connection {
                    from,
                    from_faces: faces(e.from.0, from),
                    to,
                    to_faces: faces(e.to.0, to),
                    from_port: e.edge.source.id(),
                    to_port: e.edge.target.id(),
                    // Its ends' ancestors hold it: it runs inside them.
                    inside: nesting.lineage(e.from.0).skip(1).chain(nesting.lineage(e.to.0).skip(1)).collect(),
                },
            ))
        })
        .unzip();
    let given: Vec<Option<Vec<Point>>> = match arranged {
        arrange::Arranged::Fresh if nesting.is_flat() => {
            let followed: Vec<channels::Followed> = wired
                .iter()
                .zip(&wires)
                .map(|(&k, c)| {
                    // A port facing the other way (a provider on a box's left) is left to the router.
                    let facing = c.from_faces > 0.0 && c.to_faces < 0.0;
                    channels::Followed { from: c.from, to: c.to, route: if facing { &layout.edges[k] } else { &[] } }
                })
                .collect();
            channels::follow(&followed)
        }
        arrange::Arranged::Fresh => Vec::new(),
        arrange::Arranged::Around { kept } => wired.iter().map(|&k| kept[k].then(|| layout.edges[k].clone())).collect(),
    };
    for (k, route) in wired.into_iter().zip(connections::route(&wires, obstacles, given)) {
        layout.edges[k] = route;
    }
    for point in layout.edges.iter().flatten() {
        layout.width = layout.width.max(point.x + 20.0);
        layout.height = layout.height.max(point.y + 20.0);
    }
    for (route, e) in layout.edges.iter_mut().zip(&parts.edges) {
        for (node, at_end) in [(e.from.0, false), (e.to.0, true)] {
            if graph.nodes[node].shape == NodeShape::Decision && e.from.0 != e.to.0 {
                notation::clip_to_diamond(route, at_end, boxes[node]);
            }
        }
    }
}

/// The drawing's width and height, grown to hold edge labels that reach past the boxes and
/// every swimlane; each swimlane's span: its nodes, the routes and labels of the edges between
/// them, and its title.
fn fit_lanes(
    parts: &Parts,
    layout: &Layout,
    boxes: &[Rect],
    labels: &[labels::Placed],
) -> (f64, f64, Vec<Option<(f64, f64)>>) {
    let graph = parts.graph;
    let placed = || labels.iter().flat_map(labels::Placed::all);
    let width = placed().map(|l| l.x + l.width + 8.0).fold(layout.width, f64::max);
    let height = placed().map(|l| l.y + l.height + 8.0).fold(layout.height, f64::max);
    let lane_spans: Vec<Option<(f64, f64)>> = graph
        .groups
        .iter()
        .map(|group| {
            let inside = |node: usize| graph.nodes[node].group.as_ref() == Some(&group.id);
            let mut members: Vec<Rect> = (0..boxes.len()).filter(|&i| inside(i)).map(|i| boxes[i]).collect();
            for ((e, route), label) in parts.edges.iter().zip(&layout.edges).zip(labels) {
                if inside(e.from.0) && inside(e.to.0) && !members.is_empty() {
                    members.extend(route.iter().map(|p| Rect { x: p.x, y: p.y, width: 0.0, height: 0.0 }));
                    members.extend(label.all());
                }
            }
            lane_span(group, &members, BODY_INSET)
        })
        .collect();
    let width = lane_spans.iter().flatten().fold(width, |w, &(_, right)| w.max(right + BODY_INSET));
    (width, height, lane_spans)
}

/// The scene's edges: each route with its labels at their places.
fn scene_edges(
    parts: &Parts,
    texts: Vec<labels::EdgeTexts>,
    routes: Vec<Vec<Point>>,
    labels: Vec<labels::Placed>,
) -> Vec<SceneEdge> {
    parts
        .edges
        .iter()
        .zip(routes)
        .zip(texts)
        .zip(labels)
        .map(|(((e, points), texts), at)| SceneEdge {
            id: e.edge.id.clone(),
            kind: e.edge.kind,
            source: e.edge.source.id().to_string(),
            target: e.edge.target.id().to_string(),
            label: at.middle.map(|rect| edge_label(texts.middle, rect)),
            tail_label: at.tail.map(|rect| edge_label(texts.tail, rect)),
            head_label: at.head.map(|rect| edge_label(texts.head, rect)),
            points,
        })
        .collect()
}
