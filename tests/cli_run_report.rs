//! End-to-end tests of what `gudsl run` reports and keeps of a pipeline run (issue 51): a run on
//! the CPU reference says why, `report.json` names its times per frame or over the run, and a
//! sink that fails fails alone — the other sinks write every frame and their end-of-run files.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl_run as run, repo, temp_dir};

const SAMPLE: &str = "samples/pipelines/ch4_motion_compensation.gudsl";

fn gpu() -> bool {
    std::env::var_os("GUDSL_NO_GPU").is_none()
}

/// Issue 51, item 8: `--cpu` on a machine with an adapter says it runs on the CPU reference,
/// not that there is no adapter; `report.json` names its times per frame or over the run, and
/// its per-frame figures are the printed table's.
#[test]
fn a_cpu_run_says_why_and_the_report_says_per_frame_or_total() {
    let out = temp_dir("pipeline-cpu-report");
    let (code, stdout, stderr) = run(&[&repo(SAMPLE), "--cpu", "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    if gpu() {
        assert!(!format!("{stdout}{stderr}").contains("no GPU adapter"), "{stdout}\n{stderr}");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["device"], "the CPU reference");
    assert_eq!(report["frames"], 2);
    let close = |a: &serde_json::Value, b: f64| (a.as_f64().unwrap() - b).abs() < 1e-9;
    assert!(close(&report["ms_per_frame"], report["total_ms"].as_f64().unwrap() / 2.0), "{report}");
    for stage in report["stages"].as_array().unwrap() {
        for side in ["host", "device"] {
            let total = stage[format!("{side}_ms_total")].as_f64().unwrap();
            assert!(close(&stage[format!("{side}_ms_per_frame")], total / 2.0), "{stage}");
        }
        // The table's row of the stage shows its host time per frame.
        let instance = stage["instance"].as_str().unwrap();
        let row = stdout.lines().find(|l| l.starts_with(&format!("{instance} "))).unwrap();
        let host: f64 = row.split_whitespace().rev().nth(2).unwrap().parse().unwrap();
        assert!((host - stage["host_ms_per_frame"].as_f64().unwrap()).abs() < 0.001, "{row} / {stage}");
    }
}

/// Issue 51, item 2: a sink that cannot write fails alone — the run goes on, the other sinks
/// write every frame and their end-of-run files, `report.json` says which sink failed and why,
/// and the exit code is 1.
#[test]
fn a_failing_sink_fails_alone_and_the_others_write_everything() {
    let out = temp_dir("pipeline-sink-fails");
    // A file where the `Depth` writer's folder belongs.
    std::fs::write(out.join("Depth"), "in the way").unwrap();
    let (code, stdout, stderr) = run(&[&repo(SAMPLE), "--cpu", "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stdout}\n{stderr}");
    for file in [
        "Images/distance_0000.png",
        "Images/distance_0001.png",
        "Images/preview_0001.png",
        "Accuracy/accuracy.csv",
        "Accuracy/accuracy.svg",
        "report.json",
    ] {
        assert!(out.join(file).is_file(), "{file} is missing\n{stdout}\n{stderr}");
    }
    assert_eq!(std::fs::read_to_string(out.join("Depth")).unwrap(), "in the way");
    assert!(stderr.contains("Depth") && stderr.contains("not a folder"), "{stderr}");
    assert!(stdout.contains("(2 frames; failed: Depth)"), "{stdout}");
    assert!(stdout.lines().any(|l| l.starts_with("Depth ") && l.ends_with("  failed")), "{stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let stage =
        |name: &str| report["stages"].as_array().unwrap().iter().find(|s| s["instance"] == name).unwrap().clone();
    assert_eq!(stage("Depth")["state"], "failed", "{report}");
    assert!(stage("Depth")["error"].as_str().unwrap().contains("not a folder"), "{report}");
    for name in ["Images", "Accuracy", "Camera", "Motion"] {
        assert_eq!(stage(name)["state"], "ok", "{name}: {report}");
    }
    assert_eq!(report["frames"], 2);
    let outputs = report["outputs"].as_array().unwrap();
    assert!(outputs.iter().any(|o| o.as_str().unwrap().ends_with("distance_0001.png")), "{report}");
}
