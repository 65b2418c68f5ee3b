//! Tests of fresh layouts that keep the rows of the layout before (`layout::seeded`): a layout
//! from its own rows is the same drawing, for every sample diagram; a class added to the
//! 200-class A4 model moves the others by a few points where a layout without the rows moves
//! them by hundreds, with no more crossings; a wrapped pipeline keeps its rows' columns and
//! ranks' places; rows that name what is gone, or say nothing useful, are no error.

use gudsl_model::graph::Graph;

use crate::{
    pins::Rows,
    scene::{self, Hints, Scene},
    tests::{assert_clean, sample_graphs},
};

/// The mean distance the nodes of `before` that `after` still has moved, less the median shift
/// (as `research/layout_metrics.py --stability` scores it).
fn mean_displacement(before: &Scene, after: &Scene) -> f64 {
    let moved: Vec<(f64, f64)> = before
        .nodes
        .iter()
        .filter_map(|b| after.nodes.iter().find(|a| a.id == b.id).map(|a| (a.rect.x - b.rect.x, a.rect.y - b.rect.y)))
        .collect();
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let (mx, my) = (median(moved.iter().map(|m| m.0).collect()), median(moved.iter().map(|m| m.1).collect()));
    moved.iter().map(|(dx, dy)| (dx - mx).hypot(dy - my)).sum::<f64>() / moved.len() as f64
}

/// The 200-class model of the reference picture `Classes200` (an inheritance forest and
/// associations with role names and multiplicities).
fn classes200() -> Graph {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference/models/Classes200.gudsl");
    let text = std::fs::read_to_string(&path).unwrap();
    let (host, files) = gudsl_model::AnalysisHost::with_files([(path.display().to_string(), text)]);
    host.analysis().graphs(files[0]).unwrap()[0].clone()
}

/// The number of pairs of edge segments that cross (ends shared aside).
fn crossings(scene: &Scene) -> usize {
    let segments: Vec<(usize, crate::geometry::Point, crate::geometry::Point)> = scene
        .edges
        .iter()
        .enumerate()
        .flat_map(|(e, edge)| edge.points.windows(2).map(move |s| (e, s[0], s[1])))
        .collect();
    let cross = |(a, b): (crate::geometry::Point, crate::geometry::Point),
                 (c, d): (crate::geometry::Point, crate::geometry::Point)| {
        let side = |p: crate::geometry::Point, q: crate::geometry::Point, r: crate::geometry::Point| {
            (q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x)
        };
        side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0
    };
    let mut count = 0;
    for (i, s) in segments.iter().enumerate() {
        for t in &segments[i + 1..] {
            if s.0 != t.0 && cross((s.1, s.2), (t.1, t.2)) {
                count += 1;
            }
        }
    }
    count
}

#[test]
fn a_layout_from_its_own_rows_is_the_same_drawing() {
    for graph in &sample_graphs() {
        let first = scene::build(graph, Hints::default());
        let again = scene::build(graph, Hints { rows: Some(&first.rows), ..Hints::default() });
        assert_eq!(again, first, "{}", graph.id);
    }
    let page = crate::layout::Page::paper("A4").unwrap();
    let graph = classes200();
    let first = scene::build(&graph, Hints { page, ..Hints::default() });
    assert_eq!(scene::build(&graph, Hints { rows: Some(&first.rows), page, ..Hints::default() }), first);
}

#[test]
fn a_class_added_to_a_fresh_layout_that_keeps_the_rows_moves_the_others_little() {
    let page = crate::layout::Page::paper("A4").unwrap();
    let graph = classes200();
    let mut smaller = graph.clone();
    let gone = smaller.nodes.pop().unwrap().id;
    smaller.edges.retain(|e| e.source.node != gone && e.target.node != gone);
    let before = scene::build(&smaller, Hints { page, ..Hints::default() });
    let kept = scene::build(&graph, Hints { rows: Some(&before.rows), page, ..Hints::default() });
    let afresh = scene::build(&graph, Hints { page, ..Hints::default() });
    let (kept_moved, afresh_moved) = (mean_displacement(&before, &kept), mean_displacement(&before, &afresh));
    assert!(kept_moved < 5.0 && afresh_moved > 10.0 * kept_moved, "kept {kept_moved}, afresh {afresh_moved}");
    assert!(crossings(&kept) <= crossings(&afresh) * 11 / 10, "{} vs {}", crossings(&kept), crossings(&afresh));
    assert_clean(&graph, &kept, false);
}

#[test]
fn a_wrapped_pipeline_with_a_node_added_keeps_its_columns_and_its_ranks_places() {
    let before = scene::build(&crate::tests_bindings::reference_pipeline(), Hints::default());
    // Wrapped: the rows mark where the second column (a row of the drawing) starts, and every
    // row where its band is.
    let marks =
        |mark: &str| before.rows.iter().filter(|row| row.iter().any(|e| e.split(' ').next() == Some(mark))).count();
    assert_eq!((marks("|"), marks("=")), (1, before.rows.len()));
    // One filter more, bound from a filter that feeds the last viewer: in the viewer's rank, and
    // wider than the viewer (that rank's band grows: the viewer, centred in it, moves 34 pt along
    // the ranks, 42 without the bands kept — the gap before it has too little room to give).
    let filter = "MeanFilter ( )\n    {\n        FilterPortInstance : FilterPort ( processor ImageIn = IImageProcessor(); provider ImageOut = IImageProvider(); );\n";
    let graph = crate::tests_bindings::edited_pipeline(&|text| {
        let bound = text.replacen(
            "[ source FilterPortInstance.ImageOut ==> target I59.ViewerPortInstance.ImageIn ]",
            "[ source FilterPortInstance.ImageOut ==> target I59.ViewerPortInstance.ImageIn ]\n        [ source FilterPortInstance.ImageOut ==> target X.FilterPortInstance.ImageIn ]",
            1,
        );
        let end = bound.trim_end().strip_suffix('}').unwrap().to_string();
        format!("{end}    X instantiates ComponentClassDefinitions.{filter}    }}\n}}\n")
    });
    assert_eq!(graph.nodes.len(), 61);
    let kept = scene::build(&graph, Hints { rows: Some(&before.rows), ..Hints::default() });
    let moved = mean_displacement(&before, &kept);
    assert!(moved < 1.0, "{moved}");
    assert_clean(&graph, &kept, false);
}

#[test]
fn rows_naming_what_is_gone_or_nothing_useful_are_no_error() {
    let graph = classes200();
    let fresh = scene::build(&graph, Hints::default());
    let odd: Rows = vec![
        vec!["Nowhere.Gone 12".into(), "".into(), " ".into(), "A->B#9 NaN".into()],
        vec![],
        vec![format!("{} inf", graph.nodes[0].id), format!("{} -1e308", graph.nodes[1].id)],
    ];
    // Too few nodes seated to keep: laid out afresh.
    assert_eq!(
        scene::build(&graph, Hints { rows: Some(&odd), ..Hints::default() }),
        Scene { rows: fresh.rows.clone(), ..fresh.clone() }
    );
    // A million rows between the rows of a layout — of ids gone, of an edge, of a box already
    // placed — are no million ranks: the same drawing.
    let edge = fresh.rows.iter().flatten().find(|e| e.contains("->")).unwrap().clone();
    let first_box = fresh.rows[0][0].clone();
    let mut padded: Rows = fresh.rows.clone();
    let filler = [vec!["Nowhere.Gone 1".to_string()], vec![edge], vec![first_box]];
    padded.splice(1..1, filler.iter().cycle().take(1_000_000).cloned());
    let started = std::time::Instant::now();
    assert_eq!(scene::build(&graph, Hints { rows: Some(&padded), ..Hints::default() }), fresh);
    assert!(started.elapsed().as_secs() < 20, "{:?}", started.elapsed());
    // Rows claiming every band far down: the ranks stay near where they would be.
    let far: Rows = fresh
        .rows
        .iter()
        .map(|row| row.iter().map(|e| if e.starts_with("= ") { "= 9999999".to_string() } else { e.clone() }).collect())
        .collect();
    let scene = scene::build(&graph, Hints { rows: Some(&far), ..Hints::default() });
    assert!(scene.height < 2.0 * fresh.height, "{} against {}", scene.height, fresh.height);
    // Every node seated in one row, in reverse: kept where the edges allow, still clean.
    let reversed: Rows = vec![graph.nodes.iter().rev().map(|n| format!("{} 0", n.id)).collect()];
    let scene = scene::build(&graph, Hints { rows: Some(&reversed), ..Hints::default() });
    assert_clean(&graph, &scene, false);
}
