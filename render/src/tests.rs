//! Tests over every sample diagram: the scene's geometry (no overlaps, labels clear, edges on
//! their boxes and ports), text that fits its box, and the writers (SVG deterministic and
//! rasterizable, layout JSON in the metrics script's format).

use gudsl_model::{
    graph::{Graph, GraphKind, NodeShape},
    AnalysisHost,
};

use crate::{
    geometry::{intersects, segment_meets_box},
    json,
    scene::{
        self,
        measure::{content, port_anchors, FONT_SIZE, PADDING, PORT_INSET, PORT_SIZE},
        Point, Rect, Scene,
    },
    svg::render,
    text::{self, Style},
};

#[path = "../tests/common/samples.rs"]
mod samples;
pub(crate) use samples::{sample, sample_graphs};

#[test]
fn every_sample_diagram_renders_deterministically() {
    let graphs = sample_graphs();
    assert!(graphs.len() > 40);
    for graph in &graphs {
        let svg = render(graph);
        assert!(svg.starts_with("<svg ") && svg.ends_with("</svg>\n"), "{}", graph.id);
        assert_eq!(svg, render(graph), "{}: not deterministic", graph.id);
        // Every node of the graph, and the decisions and merges the text leaves implicit.
        let scene = scene::build(graph, scene::Hints::default());
        assert_eq!(svg.matches("<g class=\"node\"").count(), scene.nodes.len(), "{}", graph.id);
        for node in &graph.nodes {
            assert!(svg.contains(&format!("<g class=\"node\" data-id=\"{}\"", node.id)), "{}: {}", graph.id, node.id);
        }
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{}", graph.id);
    }
}

#[test]
fn every_sample_diagram_has_its_frame_and_heading() {
    for graph in &sample_graphs() {
        let scene = scene::build(graph, scene::Hints::default());
        let frame = &scene.frame;
        let kind = match graph.kind {
            GraphKind::Class => "class",
            GraphKind::Activity => "act",
            GraphKind::Component => "cmp",
            GraphKind::ComponentInstance => "inst",
        };
        let lines: Vec<&str> = frame.heading.iter().map(|l| l.text.as_str()).collect();
        assert_eq!(lines[0], format!("{kind} {}", graph.id));
        // An activity's parameters, its owner and its variables are in its header.
        let heading = lines.join(" ");
        for parameter in &graph.parameters {
            assert!(heading.contains(parameter.as_str()), "{}: {parameter} not in {heading}", graph.id);
        }
        if let Some(owner) = &graph.owner {
            assert!(heading.contains(&format!("owner {owner}")), "{}: no owner in {heading}", graph.id);
        }
        let variables: Vec<&str> =
            frame.variables.iter().flat_map(|(_, l)| l.iter().map(|l| l.text.as_str())).collect();
        for variable in &graph.variables {
            assert!(variables.contains(&variable.as_str()), "{}: variable {variable} not shown", graph.id);
        }
        // The tab is in the frame, and the frame holds every node.
        let inside = |r: Rect| {
            r.x >= frame.rect.x
                && r.y >= frame.rect.y
                && r.x + r.width <= frame.rect.x + frame.rect.width
                && r.y + r.height <= frame.rect.y + frame.rect.height
        };
        assert!(inside(frame.tab), "{}: the tab sticks out", graph.id);
        for node in &scene.nodes {
            assert!(inside(node.rect), "{}: {} is outside the frame", graph.id, node.id);
        }
        let svg = render(graph);
        assert!(svg.contains("<g class=\"frame\">"), "{}", graph.id);
        assert!(svg.contains(&format!(">{kind} {}<", graph.id)), "{}: no heading drawn", graph.id);
    }
}

#[test]
fn swimlanes_hold_their_nodes_edges_and_labels_and_do_not_overlap() {
    let mut lanes_seen = 0;
    for graph in &sample_graphs() {
        let scene = scene::build(graph, scene::Hints::default());
        let lane_of = |id: &str| graph.nodes.iter().find(|n| n.id == id).and_then(|n| n.group.clone());
        let within = |r: Rect, lane: Rect| {
            r.x >= lane.x
                && r.y >= lane.y
                && r.x + r.width <= lane.x + lane.width
                && r.y + r.height <= lane.y + lane.height
        };
        for (k, lane) in scene.lanes.iter().enumerate() {
            lanes_seen += 1;
            assert!(within(lane.rect, scene.frame.rect), "{}: lane {} sticks out of the frame", graph.id, lane.id);
            for other in &scene.lanes[k + 1..] {
                assert!(!intersects(lane.rect, other.rect), "{}: lanes {} and {} overlap", graph.id, lane.id, other.id);
            }
            for node in scene.nodes.iter().filter(|n| lane_of(&n.id).as_deref() == Some(lane.id.as_str())) {
                assert!(within(node.rect, lane.rect), "{}: {} is outside its lane {}", graph.id, node.id, lane.id);
            }
            // An edge between two nodes of the lane runs inside it, with its labels.
            let inside = |id: &str| lane_of(id).as_deref() == Some(lane.id.as_str());
            for edge in scene.edges.iter().filter(|e| inside(&e.source) && inside(&e.target)) {
                for p in &edge.points {
                    let point = Rect { x: p.x, y: p.y, width: 0.0, height: 0.0 };
                    assert!(within(point, lane.rect), "{}: {} leaves its lane {}", graph.id, edge.id, lane.id);
                }
                for label in [&edge.label, &edge.tail_label, &edge.head_label].into_iter().flatten() {
                    assert!(within(label.rect, lane.rect), "{}: {}'s label is outside {}", graph.id, edge.id, lane.id);
                }
            }
        }
    }
    assert!(lanes_seen > 5, "the samples have swimlanes");
}

#[test]
fn every_sample_svg_rasterizes_with_resvg() {
    for graph in sample_graphs().iter() {
        let png = crate::png::to_png(&render(graph), 1.0).unwrap_or_else(|e| panic!("{}: {e}", graph.id));
        assert!(png.starts_with(b"\x89PNG"), "{}", graph.id);
    }
    for graph in sample_graphs() {
        crate::png::parse(&render(&graph)).unwrap_or_else(|e| panic!("{}: {e}", graph.id));
    }
}

#[test]
fn no_text_is_lost_long_lines_wrap_and_the_title_holds_everything() {
    let mut wrapped = 0;
    for graph in sample_graphs().iter() {
        let scene = scene::build(graph, scene::Hints::default());
        for node in graph.nodes.iter() {
            let drawn = scene.nodes.iter().find(|n| n.id == node.id).expect("every node is drawn");
            let lines: Vec<&str> = drawn.compartments.iter().flat_map(|c| &c.lines).map(|l| l.text.as_str()).collect();
            for line in &lines {
                assert!(line.chars().count() <= 60, "{}: `{line}` is too long", node.id);
                assert!(!line.ends_with('…') || line.ends_with("more lines"), "{}: `{line}` is cut", node.id);
            }
            // Every line of the model is in the tooltip whole, and drawn (wrapped) unless the
            // body says how many lines it collapsed.
            let joined: String = lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
            let collapsed = lines.iter().any(|l| l.ends_with("more lines"));
            for line in node.compartments.iter().flat_map(|c| &c.lines) {
                assert!(drawn.title.contains(line.as_str()), "{}: `{line}` is not in the title", node.id);
                let squeezed = |s: &str| s.split_whitespace().collect::<String>();
                assert!(collapsed || squeezed(&joined).contains(&squeezed(line)), "{}: `{line}` is not drawn", node.id);
            }
            let indented = |l: &&crate::scene::TextLine| l.x > drawn.rect.x + PADDING + 1.0;
            wrapped += drawn.compartments.iter().flat_map(|c| &c.lines).filter(indented).count();
        }
        assert!(crate::svg::write(&scene).contains("<title>"), "{}", graph.id);
    }
    assert!(wrapped > 0, "some sample has a line long enough to wrap");
}

#[test]
fn static_members_are_underlined() {
    let graphs = sample_graphs();
    let svg = render(sample(&graphs, "Qualifiers")); // listing 3
    let underlined: Vec<&str> = svg.lines().filter(|l| l.contains(r#"text-decoration="underline""#)).collect();
    assert_eq!(underlined.len(), 1, "one node line holds them: {svg}");
    let line = underlined[0];
    // g, k and memcpy, wrapped on two lines.
    assert_eq!(line.matches(r#"text-decoration="underline""#).count(), 4, "{line}");
    assert!(line.contains(r#"text-decoration="underline">+ memcpy("#), "{line}");
}

#[test]
fn wrapping_breaks_after_spaces_and_commas_and_cuts_nothing() {
    let signature =
        "+ filterBilateral(inBuffer : image2D_uc, outBuffer : image2D_uc, kernelSize : int, sigma : float) : void";
    let lines = scene::measure::wrap(signature);
    assert!(lines.len() > 1 && lines.iter().all(|l| l.chars().count() <= 60), "{lines:?}");
    assert!(lines[0].ends_with(','), "{lines:?}");
    assert!(lines[1..].iter().all(|l| l.starts_with("    ")));
    let back: String = lines.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
    assert_eq!(back, signature);
    // A word longer than a line is broken within it.
    let word = "x".repeat(130);
    let lines = scene::measure::wrap(&word);
    assert_eq!(lines.iter().map(|l| l.trim()).collect::<String>(), word);
    assert_eq!(scene::measure::wrap("short"), ["short"]);
}

#[test]
fn layout_json_is_the_metrics_script_format() {
    let mut kinds = std::collections::BTreeSet::new();
    for graph in sample_graphs().iter() {
        let scene = scene::build(graph, scene::Hints::default());
        let json: serde_json::Value = serde_json::from_str(&json::write(&scene)).expect("layout JSON parses");
        let (nodes, edges, labels) = (&json["nodes"], &json["edges"], &json["labels"]);
        assert_eq!(nodes.as_array().map(Vec::len), Some(scene.nodes.len()), "{}", graph.id);
        assert!(nodes.as_array().unwrap().iter().all(|n| ["id", "x", "y", "w", "h"].iter().all(|k| !n[k].is_null())));
        assert_eq!(edges.as_array().map(Vec::len), Some(scene.edges.len()), "{}", graph.id);
        for edge in edges.as_array().unwrap() {
            assert!(edge["src"].is_string() && edge["dst"].is_string() && edge["kind"].is_string(), "{edge}");
            assert!(edge["points"].as_array().is_some_and(|p| p.len() >= 2), "{edge}");
        }
        for label in labels.as_array().unwrap() {
            let edge = label["edge"].as_u64().expect("a label names its edge") as usize;
            let kind = label["kind"].as_str().unwrap_or_default();
            assert!(edge < scene.edges.len() && ["mid", "head", "tail"].contains(&kind), "{label}");
            assert!(label["text"].as_str().is_some_and(|t| !t.is_empty()), "{label}");
            kinds.insert(kind.to_string());
        }
    }
    // The samples have guards (middle labels) and associations with roles and multiplicities.
    assert_eq!(kinds.into_iter().collect::<Vec<_>>(), ["head", "mid", "tail"]);
}

/// Geometry of every sample diagram: boxes do not overlap, no label covers a box or is crossed
/// by an edge, and every edge starts and ends on the border of its boxes (or at its ports).
#[test]
fn sample_geometry_is_clean() {
    for graph in sample_graphs() {
        assert_clean(&graph, &scene::build(&graph, scene::Hints::default()), true);
    }
}

/// Boxes do not overlap, no label covers a box or another label (or is crossed by an edge, if
/// `labels_off_edges`), and every edge starts and ends on the border of its boxes (or at its
/// ports).
pub(crate) fn assert_clean(graph: &Graph, scene: &Scene, labels_off_edges: bool) {
    let boxes: Vec<Rect> = scene.nodes.iter().map(|n| n.rect).collect();
    // A nested component and the nodes that hold it: it lies inside each of them.
    let lineage = |node: usize| {
        std::iter::successors(Some(node), |&n| {
            let parent = scene.nodes[n].parent.as_ref()?;
            scene.nodes.iter().position(|m| &m.id == parent)
        })
        .collect::<Vec<usize>>()
    };
    for a in 0..boxes.len() {
        for b in a + 1..boxes.len() {
            let (outer, inner) = if lineage(a).contains(&b) { (b, a) } else { (a, b) };
            if lineage(inner).contains(&outer) {
                let (o, i) = (boxes[outer], boxes[inner]);
                let within = i.x > o.x && i.y > o.y && i.x + i.width < o.x + o.width && i.y + i.height < o.y + o.height;
                assert!(within, "{}: {} sticks out of {}", graph.id, scene.nodes[inner].id, scene.nodes[outer].id);
                continue;
            }
            assert!(
                !intersects(boxes[a], boxes[b]),
                "{}: {} overlaps {}",
                graph.id,
                scene.nodes[a].id,
                scene.nodes[b].id
            );
        }
    }
    // Every label: the middle one and those at the ends.
    let labels: Vec<(&str, Rect)> = scene
        .edges
        .iter()
        .flat_map(|e| [&e.label, &e.tail_label, &e.head_label].into_iter().flatten().map(|l| (e.id.as_str(), l.rect)))
        .collect();
    for (k, (a, ra)) in labels.iter().enumerate() {
        for (b, rb) in &labels[k + 1..] {
            assert!(!intersects(*ra, *rb), "{}: the labels of {a} and {b} overlap", graph.id);
        }
    }
    let frame = scene.frame.rect;
    let index_of = |id: &str| scene.nodes.iter().position(|n| id == n.id || id.starts_with(&format!("{}.", n.id)));
    // The nodes that hold an edge's two ends (or are one end and hold the other).
    let holding = |edge: &str| {
        let e = scene.edges.iter().find(|e| e.id == edge).unwrap();
        let (Some(s), Some(t)) = (index_of(&e.source), index_of(&e.target)) else { return Vec::new() };
        lineage(s).into_iter().filter(|&n| lineage(t).contains(&n) && (n != s || n != t)).collect::<Vec<usize>>()
    };
    for &(edge, label) in &labels {
        for other in scene.edges.iter().filter(|_| labels_off_edges) {
            let crossed = other.points.windows(2).any(|s| segment_meets_box(s[0], s[1], label));
            assert!(!crossed, "{}: label of {edge} is crossed by {}", graph.id, other.id);
        }
        let open = holding(edge);
        for (i, b) in boxes.iter().enumerate() {
            let clear = !intersects(label, *b) || (open.contains(&i) && !intersects(label, text_area(&scene.nodes[i])));
            assert!(clear, "{}: label of {edge} covers {}", graph.id, scene.nodes[i].id);
        }
        let inside = label.x >= frame.x
            && label.y >= frame.y
            && label.x + label.width <= frame.x + frame.width
            && label.y + label.height <= frame.y + frame.height;
        assert!(inside, "{}: label of {edge} is outside the frame", graph.id);
    }
    let graph_node = |node: usize| graph.nodes.iter().find(|n| n.id == scene.nodes[node].id);
    for edge in &scene.edges {
        let route = &edge.points;
        let (Some(s), Some(t)) = (index_of(&edge.source), index_of(&edge.target)) else { continue };
        if s == t {
            continue;
        }
        // Port-to-port edges end at the ports' anchors, outside the boxes.
        let port_anchor = |node: usize, id: &str| {
            let drawn = graph_node(node)?;
            drawn.ports.iter().position(|p| p.id == id).map(|i| {
                let at = Point { x: boxes[node].x, y: boxes[node].y };
                let mut measured = content(drawn);
                // A parent's text stays on top of the room its nested components take.
                measured.nested = boxes[node].height - measured.height;
                (measured.width, measured.height) = (boxes[node].width, boxes[node].height);
                port_anchors(drawn, &measured, at)[i]
            })
        };
        // It runs inside its ends' parents, never through their text.
        let inside: Vec<usize> = lineage(s).into_iter().skip(1).chain(lineage(t).into_iter().skip(1)).collect();
        if let (Some(a), Some(b)) = (port_anchor(s, &edge.source), port_anchor(t, &edge.target)) {
            // At its port's anchor, or fanned out beside it with the other routes at that port
            // (no further than 4.5 pt: the layout's fan takes at most 9).
            let at_port = |end: Point, anchor: Point| end.x == anchor.x && (end.y - anchor.y).abs() <= 4.5;
            assert!(at_port(route[0], a), "{}: {} does not start at its port", graph.id, edge.id);
            assert!(at_port(*route.last().unwrap(), b), "{}: {} does not end at its port", graph.id, edge.id);
            // Axis-parallel segments: none may pass through a box.
            for segment in route.windows(2) {
                let (x0, x1) = (segment[0].x.min(segment[1].x), segment[0].x.max(segment[1].x));
                let (y0, y1) = (segment[0].y.min(segment[1].y), segment[0].y.max(segment[1].y));
                for (i, bx) in boxes.iter().enumerate() {
                    let bx = if inside.contains(&i) { &text_area(&scene.nodes[i]) } else { bx };
                    let hit = x0 < bx.x + bx.width
                        && bx.x < x1.max(x0 + 0.01)
                        && y0 < bx.y + bx.height
                        && bx.y < y1.max(y0 + 0.01);
                    assert!(!hit, "{}: {} passes through {}", graph.id, edge.id, scene.nodes[i].id);
                }
            }
            continue;
        }
        let on_border = |p: Point, b: Rect| {
            let e = 0.01;
            let inside = p.x >= b.x - e && p.x <= b.x + b.width + e && p.y >= b.y - e && p.y <= b.y + b.height + e;
            let edge_x = (p.x - b.x).abs() < e || (p.x - b.x - b.width).abs() < e;
            let edge_y = (p.y - b.y).abs() < e || (p.y - b.y - b.height).abs() < e;
            inside && (edge_x || edge_y)
        };
        // A diamond's edges end on its outline.
        let on_outline = |p: Point, node: usize| match scene.nodes[node].shape {
            NodeShape::Decision => (crate::scene::notation::diamond_distance(p, boxes[node]) - 1.0).abs() < 1e-3,
            _ => on_border(p, boxes[node]),
        };
        assert!(on_outline(route[0], s), "{}: {} does not start on its node's outline", graph.id, edge.id);
        assert!(on_outline(*route.last().unwrap(), t), "{}: {} does not end on its node's outline", graph.id, edge.id);
    }
}

#[test]
fn text_fits_its_box() {
    for graph in sample_graphs() {
        for node in &graph.nodes {
            let c = content(node);
            for (line, style) in &c.header {
                assert!(text::width(line, FONT_SIZE, *style) + 2.0 * PADDING <= c.width + 1e-6, "{}: {line}", node.id);
            }
            for (line, style) in c.compartments.iter().flatten() {
                assert!(text::width(line, FONT_SIZE, *style) + 2.0 * PADDING <= c.width + 1e-6, "{}: {line}", node.id);
            }
            for port in &node.ports {
                let line = &port.label;
                assert!(
                    text::width(line, PORT_SIZE, Style::Regular) + PORT_INSET + 2.0 * PADDING <= c.width + 1e-6,
                    "{}: {line}",
                    node.id
                );
            }
        }
    }
}

/// Where an activity's control branches or meets, the drawing has UML's diamond: no action
/// has two guarded flows out or two flows in, and the empty guard reads `[else]`.
#[test]
fn activity_branches_and_meetings_go_through_diamonds() {
    let mut diamonds = 0;
    for graph in sample_graphs().iter().filter(|g| g.kind == GraphKind::Activity) {
        let scene = scene::build(graph, scene::Hints::default());
        for node in scene.nodes.iter().filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Fork)) {
            let out: Vec<_> = scene.edges.iter().filter(|e| e.source == node.id && e.target != node.id).collect();
            let guarded =
                out.iter().filter(|e| e.label.as_ref().is_some_and(|l| l.lines[0].1.starts_with('['))).count();
            assert!(out.len() < 2 || guarded == 0, "{}: {} branches without a decision", graph.id, node.id);
        }
        for node in scene.nodes.iter().filter(|n| !matches!(n.shape, NodeShape::Decision | NodeShape::Join)) {
            let into = scene.edges.iter().filter(|e| e.target == node.id && e.source != node.id).count();
            assert!(into < 2, "{}: flows meet at {} without a merge", graph.id, node.id);
        }
        for edge in &scene.edges {
            assert!(edge.label.as_ref().is_none_or(|l| !l.lines[0].1.starts_with("[]")), "{}: {}", graph.id, edge.id);
            // Every branch has its guard; the one taken when none holds is `[else]`.
            let guarded = edge.label.as_ref().is_some_and(|l| l.lines[0].1.starts_with('['));
            assert!(!edge.source.ends_with("#decision") || guarded, "{}: {} has no guard", graph.id, edge.id);
        }
        diamonds += scene.nodes.iter().filter(|n| n.id.ends_with("#decision") || n.id.ends_with("#merge")).count();
    }
    assert!(diamonds > 10, "{diamonds}");
}

#[test]
fn loops_and_calc_nodes_are_drawn_as_expansion_regions() {
    let graphs = sample_graphs();
    let window = sample(&graphs, "LoopWindowExample"); // listing 12
    let svg = render(window);
    let node = node_svg(&svg, "LoopWindowExample/Lane/filterKernel");
    assert!(node.contains(r#"stroke-dasharray="6,4""#), "a dashed region: {node}");
    assert!(node.contains(r#"class="expansion-node""#), "with its expansion node: {node}");
    // The dissertation's areas, labelled, each loop of the window in every area.
    for area in ["setup: var int u = -n_radius, var float v", "test: u &lt; n_radius, v &lt; n_radius", "increment: u"]
    {
        assert!(node.contains(area), "{area}: {node}");
    }
    let scene = scene::build(window, scene::Hints::default());
    let region = scene.nodes.iter().find(|n| n.id.ends_with("filterKernel")).unwrap();
    // The keyword in the top left corner, the name centred.
    let (keyword, name) = (&region.header[0], &region.header[1]);
    assert_eq!(keyword.text, "«loopWindow»");
    let keyword_left = keyword.x - text::width(&keyword.text, FONT_SIZE, keyword.style) / 2.0;
    assert!((keyword_left - region.rect.x - PADDING).abs() < 0.01, "{keyword_left} vs {:?}", region.rect);
    assert!((name.x - region.rect.x - region.rect.width / 2.0).abs() < 0.01);
    // An action stays a solid box without expansion nodes.
    let action = node_svg(&svg, "LoopWindowExample/Lane/writeOutput");
    assert!(!action.contains("stroke-dasharray") && !action.contains("expansion-node"), "{action}");

    let svg = render(sample(&graphs, "CalcNodeExample")); // listing 10
    let node = node_svg(&svg, "CalcNodeExample/Lane/filterData");
    assert!(node.contains(r#"stroke-dasharray="6,4""#) && node.contains("expansion-node"), "{node}");
}

/// The SVG group that draws the node `id` (its title may span lines).
fn node_svg<'a>(svg: &'a str, id: &str) -> &'a str {
    let start = svg.find(&format!(r#"<g class="node" data-id="{id}">"#)).expect("the node is drawn");
    &svg[start..start + svg[start..].find("</g>").unwrap()]
}

/// A node's box down to its last line of text or port row (a nested component's parent holds
/// its children under it).
fn text_area(node: &scene::SceneNode) -> Rect {
    let line_h = text::line_height(FONT_SIZE);
    let last = node.header.iter().chain(node.compartments.iter().flat_map(|c| &c.lines)).map(|l| l.y);
    let bottom = last.chain(node.ports.iter().map(|p| p.anchor.y)).fold(node.rect.y, f64::max) + line_h / 2.0;
    Rect { height: bottom - node.rect.y, ..node.rect }
}

/// The graph of the first diagram of `text` and its scene, laid out without hints.
fn first_diagram_drawn(text: &str) -> (Graph, Scene) {
    let (host, files) = AnalysisHost::with_files(vec![("nested.gudsl".to_string(), text.to_string())]);
    let graph = host.analysis().graphs(files[0]).unwrap()[0].clone();
    let scene = scene::build(&graph, scene::Hints::default());
    (graph, scene)
}

#[test]
fn nested_components_are_drawn_inside_their_parents_with_their_connections() {
    let text = "ComponentDiagram Nested {
        filter P.Pipeline {
            port PipeIn ( processor In : P.IImageProcessor )
            port PipeOut ( provider Out : P.IImageProvider )
            [Delegate source PipeIn.In ==> target FilterPort.ImageIn]
            source P.Camera {
                port CameraPort ( provider ImageOut : P.IImageProvider )
                [CameraToFilter source CameraPort.ImageOut ==> target FilterPort.ImageIn]
                class P.Inner { }
            }
            filter P.MeanFilter {
                port FilterPort ( processor ImageIn : P.IImageProcessor, provider ImageOut : P.IImageProvider )
                [FilterToViewer source FilterPort.ImageOut ==> target ViewerPort.ImageIn]
                [Out source FilterPort.ImageOut ==> target PipeOut.Out]
            }
        }
        source P.Source {
            port SrcPort ( provider O : P.IImageProvider )
            [ToPipe source SrcPort.O ==> target PipeIn.In]
        }
        sink P.Viewer { port ViewerPort ( processor ImageIn : P.IImageProcessor ) }
    }";
    let (graph, scene) = first_diagram_drawn(text);
    let parent = |id: &str| scene.nodes.iter().find(|n| n.id == id).unwrap().parent.clone();
    assert_eq!(parent("P.Camera").as_deref(), Some("P.Pipeline"));
    assert_eq!(parent("P.Inner").as_deref(), Some("P.Camera"));
    assert_eq!(parent("P.Source"), None);
    // Inside their parents, clear of each other; every connection from port to port, through
    // no box but its ends' parents and through none of their text.
    assert_clean(&graph, &scene, true);
    assert_eq!(scene.edges.iter().filter(|e| e.points.len() >= 2).count(), 5);
    // Parents are drawn before the connections inside them, the rest after.
    let svg = render(&graph);
    let at = |what: &str| svg.find(what).unwrap_or_else(|| panic!("{what} is drawn"));
    assert!(at(r#"data-id="P.Pipeline""#) < at(r#"class="edge" data-id="P.Camera.CameraPort"#));
    assert!(at(r#"class="edge" data-id="P.Camera.CameraPort"#) < at(r#"data-id="P.MeanFilter""#));
}

#[test]
fn nested_activity_nodes_are_drawn_inside_their_containers() {
    let text = "ActivityDiagram Ad(int n) {
        public int total = 0;
        swimlane L {
            start S { => each; }
            loop each(var int i = 0; i < n; i = i + 1) {
                total = total + 1;
                start inner { => pick; }
                decision pick {
                    start s2 { => test; }
                    action test { total = total * 2; => t; }
                    final t;
                    [i % 2 == 0] => even;
                    [] => done;
                }
                action even { total = total + i; => done; }
                final done;
                => f;
            }
            final f;
        }
    }";
    let (graph, scene) = first_diagram_drawn(text);
    let parent = |id: &str| scene.nodes.iter().find(|n| n.id == id).unwrap().parent.clone();
    assert_eq!(parent("Ad/L/pick").as_deref(), Some("Ad/L/each"));
    assert_eq!(parent("Ad/L/test").as_deref(), Some("Ad/L/pick"));
    assert_eq!(parent("Ad/L/f"), None);
    // Inside their containers (two levels), clear of each other, guards off the boxes.
    assert_clean(&graph, &scene, true);
    assert!(scene.edges.iter().all(|e| e.points.len() >= 2));
}
