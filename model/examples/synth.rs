//! Writes a generated GU-DSL workspace to disk, for benchmarks and manual tests:
//! `cargo run -p gudsl-model --example synth -- DIR [FILES] [LINES]` (default 200 files, 50 000
//! lines), or `… -- --linked DIR [FILES]` for the densely linked shape of the Langium anchor
//! (default 200 files of about 260 lines).
fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let linked = args.first().is_some_and(|a| a == "--linked");
    if linked {
        args.remove(0);
    }
    let mut args = args.into_iter();
    let dir = std::path::PathBuf::from(args.next().expect("usage: synth [--linked] DIR [FILES] [LINES]"));
    let files: usize = args.next().map_or(200, |a| a.parse().expect("FILES is a number"));
    let workspace = if linked {
        gudsl_model::synth::linked_workspace(files)
    } else {
        let lines: usize = args.next().map_or(50_000, |a| a.parse().expect("LINES is a number"));
        gudsl_model::synth::workspace(files, lines)
    };
    std::fs::create_dir_all(&dir).expect("create the output folder");
    for file in &workspace {
        std::fs::write(dir.join(&file.path), &file.text).expect("write a file");
    }
    let total: usize = workspace.iter().map(|f| f.text.lines().count()).sum();
    println!("wrote {} files, {total} lines to {}", workspace.len(), dir.display());
}
