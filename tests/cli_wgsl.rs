//! End-to-end tests of `gudsl wgsl`: the built binary generates the samples' device diagrams,
//! and refuses a model with errors, a construct it cannot generate, and nothing to generate.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, repo, temp_dir};

const GPU_CLASS: &str = "ClassDiagram K { import OpenCL.GPU.*; public class Gpu implements OpenCL { } }\n";

#[test]
fn the_samples_device_diagrams_are_written_one_file_each() {
    let out = temp_dir("samples");
    let run = gudsl().args(["wgsl", &repo("samples"), "-o", out.to_str().unwrap()]).output().unwrap();
    assert_eq!(run.status.code(), Some(0), "{}", String::from_utf8_lossy(&run.stderr));
    for diagram in
        ["AdFilterMean", "AdFilterBilateral", "AdFindMinimumIndexFirstStage", "AdFindMinimumIndexSecondStage"]
    {
        let wgsl = std::fs::read_to_string(out.join(format!("{diagram}.wgsl"))).unwrap();
        assert!(wgsl.contains(&format!("fn {diagram}(")), "{wgsl}");
        assert!(wgsl.contains("@compute"), "{wgsl}");
    }
    // One diagram, printed.
    let run = gudsl().args(["wgsl", &repo("samples"), "--diagram", "AdFilterMean"]).output().unwrap();
    assert_eq!(run.status.code(), Some(0));
    let printed = String::from_utf8_lossy(&run.stdout);
    assert!(printed.contains("fn AdFilterMean(") && !printed.contains("fn AdFilterBilateral("), "{printed}");
}

#[test]
fn a_model_with_errors_is_refused_with_its_diagnostics() {
    let dir = temp_dir("errors");
    std::fs::write(dir.join("k.gudsl"), GPU_CLASS).unwrap();
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad(int n)\n{\n    swimlane L, owner K.Gpu\n    {\n        start S { var int x = nn + 1; => f; }\n        final f;\n    }\n}\n",
    )
    .unwrap();
    let run = gudsl().args(["wgsl", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("E0228") && stdout.contains("nn"), "{stdout}");
    assert!(!stdout.contains("@compute"), "no WGSL for a model with errors: {stdout}");
    assert!(String::from_utf8_lossy(&run.stderr).contains("the model has errors"));
}

#[test]
fn what_cannot_be_generated_is_an_error_at_its_place() {
    let dir = temp_dir("unsupported");
    std::fs::write(dir.join("k.gudsl"), GPU_CLASS).unwrap();
    // A fork splits a work-item's flow in two: no WGSL form.
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad()\n{\n    swimlane L, owner K.Gpu\n    {\n        start S { => split; }\n        fork split { => a; => b; }\n        action a { => j; }\n        action b { => j; }\n        join j { => f; }\n        final f;\n    }\n}\n",
    )
    .unwrap();
    let run = gudsl().args(["wgsl", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("E0301"), "{stdout}");
    assert!(stdout.contains("ad.gudsl:6:9"), "the fork node's place: {stdout}");
    assert!(stdout.contains("a work-item has one flow"), "{stdout}");
}

#[test]
fn nothing_to_generate_and_unreadable_paths() {
    let dir = temp_dir("nothing");
    std::fs::write(dir.join("c.gudsl"), "ClassDiagram C { public class Plain { } }\n").unwrap();
    let run = gudsl().args(["wgsl", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("no device diagrams"));
    let run = gudsl().args(["wgsl", &repo("samples"), "--diagram", "NoSuchDiagram"]).output().unwrap();
    assert_eq!(run.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&run.stderr).contains("no device diagram named `NoSuchDiagram`"));
    let run = gudsl().args(["wgsl", "no/such/path.gudsl"]).output().unwrap();
    assert_eq!(run.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&run.stderr).contains("no/such/path.gudsl"));
}
