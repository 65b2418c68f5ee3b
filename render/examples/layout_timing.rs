//! Times the layout, two ways (release build): with no arguments, the layered layout alone on
//! generated graphs of 10 to 2 000 boxes; with `.gudsl` files, each of their diagrams drawn
//! whole (`scene::build`: measuring, layout, routing, labels), its geometry written beside it as
//! `<diagram>.json` (what `gudsl render --format layout-json` writes) for
//! `research/layout_metrics.py`:
//! `cargo run --release -p gudsl-render --example layout_timing [-- FILE.gudsl…]`.
use gudsl_model::AnalysisHost;
use gudsl_render::layout::{layered, LayoutInput, LayoutNode, Spacing};
use gudsl_render::scene::{self, Hints};

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        generated();
    } else {
        diagrams(files);
    }
}

fn generated() {
    for n in [10usize, 50, 200, 1000, 2000] {
        let nodes: Vec<LayoutNode> =
            (0..n).map(|i| LayoutNode { width: 80.0 + (i % 5) as f64 * 15.0, height: 40.0 }).collect();
        let edges: Vec<(usize, usize)> =
            (1..n).map(|i| ((i * 7) % i, i)).chain((0..n / 4).map(|i| (i * 3 % n, (i * 11 + 5) % n))).collect();
        let input = LayoutInput { nodes, edges, ..Default::default() };
        let start = std::time::Instant::now();
        let runs = if n > 200 { 1 } else { 5 };
        for _ in 0..runs {
            std::hint::black_box(layered(&input, Spacing::default()));
        }
        println!(
            "{n:>4} boxes, {:>4} edges: {:>8.2} ms per layout",
            input.edges.len(),
            start.elapsed().as_secs_f64() * 1e3 / runs as f64
        );
    }
}

fn diagrams(paths: Vec<String>) {
    let files: Vec<(String, String)> = paths
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
            (path, text)
        })
        .collect();
    let (host, ids) = AnalysisHost::with_files(files.clone());
    let analysis = host.analysis();
    for ((path, _), &file) in files.iter().zip(&ids) {
        for graph in analysis.graphs(file).expect("not cancelled").iter() {
            let start = std::time::Instant::now();
            let scene = scene::build(graph, Hints { pins: None, previous: None, ..Hints::default() });
            let took = start.elapsed().as_secs_f64() * 1e3;
            let out = std::path::Path::new(path).with_file_name(format!("{}.json", graph.id));
            std::fs::write(&out, gudsl_render::json::write(&scene)).expect("written");
            println!("{}: {} nodes, {took:.0} ms -> {}", graph.id, graph.nodes.len(), out.display());
        }
    }
}
