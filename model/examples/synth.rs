//! Writes a generated GU-DSL workspace to disk, for benchmarks and manual tests:
//! `cargo run -p gudsl-model --example synth -- DIR [FILES] [LINES]` (default 200 files, 50 000 lines).
fn main() {
    let mut args = std::env::args().skip(1);
    let dir = std::path::PathBuf::from(args.next().expect("usage: synth DIR [FILES] [LINES]"));
    let files: usize = args.next().map_or(200, |a| a.parse().expect("FILES is a number"));
    let lines: usize = args.next().map_or(50_000, |a| a.parse().expect("LINES is a number"));
    std::fs::create_dir_all(&dir).expect("create the output folder");
    let workspace = gudsl_model::synth::workspace(files, lines);
    for file in &workspace {
        std::fs::write(dir.join(&file.path), &file.text).expect("write a file");
    }
    let total: usize = workspace.iter().map(|f| f.text.lines().count()).sum();
    println!("wrote {} files, {total} lines to {}", workspace.len(), dir.display());
}
