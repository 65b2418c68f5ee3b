//! End-to-end tests of parameter overrides and studies (issue 51, item 4): `gudsl run --set`
//! runs the model as if the value were written in it, `--sweep` runs the grid into a folder a
//! setting with one table, `study.csv` and plot of what each setting measured, and a value that
//! does not fit is refused before anything runs, told at the argument that gave it (E0403).

#[path = "support/cli.rs"]
mod cli;

use std::path::Path;

use cli::{gudsl_run as run, repo, temp_dir};

const SAMPLE: &str = "samples/pipelines/ch4_motion_compensation.gudsl";

fn report(folder: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(folder.join("report.json")).unwrap()).unwrap()
}

/// The figure `name` of the stage `Accuracy` in a run's `report.json`.
fn figure(report: &serde_json::Value, name: &str) -> f64 {
    let figures = report["figures"].as_array().unwrap();
    let found = figures.iter().find(|f| f["stage"] == "Accuracy" && f["name"] == name);
    found.unwrap_or_else(|| panic!("no {name} in {report}"))["value"].as_f64().unwrap()
}

fn run_into(out: &Path, model: &str, more: &[&str]) -> (Option<i32>, String, String) {
    let mut args = vec![model, "--cpu", "--frames", "2", "-o", out.to_str().unwrap()];
    args.extend_from_slice(more);
    run(&args)
}

/// `--set` gives what the same value written into the model gives, figure for figure, and
/// changes the run (θ 5 % compensates less than the model's 1 %).
#[test]
fn a_set_value_runs_as_if_written_in_the_model() {
    let dir = temp_dir("study-set");
    let edited = dir.join("edited.gudsl");
    let text = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    std::fs::write(&edited, text.replace("threshold = 1,", "threshold = 5,")).unwrap();
    let (set, written, plain) = (dir.join("set"), dir.join("written"), dir.join("plain"));
    let (code, stdout, stderr) = run_into(&set, &repo(SAMPLE), &["--set", "Motion.threshold=5"]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let (code, stdout, stderr) = run_into(&written, edited.to_str().unwrap(), &["--root", dir.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert_eq!(run_into(&plain, &repo(SAMPLE), &[]).0, Some(0));
    let (set, written, plain) = (report(&set), report(&written), report(&plain));
    assert_eq!(set["figures"], written["figures"], "--set equals the value written in the model");
    let compensated = |r: &serde_json::Value| figure(r, "Compensated mean_cm");
    assert!(compensated(&set) > compensated(&plain) + 0.5, "θ 5 % against 1 %: {set} / {plain}");
    assert_eq!(figure(&set, "Uncompensated mean_cm"), figure(&plain, "Uncompensated mean_cm"));
    assert_eq!(std::fs::read_to_string(repo(SAMPLE)).unwrap(), text, "the model file is left as it was");
}

/// `--sweep` runs every combination into a folder of its own; `study.csv` holds one row a
/// setting with the figures of that setting's own `report.json`, and the plot is written.
#[test]
fn a_sweep_runs_the_grid_with_one_table_csv_and_plot() {
    let out = temp_dir("study-sweep");
    let sweeps =
        ["--sweep", "Motion.threshold=0,5", "--sweep", "Motion.subpixel=false,true", "--set", "Motion.windowSize=7"];
    let (code, stdout, stderr) = run_into(&out, &repo(SAMPLE), &sweeps);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let mut csv = csv::Reader::from_path(out.join("study.csv")).unwrap();
    let header: Vec<String> = csv.headers().unwrap().iter().map(str::to_string).collect();
    assert_eq!(header[..2], ["Motion.threshold", "Motion.subpixel"]);
    let column = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("{name}: {header:?}"));
    let rows: Vec<csv::StringRecord> = csv.records().map(Result::unwrap).collect();
    let settings: Vec<(&str, &str)> = rows.iter().map(|r| (&r[0], &r[1])).collect();
    assert_eq!(settings, [("0", "false"), ("0", "true"), ("5", "false"), ("5", "true")]);
    let mut compensated = Vec::new();
    for row in &rows {
        let folder = out.join(&row[column("folder")]);
        assert_eq!(row[column("folder")], format!("Motion.threshold={},Motion.subpixel={}", &row[0], &row[1]));
        let own = report(&folder);
        let mean: f64 = row[column("Accuracy Compensated mean_cm")].parse().unwrap();
        assert_eq!(mean, figure(&own, "Compensated mean_cm"), "{folder:?}");
        assert_eq!(row[column("state")], *"ok");
        assert!(folder.join("Images/distance_0001.png").is_file(), "each setting writes its outputs");
        compensated.push(mean);
    }
    assert!(compensated[2] > compensated[0], "θ 5 % compensates less than θ 0: {compensated:?}");
    for plot in ["study.svg", "study.png"] {
        assert!(std::fs::metadata(out.join(plot)).unwrap().len() > 1000, "{plot}");
    }
    let svg = std::fs::read_to_string(out.join("study.svg")).unwrap();
    assert!(svg.contains("Accuracy Compensated mean_cm") && svg.contains("Motion.subpixel=true"), "titles, legend");
    // The printed table: a row a setting.
    assert!(stdout.contains("study of 4 settings"), "{stdout}");
    let table_rows = stdout.lines().filter(|l| l.trim_start().starts_with('5') && l.trim_end().ends_with("ok"));
    assert_eq!(table_rows.count(), 2, "{stdout}");
}

/// A value that does not fit, a name the model does not have, a value that is not one value
/// or a file that is missing is refused before any setting runs, told at its argument; a
/// setting that cannot act is a warning and the run goes on.
#[test]
fn a_setting_that_does_not_fit_is_refused_at_its_argument_before_anything_runs() {
    let cases: [(&[&str], i32, &str); 9] = [
        (
            &["--sweep", "Motion.windowSize=5,8"],
            1,
            "error[E0403]: --sweep Motion.windowSize=8: `windowSize` is 8, but must be odd",
        ),
        (
            &["--set", "Motion.threshold=101"],
            1,
            "error[E0403]: --set Motion.threshold=101: `threshold` is 101, outside its range 0 to 100",
        ),
        (&["--set", "Motion.windowSize=7.5"], 1, "error[E0403]: --set Motion.windowSize=7.5: `windowSize` is 7.5, but must be a whole number"),
        (&["--set", "Motion.threshold=\"5\""], 1, "error[E0225]: --set Motion.threshold=\"5\": field `threshold` of `ToF.MotionCompensation` has type `float`"),
        (&["--set", "Camera.scene=Scene.Boxx"], 1, "error[E0229]: --set Camera.scene=Scene.Boxx: `ToF.Scene` has no field `Boxx`; did you mean `Box`?"),
        (
            &["--set", "Motoin.windowSize=5"],
            1,
            "has no instance `Motoin` (it has Camera, Black, Uncompensated, Motion,",
        ),
        (
            &["--set", "Motion.mws=5"],
            1,
            "`Motion` (ToF.MotionCompensation) has no parameter `mws` (its parameters: windowSize,",
        ),
        (&["--set", "Motion.windowSize=5, threshold = 3"], 1, "is not one value for `Motion.windowSize`"),
        (
            &["--set", "Motion.phaseCalibration=../../../etc/passwd"],
            2,
            "error[E0404]: --set Motion.phaseCalibration=../../../etc/passwd: ",
        ),
    ];
    for (args, expected, message) in cases {
        let out = temp_dir("study-refused");
        let target = out.join("never");
        let (code, stdout, stderr) = run_into(&target, &repo(SAMPLE), args);
        assert_eq!(code, Some(expected), "{args:?}\n{stdout}\n{stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(!target.exists(), "{args:?}: nothing runs, nothing is written");
    }
    let out = temp_dir("study-warned");
    let (code, stdout, stderr) =
        run_into(&out, &repo(SAMPLE), &["--set", "Camera.frames=1", "--set", "Motion.directionRestriction=90"]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stderr.contains("warning[E0406]: --set Motion.directionRestriction=90: ρ"), "{stderr}");
}
