//! Times the layered layout on generated graphs of 10, 50 and 200 boxes (release build):
//! `cargo run --release -p gudsl-render --example layout_timing`.
use gudsl_render::layout::{layered, LayoutInput, LayoutNode, Spacing};

fn main() {
    for n in [10usize, 50, 200] {
        let nodes: Vec<LayoutNode> =
            (0..n).map(|i| LayoutNode { width: 80.0 + (i % 5) as f64 * 15.0, height: 40.0 }).collect();
        let edges: Vec<(usize, usize)> =
            (1..n).map(|i| ((i * 7) % i, i)).chain((0..n / 4).map(|i| (i * 3 % n, (i * 11 + 5) % n))).collect();
        let input = LayoutInput { nodes, edges, ..Default::default() };
        let start = std::time::Instant::now();
        let runs = 5;
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
