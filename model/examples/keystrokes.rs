//! The workspace-scale keystroke loop without the protocol, for profiling (`perf record`):
//! `cargo run --release -p gudsl-model --example keystrokes -- [FILES] [KEYSTROKES]` builds the
//! linked workspace (`synth::linked_workspace`), checks every file, then replays the blocks of
//! four declaration edits of `tests/lsp/bench.py linked` in `f001.gudsl`, asking after each the
//! edited file's diagnostics and then every other file's, and prints the time of both phases.
use std::time::Instant;

use gudsl_model::{text::ColumnUnit, AnalysisHost, FileId, LineColEdit};

/// The edited file's diagnostics: a function of its own, so a profile tells the phases apart.
#[inline(never)]
fn edited_phase(analysis: &gudsl_model::Analysis, file: FileId) -> usize {
    analysis.diagnostics(file).expect("not cancelled").0.len()
}

fn main() {
    let mut args = std::env::args().skip(1);
    let files: usize = args.next().map_or(200, |a| a.parse().expect("FILES is a number"));
    let keystrokes: usize = args.next().map_or(200, |a| a.parse().expect("KEYSTROKES is a number"));
    let workspace = gudsl_model::synth::linked_workspace(files);
    let (mut host, ids) = AnalysisHost::with_files(workspace.iter().map(|f| (f.path.clone(), f.text.clone())));
    let check_all = |host: &AnalysisHost, first: FileId| {
        let analysis = host.analysis();
        let started = Instant::now();
        let errors = edited_phase(&analysis, first);
        let edited = started.elapsed();
        if std::env::var_os("EDITED_ONLY").is_none() {
            for &file in &ids {
                analysis.diagnostics(file).expect("not cancelled");
            }
        }
        (errors, edited, started.elapsed())
    };
    let edited = ids[1];
    let started = Instant::now();
    check_all(&host, edited);
    println!("cold check of {files} files: {:?}", started.elapsed());
    let (mut first, mut all) = (Vec::new(), Vec::new());
    let mut text = host.file_text(edited).to_string();
    for keystroke in 0..keystrokes {
        let k = 1 + (keystroke / 4) % 19;
        let class = format!("public class E1_{k}");
        let class_end =
            text.find(&format!("{class} ")).or_else(|| text.find(&format!("{class}Z "))).unwrap() + class.len();
        let type_end = class_end
            + text[class_end..]
                .find("public String")
                .unwrap_or_else(|| text[class_end..].find("public StringX").expect("the field's type"))
            + "public String".len();
        match keystroke % 4 {
            0 => text.insert(type_end, 'X'),
            1 => text.insert(class_end, 'Z'),
            2 => drop(text.remove(type_end)),
            _ => drop(text.remove(class_end)),
        }
        host.edit_file(edited, vec![LineColEdit { range: None, text: text.clone() }], ColumnUnit::Utf8)
            .expect("a full replacement");
        let (_, one, every) = check_all(&host, edited);
        first.push(one);
        all.push(every);
    }
    for (what, mut times) in [("edited file", first), ("every file", all)] {
        times.sort();
        let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize];
        println!("{what}: p50 {:?}, p95 {:?}, max {:?}", at(0.5), at(0.95), at(1.0));
    }
}
