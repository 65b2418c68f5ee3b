//! A change to the host stops the work of older snapshots part-way, also work that asks no
//! query for a long time (the outline and the semantic tokens of a big file): the change does
//! not wait for it to finish.

use std::{
    sync::mpsc,
    thread,
    time::{Duration, Instant},
};

use gudsl_model::{Analysis, AnalysisHost, Cancellable, FileId};

/// A class diagram of `classes` classes, each with two fields.
fn big_file(classes: usize) -> String {
    let mut text = String::from("ClassDiagram Big\n{\n");
    for i in 0..classes {
        text.push_str(&format!("    public class L{i} {{ public int f{i}; public L{} g{i}; }}\n", i / 2));
    }
    text.push_str("}\n");
    text
}

/// Runs `work` to completion twice (the first memoises every query it asks; the second is timed),
/// then again on a new snapshot while the host changes `other`. Returns how long a whole run
/// takes, what the interrupted run returned, and how long the change waited for it.
fn change_during<T: Send + 'static>(
    mut host: AnalysisHost,
    other: FileId,
    work: impl Fn(&Analysis) -> Cancellable<T> + Send + Clone + 'static,
) -> (Duration, Cancellable<T>, Duration) {
    work(&host.analysis()).expect("nothing changes during the first run");
    let start = Instant::now();
    work(&host.analysis()).expect("nothing changes during the second run");
    let whole = start.elapsed();
    let analysis = host.analysis();
    let (started, running) = mpsc::channel();
    let worker = thread::spawn(move || {
        started.send(()).unwrap();
        work(&analysis)
    });
    running.recv().unwrap();
    thread::sleep(whole / 10);
    let start = Instant::now();
    host.set_file_text(other, "ClassDiagram Other { public class Changed { } }\n".to_string());
    let waited = start.elapsed();
    (whole, worker.join().unwrap(), waited)
}

fn assert_stopped<T>((whole, outcome, waited): (Duration, Cancellable<T>, Duration)) {
    assert!(whole > Duration::from_millis(50), "the work must be long enough to be interrupted ({whole:?})");
    assert!(outcome.is_err(), "the running work finished on a stale snapshot ({whole:?} for a whole run)");
    assert!(waited < whole / 2, "the change waited {waited:?} for work that takes {whole:?}");
}

fn host_with(big: String) -> (AnalysisHost, Vec<FileId>) {
    AnalysisHost::with_files([
        ("big.gudsl".to_string(), big),
        ("other.gudsl".to_string(), "ClassDiagram Other { }\n".to_string()),
    ])
}

#[test]
fn a_change_stops_the_outline_of_a_big_file() {
    let (host, files) = host_with(big_file(30_000));
    let big = files[0];
    assert_stopped(change_during(host, files[1], move |a| a.document_symbols(big).map(|s| s.len())));
}

#[test]
fn a_change_stops_the_semantic_tokens_of_a_big_file() {
    let (host, files) = host_with(big_file(30_000));
    let big = files[0];
    assert_stopped(change_during(host, files[1], move |a| a.semantic_tokens(big).map(|t| t.len())));
}
