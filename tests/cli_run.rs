//! End-to-end tests of `gudsl run`: the built binary runs `Main` of the samples (Listings
//! 30–33) on lavapipe and writes the viewer's images and `report.json`; it refuses a model with
//! errors, a diagram that cannot run (E0302) and an unknown diagram, and shows where a run
//! stopped (E0303: a missing image).

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, repo, temp_dir};

/// Whether this machine has a GPU adapter (lavapipe counts); `GUDSL_NO_GPU=1` says it has none
/// on purpose, as for the runtime's tests.
fn gpu() -> bool {
    std::env::var_os("GUDSL_NO_GPU").is_none()
}

#[test]
fn main_runs_and_writes_the_viewer_images_and_the_report() {
    if !gpu() {
        return;
    }
    let out = temp_dir("main");
    let run =
        gudsl().args(["run", &repo("samples"), "--diagram", "Main", "-o", out.to_str().unwrap()]).output().unwrap();
    let (stdout, stderr) = (String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert_eq!(run.status.code(), Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("first index of a value >= "), "{stdout}");
    assert!(stdout.contains("ran Main to final node `f`"), "{stdout}");
    for node in ["filterBilateralCL", "filterMean", "findIndexFirstStage", "findIndexSecondStage"] {
        assert!(stdout.lines().any(|l| l.starts_with(node)), "{node} in\n{stdout}");
    }
    assert!(stderr.contains("node initRandomReduceBuffer"), "progress: {stderr}");
    for i in 0..4 {
        let image = image::open(out.join(format!("viewer1-image{i}.png"))).unwrap();
        assert_eq!((image.width(), image.height()), (512, 512));
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["reached_final_node"], true);
    assert_eq!(report["calcs"].as_array().unwrap().len(), 4);
    assert_eq!(report["images"].as_array().unwrap().len(), 4);
    // Nothing outside the folder named.
    let mut written: Vec<String> =
        std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    written.sort();
    assert_eq!(
        written,
        ["report.json", "viewer1-image0.png", "viewer1-image1.png", "viewer1-image2.png", "viewer1-image3.png"]
    );
}

/// What a run printed, stdout then stderr (diagnostics go to stdout, as `gudsl check` writes
/// them; progress and refusals to stderr).
fn output(run: &std::process::Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr))
}

/// The samples `Main` needs, copied into `dir` with `edit` applied to `main_full.gudsl`.
fn samples_in(dir: &std::path::Path, edit: impl Fn(String) -> String) {
    for sample in [
        "framework/framework.gudsl",
        "seed/listing15_mean_filter.gudsl",
        "seed/listing16_bilateral_filter.gudsl",
        "seed/listing34_39_find_index.gudsl",
    ] {
        let name = sample.rsplit('/').next().unwrap();
        std::fs::copy(repo(&format!("samples/{sample}")), dir.join(name)).unwrap();
    }
    let main = std::fs::read_to_string(repo("samples/seed/main_full.gudsl")).unwrap();
    std::fs::write(dir.join("main_full.gudsl"), edit(main)).unwrap();
}

#[test]
fn a_missing_image_is_shown_where_the_run_stopped() {
    if !gpu() {
        return;
    }
    let dir = temp_dir("missing");
    samples_in(&dir, |main| main);
    let run =
        gudsl().args(["run", dir.to_str().unwrap(), "--diagram", "Main", "-o"]).arg(dir.join("out")).output().unwrap();
    let stderr = output(&run);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("E0303") && stderr.contains("tof_amplitude.png") && stderr.contains("image.load(asd)"),
        "{stderr}"
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("out/report.json")).unwrap()).unwrap();
    assert_eq!(report["reached_final_node"], false);
    assert!(report["error"].as_str().unwrap().contains("cannot read"), "{report}");
}

#[test]
fn models_with_errors_and_diagrams_that_cannot_run_are_refused() {
    let dir = temp_dir("refused");
    samples_in(&dir, |main| main.replace("imageIndex = imageIndex + 1;", "imageIndex = imageIndx + 1;"));
    let run = gudsl().args(["run", dir.to_str().unwrap(), "--diagram", "Main"]).current_dir(&dir).output().unwrap();
    let stderr = output(&run);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("the model has errors") && stderr.contains("imageIndx"), "{stderr}");
    assert!(!dir.join("report.json").exists(), "nothing runs");

    let dir = temp_dir("not-runnable");
    std::fs::write(
        dir.join("fork.gudsl"),
        "ActivityDiagram Forks()\n{\n    swimlane L\n    {\n        start S { => split; }\n        fork split { => a; => b; }\n        action a { => f; }\n        action b { => f; }\n        final f;\n    }\n}\n",
    )
    .unwrap();
    let run = gudsl().args(["run", dir.to_str().unwrap(), "--diagram", "Forks"]).current_dir(&dir).output().unwrap();
    let stderr = output(&run);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("E0302") && stderr.contains("one flow") && stderr.contains("fork split"), "{stderr}");

    let run = gudsl().args(["run", dir.to_str().unwrap(), "--diagram", "Nope"]).output().unwrap();
    let stderr = output(&run);
    assert_eq!(run.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no activity diagram named `Nope`") && stderr.contains("Forks"), "{stderr}");
}
