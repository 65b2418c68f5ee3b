//! Semantic check benchmark on a generated 50 000-line, 200-file workspace: a cold full check,
//! a re-check after typing one character inside a method body, and after renaming a class that
//! one other file uses. Median and p95 of the runs, printed as a table.
//!
//! `cargo bench -p gudsl-model --bench check`

use std::time::{Duration, Instant};

use gudsl_model::{AnalysisHost, FileId};

fn stats(mut samples: Vec<Duration>) -> (f64, f64) {
    samples.sort();
    let at = |p: f64| samples[((samples.len() - 1) as f64 * p).round() as usize].as_secs_f64() * 1e3;
    (at(0.5), at(0.95))
}

fn load(files: &[gudsl_model::synth::SynthFile]) -> (AnalysisHost, Vec<FileId>) {
    AnalysisHost::with_files(files.iter().map(|f| (f.path.clone(), f.text.clone())))
}

fn check_all(host: &AnalysisHost, inputs: &[FileId]) -> usize {
    let analysis = host.analysis();
    inputs.iter().map(|&f| analysis.diagnostics(f).expect("nothing changes the host meanwhile").0.len()).sum()
}

fn main() {
    let files = gudsl_model::synth::workspace(200, 50_000);
    let lines: usize = files.iter().map(|f| f.text.lines().count()).sum();
    println!("workspace: {} files, {lines} lines", files.len());
    println!("{:<52} {:>10} {:>10} {:>6}", "case", "median", "p95", "runs");

    let cold: Vec<Duration> = (0..10)
        .map(|_| {
            let start = Instant::now();
            let (host, inputs) = load(&files);
            let n = check_all(&host, &inputs);
            assert_eq!(n, 0, "the generated workspace must check clean");
            start.elapsed()
        })
        .collect();
    let (m, p) = stats(cold);
    println!("{:<52} {m:>8.1}ms {p:>8.1}ms {:>6}", "cold: load + parse + check all 200 files", 10);

    // Typing inside a method body of file 100: one character more, then one less, alternating.
    let (mut host, inputs) = load(&files);
    check_all(&host, &inputs);
    let target = inputs[100];
    let original = files[100].text.clone();
    let anchor = original.find("var int acc = a * ").expect("a method body") + "var int acc = a * ".len();
    let body_edit: Vec<Duration> = (0..50)
        .map(|i| {
            let text =
                if i % 2 == 0 { format!("{}1{}", &original[..anchor], &original[anchor..]) } else { original.clone() };
            let start = Instant::now();
            host.set_file_text(target, text);
            check_all(&host, &inputs);
            start.elapsed()
        })
        .collect();
    let (m, p) = stats(body_edit);
    println!("{:<52} {m:>8.2}ms {p:>8.2}ms {:>6}", "one-character edit in a method body, re-check all", 50);

    // Renaming class C100_1 (used by no other file) and Image100 (used by file 99).
    for (class, what) in
        [("C100_1", "rename a class no other file uses"), ("Image100", "rename a class another file uses")]
    {
        host.set_file_text(target, original.clone());
        check_all(&host, &inputs);
        let renamed = original.replace(&format!("public class {class}"), &format!("public class {class}X"));
        let rename: Vec<Duration> = (0..30)
            .map(|i| {
                let text = if i % 2 == 0 { renamed.clone() } else { original.clone() };
                let start = Instant::now();
                host.set_file_text(target, text);
                check_all(&host, &inputs);
                start.elapsed()
            })
            .collect();
        let (m, p) = stats(rename);
        println!("{:<52} {m:>8.2}ms {p:>8.2}ms {:>6}", format!("{what}, re-check all"), 30);
    }
}
