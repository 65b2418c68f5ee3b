//! Parse benchmark: lexing and parsing a generated 50 000-line, 200-file workspace, printed as
//! a table (median and p95 of 15 runs, throughput in MB/s).
//!
//! `cargo bench -p gudsl-model --bench parse`

use std::time::{Duration, Instant};

fn percentile(samples: &mut [Duration], p: f64) -> Duration {
    samples.sort();
    samples[((samples.len() - 1) as f64 * p).round() as usize]
}

fn measure(runs: usize, mut f: impl FnMut()) -> (Duration, Duration) {
    f(); // warm-up
    let mut samples: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    (percentile(&mut samples, 0.5), percentile(&mut samples, 0.95))
}

fn main() {
    let files = gudsl_model::synth::workspace(200, 50_000);
    let bytes: usize = files.iter().map(|f| f.text.len()).sum();
    let lines: usize = files.iter().map(|f| f.text.lines().count()).sum();
    let one_file = files.iter().map(|f| f.text.as_str()).collect::<String>();
    let mb = bytes as f64 / 1e6;
    println!("workspace: {} files, {lines} lines, {:.2} MB", files.len(), mb);
    println!("{:<40} {:>10} {:>10} {:>10}", "case", "median", "p95", "MB/s");
    let row = |name: &str, (median, p95): (Duration, Duration), size_mb: f64| {
        println!(
            "{name:<40} {:>8.2}ms {:>8.2}ms {:>10.1}",
            median.as_secs_f64() * 1e3,
            p95.as_secs_f64() * 1e3,
            size_mb / median.as_secs_f64()
        );
    };
    row(
        "lex only (200 files)",
        measure(15, || {
            for f in &files {
                std::hint::black_box(gudsl_model::syntax::lexer::lex(&f.text));
            }
        }),
        mb,
    );
    row(
        "lex + parse + tree (200 files)",
        measure(15, || {
            for f in &files {
                std::hint::black_box(gudsl_model::parse(&f.text));
            }
        }),
        mb,
    );
    row(
        "lex + parse + tree (one 50k-line file)",
        measure(15, || {
            std::hint::black_box(gudsl_model::parse(&one_file));
        }),
        mb,
    );
    let errors: usize = files.iter().map(|f| gudsl_model::parse(&f.text).errors().len()).sum();
    println!("syntax errors in the workspace: {errors}");
}
