//! Semantic check benchmark on a generated 50 000-line, 200-file workspace: a cold full check,
//! a re-check after typing one character inside a method body, and after renaming a class that
//! one other file uses. Median and p95 of the runs, printed as a table. Then the check's growth
//! in the size of one diagram (10 000 to 100 000 nodes) and of one file (1 to 10 MB of small
//! diagrams): each must stay linear, the largest under 2 s.
//!
//! `cargo bench -p gudsl-model --bench check` (`-- scaling [long|many]` runs only the growth cases)

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
    if std::env::args().all(|a| a != "scaling") {
        workspace_cases();
    }
    scaling();
}

/// A cold check of one generated file, in seconds: the median of three.
fn cold_check(file: &gudsl_model::synth::SynthFile) -> f64 {
    let runs = (0..3).map(|_| {
        let start = Instant::now();
        let (host, inputs) = load(std::slice::from_ref(file));
        let n = check_all(&host, &inputs);
        assert_eq!(n, 0, "{} must check clean", file.path);
        start.elapsed()
    });
    stats(runs.collect()).0 / 1e3
}

/// The check's time against the size of one diagram and of one file.
fn scaling() {
    println!("{:<52} {:>10} {:>12}", "growth", "seconds", "µs per unit");
    let only = |case: &str| std::env::args().all(|a| a != "long" && a != "many") || std::env::args().any(|a| a == case);
    for nodes in [10_000, 20_000, 40_000, 100_000].into_iter().filter(|_| only("long")) {
        let seconds = cold_check(&gudsl_model::synth::long_activity(nodes));
        println!(
            "{:<52} {seconds:>9.2}s {:>11.1}",
            format!("one activity diagram of {nodes} nodes"),
            seconds * 1e6 / nodes as f64
        );
    }
    for megabytes in [1, 2, 5, 10].into_iter().filter(|_| only("many")) {
        let file = gudsl_model::synth::many_diagrams(megabytes << 20);
        let diagrams = file.text.matches("ActivityDiagram").count();
        let seconds = cold_check(&file);
        println!(
            "{:<52} {seconds:>9.2}s {:>11.1}",
            format!("one {megabytes} MB file of {diagrams} small diagrams"),
            seconds * 1e6 / diagrams as f64
        );
    }
}

fn workspace_cases() {
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
