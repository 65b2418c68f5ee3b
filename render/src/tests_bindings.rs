//! Tests of bindings drawn along a fresh layout (`scene::channels`): on the reference pipeline
//! of 60 instances, no two bindings touch (those at one port leave it side by side) and they
//! cross no more than the layout's order makes them; arranged around a previous scene, the
//! bindings between nodes that stayed keep their routes.

use gudsl_model::graph::Graph;

use crate::{
    geometry::Point,
    layout::tracks::TRACK,
    scene::{self, Hints, Scene},
    tests::assert_clean,
};

/// The reference pipeline (`tests/reference/models/LongPipeline.gudsl`) with the seed's
/// component classes.
pub(crate) fn reference_pipeline() -> Graph {
    edited_pipeline(&str::to_string)
}

/// The reference pipeline, its text edited by `edit`.
pub(crate) fn edited_pipeline(edit: &dyn Fn(&str) -> String) -> Graph {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |path: std::path::PathBuf| (path.display().to_string(), std::fs::read_to_string(&path).unwrap());
    let pipeline = read(root.join("tests/reference/models/LongPipeline.gudsl"));
    let (host, files) = gudsl_model::AnalysisHost::with_files([
        read(root.join("../samples/seed/listing26_component_classes_example.gudsl")),
        (pipeline.0, edit(&pipeline.1)),
    ]);
    let graphs = host.analysis().graphs(files[1]).unwrap().to_vec();
    graphs.into_iter().next().expect("the pipeline's diagram")
}

/// Where two axis-parallel routes meet: (crossings, touches), a touch being a segment's end
/// on the other route (where a tree's branch would leave its trunk); layout_metrics.py counts
/// both as crossings.
pub(crate) fn meetings(a: &[Point], b: &[Point]) -> (usize, usize) {
    let (mut crossings, mut touches) = (0, 0);
    for s in a.windows(2) {
        for t in b.windows(2) {
            let (vertical, level) = if s[0].x == s[1].x { (s, t) } else { (t, s) };
            if vertical[0].x != vertical[1].x || level[0].y != level[1].y {
                continue; // parallel
            }
            let (x, y) = (vertical[0].x, level[0].y);
            let within = |v: f64, a: f64, b: f64| a.min(b) <= v && v <= a.max(b);
            let inside = |v: f64, a: f64, b: f64| a.min(b) < v && v < a.max(b);
            if within(x, level[0].x, level[1].x) && within(y, vertical[0].y, vertical[1].y) {
                if inside(x, level[0].x, level[1].x) && inside(y, vertical[0].y, vertical[1].y) {
                    crossings += 1;
                } else {
                    touches += 1;
                }
            }
        }
    }
    (crossings, touches)
}

/// Over every pair of the scene's routes, where they meet: (crossings, touches).
fn all_meetings(scene: &Scene) -> (usize, usize) {
    let routes: Vec<&[Point]> = scene.edges.iter().map(|e| e.points.as_slice()).collect();
    let pairs = routes.iter().enumerate().flat_map(|(i, a)| routes[i + 1..].iter().map(move |b| meetings(a, b)));
    pairs.fold((0, 0), |(c, t), (pc, pt)| (c + pc, t + pt))
}

#[test]
fn bindings_of_a_fresh_pipeline_neither_touch_nor_cross_where_the_layout_does_not() {
    let graph = reference_pipeline();
    assert_eq!(graph.nodes.len(), 60);
    let scene = scene::build(&graph, Hints::default());
    assert_clean(&graph, &scene, false);
    for edge in &scene.edges {
        assert!(edge.points.windows(2).all(|s| s[0].x == s[1].x || s[0].y == s[1].y), "{} slants", edge.id);
    }
    let (crossings, touches) = all_meetings(&scene);
    assert_eq!(touches, 0);
    // Where the layout's order crosses them: three times (routed around the boxes instead, as
    // before the bindings followed the layout, they cross 8 times and touch 104 times).
    assert!(crossings <= 3, "{crossings} crossings");
}

#[test]
fn the_layout_gives_each_gap_room_for_its_tracks() {
    // Upright stretches of two bindings side by side (their heights overlapping) run a track's
    // width apart: the gaps between the ranks were sized for them, none squeezed.
    let graph = reference_pipeline();
    let scene = scene::build(&graph, Hints::default());
    let uprights: Vec<(usize, f64, f64, f64)> = (scene.edges.iter().enumerate())
        .flat_map(|(k, e)| e.points.windows(2).map(move |s| (k, s[0], s[1])))
        .filter(|(_, a, b)| a.x == b.x && a.y != b.y)
        .map(|(k, a, b)| (k, a.x, a.y.min(b.y), a.y.max(b.y)))
        .collect();
    assert!(uprights.len() > 40, "{}", uprights.len());
    for (i, &(k, x, top, bottom)) in uprights.iter().enumerate() {
        for &(l, x2, top2, bottom2) in &uprights[i + 1..] {
            if k != l && top <= bottom2 && top2 <= bottom {
                assert!(
                    (x - x2).abs() >= TRACK - 1e-6,
                    "{} and {} {} pt apart",
                    scene.edges[k].id,
                    scene.edges[l].id,
                    (x - x2).abs()
                );
            }
        }
    }
}

#[test]
fn arranged_around_the_scene_before_the_bindings_between_nodes_that_stayed_keep_their_routes() {
    let graph = reference_pipeline();
    let before = scene::build(&graph, Hints::default());
    let again = scene::build(&graph, Hints { previous: Some(&before), ..Hints::default() });
    for (was, is) in before.nodes.iter().zip(&again.nodes) {
        assert_eq!(was.rect, is.rect, "{}", was.id);
    }
    for (was, is) in before.edges.iter().zip(&again.edges) {
        assert_eq!(was.points, is.points, "{}", was.id);
    }
}
