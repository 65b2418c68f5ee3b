//! Tests of arranging around pins and a previous scene, over every sample diagram: pinned
//! nodes are drawn exactly where they were put, an added node leaves every other node where it
//! was, and the geometry stays clean: no overlaps, edges on their boxes, labels clear of boxes
//! and of each other. (A straight route to a node that moved may cross a label where the
//! drawing leaves no room; the fresh layout's never do, `tests::sample_geometry_is_clean`.)

use gudsl_model::graph::Graph;

use crate::{
    geometry::{intersects, Point},
    pins::{Pin, Pins},
    scene::{self, measure::content, Hints, Scene},
    tests::{assert_clean, sample, sample_graphs},
};

fn fresh(graph: &Graph) -> Scene {
    scene::build(graph, Hints::default())
}

fn pin(x: f64, y: f64) -> Pin {
    Pin { x, y, width: None, height: None }
}

/// `graph` without its node `k` and the edges at it.
fn without(graph: &Graph, k: usize) -> Graph {
    let mut smaller = graph.clone();
    let gone = smaller.nodes.remove(k).id;
    let at = |id: &str| id == gone || id.starts_with(&format!("{gone}."));
    smaller.edges.retain(|e| !at(&e.source.node) && !at(&e.target.node));
    smaller
}

#[test]
fn pinned_nodes_are_drawn_where_they_were_put_and_the_others_keep_clear() {
    let mut pinned_somewhere = 0;
    for graph in sample_graphs().iter().filter(|g| g.nodes.len() >= 2) {
        // The first node dragged below and right of the drawing, the last onto the first's
        // old place.
        let before = fresh(graph);
        // Nested components move with their parents only (`move` refuses them).
        let top: Vec<_> = before.nodes.iter().filter(|n| n.parent.is_none()).collect();
        let [first, .., last] = top[..] else { continue };
        let mut pins = Pins::new();
        pins.insert(first.id.clone(), pin(before.width + 35.5, before.height / 2.0));
        pins.insert(last.id.clone(), pin(first.rect.x, first.rect.y));
        let scene = scene::build(graph, Hints { pins: Some(&pins), previous: None, ..Hints::default() });
        for (id, p) in &pins {
            let drawn = scene.nodes.iter().find(|n| &n.id == id).unwrap().rect;
            assert_eq!((drawn.x, drawn.y), (p.x, p.y), "{}: {id} is not where it was put", graph.id);
        }
        assert!(scene.width >= before.width + 35.5 + first.rect.width, "{}: the canvas holds the node", graph.id);
        assert_clean(graph, &scene, false);
        pinned_somewhere += 1;
    }
    assert!(pinned_somewhere > 30);
}

#[test]
fn a_node_added_to_a_drawing_moves_no_other_node() {
    let mut added = 0;
    for graph in sample_graphs().iter().filter(|g| g.nodes.len() >= 3) {
        for k in [graph.nodes.len() / 2, graph.nodes.len() - 1] {
            let previous = fresh(&without(graph, k));
            let scene = scene::build(graph, Hints { pins: None, previous: Some(&previous), ..Hints::default() });
            // The components that hold the new one grow to hold it too; they do not move. What
            // they hold is laid out afresh inside them (the arranging is the top level's).
            let parent = |id: &String| scene.nodes.iter().find(|n| &n.id == id).and_then(|n| n.parent.as_ref());
            let holders: Vec<&String> = std::iter::successors(parent(&graph.nodes[k].id), |p| parent(p)).collect();
            let inside_holder =
                |id: &String| std::iter::successors(parent(id), |p| parent(p)).any(|p| holders.contains(&p));
            for node in previous.nodes.iter().filter(|n| !inside_holder(&n.id)) {
                let now = scene.nodes.iter().find(|n| n.id == node.id).unwrap().rect;
                let (now, was) = if holders.contains(&&node.id) {
                    ((now.x, now.y, 0.0, 0.0), (node.rect.x, node.rect.y, 0.0, 0.0))
                } else {
                    (
                        (now.x, now.y, now.width, now.height),
                        (node.rect.x, node.rect.y, node.rect.width, node.rect.height),
                    )
                };
                assert_eq!(now, was, "{}: {} moved when {} came", graph.id, node.id, graph.nodes[k].id);
            }
            assert_clean(graph, &scene, false);
            added += 1;
        }
    }
    assert!(added > 40);
}

#[test]
fn a_node_keeps_its_place_when_another_is_pinned_onto_it_only_if_there_is_room() {
    // Dragging a node onto another pushes that one aside, to the nearest free place.
    for graph in sample_graphs().iter().filter(|g| g.nodes.len() >= 3) {
        let previous = fresh(graph);
        // Nested components move with their parents only.
        let top: Vec<_> = previous.nodes.iter().filter(|n| n.parent.is_none()).collect();
        let [target, dragged, ..] = top[..] else { continue };
        let mut pins = Pins::new();
        pins.insert(dragged.id.clone(), pin(target.rect.x, target.rect.y));
        let scene = scene::build(graph, Hints { pins: Some(&pins), previous: Some(&previous), ..Hints::default() });
        let moved = scene.nodes.iter().find(|n| n.id == target.id).unwrap().rect;
        assert_ne!(moved, target.rect, "{}", graph.id);
        let dropped = scene.nodes.iter().find(|n| n.id == dragged.id).unwrap().rect;
        assert!(!intersects(moved, dropped), "{}", graph.id);
        assert_clean(graph, &scene, false);
    }
}

#[test]
fn parallel_edges_to_a_moved_node_stay_apart() {
    // Image and Pixel have three edges between them: moved, they run apart, not on one line.
    let graphs = sample_graphs();
    let graph = sample(&graphs, "Associations");
    let before = fresh(graph);
    let image = before.nodes.iter().find(|n| n.id.ends_with("Image")).unwrap();
    let mut pins = Pins::new();
    pins.insert(image.id.clone(), pin(before.width + 60.0, before.height + 40.0));
    let scene = scene::build(graph, Hints { pins: Some(&pins), previous: None, ..Hints::default() });
    assert_clean(graph, &scene, false);
    let between: Vec<&[Point]> = scene.edges.iter().filter(|e| e.source != e.target).map(|e| &e.points[..]).collect();
    assert_eq!(between.len(), 3);
    let distance = |p: Point, route: &[Point]| {
        route.windows(2).map(|s| distance_to_segment(p, s[0], s[1])).fold(f64::INFINITY, f64::min)
    };
    for (i, a) in between.iter().enumerate() {
        for b in &between[i + 1..] {
            // Their middles are far apart (their ends may meet on the boxes).
            let middle = |r: &[Point]| {
                let (p, q) = (r[(r.len() - 1) / 2], r[r.len() / 2]);
                Point { x: (p.x + q.x) / 2.0, y: (p.y + q.y) / 2.0 }
            };
            assert!(distance(middle(a), b) > 20.0, "{a:?} runs along {b:?}");
        }
    }
}

fn distance_to_segment(p: Point, a: Point, b: Point) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let t = (((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy).max(1e-12)).clamp(0.0, 1.0);
    (p.x - a.x - t * dx).hypot(p.y - a.y - t * dy)
}

#[test]
fn a_resized_node_has_its_size_but_never_less_than_its_text() {
    let graph = sample_graphs().into_iter().find(|g| g.nodes.len() >= 3).unwrap();
    let (id, text) = (&graph.nodes[0].id, content(&graph.nodes[0]));
    let mut pins = Pins::new();
    pins.insert(id.clone(), Pin { x: 500.0, y: 20.0, width: Some(text.width + 100.0), height: Some(1.0) });
    let scene = scene::build(&graph, Hints { pins: Some(&pins), previous: None, ..Hints::default() });
    let rect = scene.nodes[0].rect;
    assert_eq!((rect.width, rect.height), (text.width + 100.0, text.height));
    assert_clean(&graph, &scene, false);
}

#[test]
fn a_previous_scene_is_followed_only_while_it_holds_half_the_nodes() {
    let graph = sample_graphs().into_iter().find(|g| g.nodes.len() >= 6).unwrap();
    let mut little = graph.clone();
    little.nodes.truncate(2);
    // Its two nodes somewhere a fresh layout would not put them.
    let mut previous = fresh(&little);
    for node in &mut previous.nodes {
        node.rect.x += 400.0;
    }
    assert_eq!(
        scene::build(&graph, Hints { pins: None, previous: Some(&previous), ..Hints::default() }),
        fresh(&graph)
    );
    // A previous scene of the same nodes is this one's layout again.
    let again = fresh(&graph);
    assert_eq!(scene::build(&graph, Hints { pins: None, previous: Some(&again), ..Hints::default() }), again);
}

/// A pipeline of `n` mean filters after a camera, each bound to the next, the last to a viewer
/// (the seed's component classes, listing 18).
fn long_pipeline(n: usize) -> Graph {
    let seed = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../samples/seed/listing26_component_classes_example.gudsl");
    let classes = std::fs::read_to_string(&seed).unwrap();
    let mut text = String::from("ComponentInstanceDiagram LongPipeline\n{\n");
    let port = |k: usize| {
        if k == 0 {
            "CameraPortInstance"
        } else if k > n {
            "ViewerPortInstance"
        } else {
            "FilterPortInstance"
        }
    };
    for k in 0..=n + 1 {
        let (class, ports) = match k {
            0 => ("Camera", "CameraPortInstance : CameraPort ( provider ImageOut = IImageProvider(); );"),
            k if k > n => ("Viewer", "ViewerPortInstance : ViewerPort ( processor ImageIn = IImageProcessor(); );"),
            _ => ("MeanFilter", "FilterPortInstance : FilterPort ( processor ImageIn = IImageProcessor(); provider ImageOut = IImageProvider(); );"),
        };
        text += &format!("    I{k} instantiates ComponentClassDefinitions.{class} ( )\n    {{\n        {ports}\n");
        if k <= n {
            text += &format!("        [ source {}.ImageOut ==> target I{}.{}.ImageIn ]\n", port(k), k + 1, port(k + 1));
        }
        text += "    }\n";
    }
    text += "}\n";
    let (host, files) =
        gudsl_model::AnalysisHost::with_files([(seed.display().to_string(), classes), ("pipeline.gudsl".into(), text)]);
    let graphs = host.analysis().graphs(files[1]).unwrap().to_vec();
    graphs.into_iter().next().expect("the pipeline's diagram")
}

#[test]
fn a_long_pipeline_fits_the_screen_unless_the_user_pinned_a_node() {
    let graph = long_pipeline(40);
    assert_eq!(graph.nodes.len(), 42);
    let scene = fresh(&graph);
    let aspect = scene.width / scene.height;
    assert!((1.6 / 1.5..1.6 * 1.5).contains(&aspect), "{} x {}", scene.width, scene.height);
    assert_clean(&graph, &scene, false);
    // Pinned, it is drawn as its ranks come, in one long row.
    let mut pins = Pins::new();
    pins.insert("I0".into(), pin(20.0, 40.0));
    let pinned = scene::build(&graph, Hints { pins: Some(&pins), ..Hints::default() });
    assert!(pinned.width / pinned.height > 10.0, "{} x {}", pinned.width, pinned.height);
    assert_clean(&graph, &pinned, false);
}

#[test]
fn a_class_added_to_a_narrowed_drawing_gets_routes_that_pass_no_box() {
    // 200 classes narrowed to an A4 page (the reference picture's model), drawn without their
    // last class, then with it as the editor draws it: the others kept where they were.
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference/models/Classes200.gudsl");
    let text = std::fs::read_to_string(&path).unwrap();
    let (host, files) = gudsl_model::AnalysisHost::with_files([(path.display().to_string(), text)]);
    let graph = host.analysis().graphs(files[0]).unwrap()[0].clone();
    let page = crate::layout::Page::paper("A4").unwrap();
    let mut rerouted = 0;
    for k in [graph.nodes.len() - 1, graph.nodes.len() / 2] {
        let previous = scene::build(&without(&graph, k), Hints { page, ..Hints::default() });
        let scene = scene::build(&graph, Hints { previous: Some(&previous), page, ..Hints::default() });
        let added = &graph.nodes[k].id;
        let rect = |id: &str| scene.nodes.iter().find(|n| n.id == id).unwrap().rect;
        for edge in scene.edges.iter().filter(|e| &e.source == added || &e.target == added) {
            for node in scene.nodes.iter().filter(|n| n.id != edge.source && n.id != edge.target) {
                let through = edge.points.windows(2).any(|s| crate::geometry::segment_meets_box(s[0], s[1], node.rect));
                assert!(!through, "{} -> {} passes {}", edge.source, edge.target, node.id);
            }
            assert!(rect(&edge.source).width > 0.0);
            rerouted += 1;
        }
    }
    assert!(rerouted >= 2);
}
