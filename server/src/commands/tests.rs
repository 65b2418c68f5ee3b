//! `gudsl run` prepares once: counted on the thread that runs it, the check and the run of a
//! pipeline or of `Main` generate each kernel of the model once (the check generates them; the
//! run takes them, and the pipeline the check prepared, instead of generating again).

use std::path::PathBuf;

use gudsl_codegen::queries::generated_kernels;

use super::run::{run, RunArgs};
use crate::workspace;

/// The repository's `path`.
fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// How many device diagrams the model under `path` has (counted without generating any).
fn device_diagrams(path: &str) -> usize {
    let loaded = workspace::load(&[repo(path)]);
    let (host, _) = workspace::analysis_host(&loaded.documents);
    let before = generated_kernels();
    let count = host.analysis().with_semantics(|sema| gudsl_codegen::device_diagrams(sema).len()).unwrap();
    assert_eq!(generated_kernels(), before, "listing device diagrams generates nothing");
    count
}

/// Runs `gudsl run PATH --diagram NAME` in this thread; the kernels it generated.
fn kernels_generated_by_run(path: &str, diagram: &str) -> usize {
    let output = std::env::temp_dir().join(format!("gudsl-prepare-once-{diagram}-{}", std::process::id()));
    let args = RunArgs {
        paths: vec![repo(path)],
        diagram: Some(diagram.to_string()),
        output: Some(output.clone()),
        frames: Some(1),
        cpu: false,
        one_frame_at_a_time: false,
        unfused: false,
        root: None,
        sets: Vec::new(),
        sweeps: Vec::new(),
        inputs: None,
        shard: None,
        resume: false,
    };
    let before = generated_kernels();
    let code = run(&args);
    let _ = std::fs::remove_dir_all(output);
    assert_eq!(format!("{code:?}"), format!("{:?}", std::process::ExitCode::SUCCESS), "{diagram} runs");
    generated_kernels() - before
}

#[test]
fn a_pipeline_run_generates_each_kernel_once() {
    let sample = "samples/pipelines/ch11_component_example.gudsl";
    let kernels = device_diagrams(sample);
    assert!(kernels > 0);
    assert_eq!(kernels_generated_by_run(sample, "ComponentExamplePipeline"), kernels);
}

#[test]
fn a_host_run_generates_each_kernel_once() {
    let kernels = device_diagrams("samples");
    assert!(kernels >= 3, "the bilateral and mean filters and findIndex: {kernels}");
    assert_eq!(kernels_generated_by_run("samples", "Main"), kernels);
}
