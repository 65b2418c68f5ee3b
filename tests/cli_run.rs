//! End-to-end tests of `gudsl run`: the built binary runs `Main` of the samples (Listings
//! 30–33) on lavapipe and writes the viewer's images and `report.json`; it refuses a model with
//! errors, a diagram that cannot run (E0302) and an unknown diagram, and shows where a run
//! stopped (E0303: a missing image). And the GPU work a frame of each sample pipeline records,
//! as `report.json` counts it, and that overlapped frames write what one frame at a time
//! writes (issue 54).

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, gudsl_run as run, repo, temp_dir};

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

/// Issue 54: the GPU work a frame of each sample pipeline records — its dispatches (compute
/// passes) by stage and its submissions — as `report.json` counts them (deterministic on any
/// adapter). Before issue 54 motion compensation took three dispatches (detection and matching
/// apart), and a point cloud read by a sink or accumulated took a submission of its own per
/// camera: `ch4_mcap_recording` 7 dispatches in 2 submissions a frame, `ch6_object_scan` 7
/// submissions over its first 4 frames. Before a black-image correction ran inside the
/// demodulation it feeds (`fusion.rs`), each took a dispatch of its own: chapter 5's sample 5
/// dispatches a frame, chapter 6's 22.5.
/// `sample`'s GPU work a frame over `frames` frames, by stage, its submissions a frame, and
/// whether its frames overlap (no stage needs a frame's reads for the next); its report.
fn gpu_work(
    sample: &str,
    frames: usize,
    dispatches: &[(&str, f64)],
    submissions: f64,
    overlapped: bool,
) -> Option<serde_json::Value> {
    if !gpu() {
        return None;
    }
    let name = std::path::Path::new(sample).file_stem().unwrap().to_string_lossy().into_owned();
    let out = temp_dir(&format!("gpu-work-{name}"));
    let frames = frames.to_string();
    let (code, stdout, stderr) = run(&[&repo(sample), "--frames", &frames, "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
    let by_stage: Vec<(String, f64)> = (report["stages"].as_array().unwrap().iter())
        .map(|s| (s["instance"].as_str().unwrap().to_string(), s["dispatches_per_frame"].as_f64().unwrap()))
        .filter(|(_, n)| *n > 0.0)
        .collect();
    let expected: Vec<(String, f64)> = dispatches.iter().map(|(s, n)| (s.to_string(), *n)).collect();
    assert_eq!(by_stage, expected, "{name}: dispatches a frame by stage");
    let total: f64 = expected.iter().map(|(_, n)| n).sum();
    assert_eq!(report["dispatches_per_frame"].as_f64(), Some(total), "{name}");
    assert_eq!(report["submissions_per_frame"].as_f64(), Some(submissions), "{name}: submissions a frame");
    // The same work by the frame it was for: each frame's dispatches and submissions alike.
    let frames: usize = frames.parse().unwrap();
    let each = |values: &serde_json::Value| -> Vec<f64> {
        values.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect()
    };
    let by_frame: Vec<f64> = (0..frames)
        .map(|f| {
            report["stages"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| each(&s["dispatches_frames"]).get(f).copied().unwrap_or(0.0))
                .sum()
        })
        .collect();
    assert_eq!(by_frame.iter().sum::<f64>(), total * frames as f64, "{name}: {by_frame:?}");
    assert_eq!(each(&report["submissions_frames"]).iter().sum::<f64>(), submissions * frames as f64, "{name}");
    assert_eq!(report["frames_overlapped"], overlapped, "{name}: frames overlapped");
    let how = if overlapped { "frames overlapped" } else { "one frame at a time" };
    let line = format!("GPU work per frame: {total} dispatches in {submissions} submissions; {how}");
    assert!(stdout.contains(&line), "{name}: the table says `{line}`:\n{stdout}");
    Some(report)
}

/// The stages whose kernel ran inside others', with those, as `report.json` says.
fn fused_into(report: &serde_json::Value) -> Vec<(String, Vec<String>)> {
    let stages = report["stages"].as_array().unwrap().iter();
    let names = |v: &serde_json::Value| -> Vec<String> {
        v.as_array().unwrap().iter().map(|s| s.as_str().unwrap().to_string()).collect()
    };
    stages
        .map(|s| (s["instance"].as_str().unwrap().to_string(), names(&s["fused_into"])))
        .filter(|(_, inside)| !inside.is_empty())
        .collect()
}

#[test]
fn gpu_work_of_chapter_4_motion_compensation() {
    // Motion compensation: detection and matching in one pass, then the correction (3 before).
    let stages = [("Black", 1.0), ("Uncompensated", 1.0), ("Motion", 2.0), ("Compensated", 1.0)];
    gpu_work("samples/pipelines/ch4_motion_taps.gudsl", 2, &stages, 1.0, true);
    // With ρ, the flow's mean direction for the next frame's search, on the GPU (no read back,
    // so frames still overlap).
    // Motion compensation reads the corrected frame many times: the correction keeps its kernel.
    let stages = [("Black", 1.0), ("Uncompensated", 1.0), ("Motion", 3.0), ("Compensated", 1.0)];
    let report = gpu_work("samples/pipelines/ch4_motion_compensation.gudsl", 2, &stages, 1.0, true);
    assert!(report.is_none_or(|report| fused_into(&report).is_empty()));
}

#[test]
fn gpu_work_of_chapter_4_recordings() {
    gpu_work("samples/pipelines/ch4_record_mcap.gudsl", 2, &[("Tof", 1.0)], 1.0, true);
    let stages = [("Uncompensated", 1.0), ("Motion", 3.0), ("Compensated", 1.0), ("Points", 2.0)];
    gpu_work("samples/pipelines/ch4_mcap_recording.gudsl", 2, &stages, 1.0, true);
}

#[test]
fn gpu_work_of_chapter_5_integration_time() {
    // Each black-image correction runs inside its demodulation's kernel.
    let stages = [("PerPixel", 1.0), ("PerPixelControl", 1.0), ("MeanIntensity", 1.0)];
    // The next integration time is set by this frame's intensities, read back.
    let Some(report) = gpu_work("samples/pipelines/ch5_integration_time.gudsl", 2, &stages, 1.0, false) else {
        return;
    };
    let fused = [("PerPixelBlack", "PerPixel"), ("MayBlack", "MeanIntensity")];
    assert_eq!(fused_into(&report), fused.map(|(s, i)| (s.to_string(), vec![i.to_string()])));
}

/// Three cameras: the first three frames learn the background (four filters a camera, the
/// black-image correction inside the demodulation); the fourth segments, makes clouds and
/// accumulates them, read back in one submission.
#[test]
fn gpu_work_of_chapter_6_object_scan() {
    let mut stages = Vec::new();
    for camera in ["Left", "Centre", "Right"] {
        for (stage, n) in [
            ("Demod", 1.0),
            ("Median", 1.0),
            ("Gaussian", 1.0),
            ("Outliers", 1.0),
            ("Background", 1.25),
            ("Mask", 0.25),
            ("Cloud", 0.5),
            ("Transform", 0.5),
        ] {
            stages.push((format!("{camera}{stage}"), n));
        }
    }
    let stages: Vec<(&str, f64)> = stages.iter().map(|(s, n)| (s.as_str(), *n)).collect();
    // The background is learnt from the first frames' reads.
    let Some(report) = gpu_work("samples/pipelines/ch6_object_scan.gudsl", 4, &stages, 1.25, false) else {
        return;
    };
    let fused = ["Left", "Centre", "Right"].map(|c| (format!("{c}Black"), vec![format!("{c}Demod")]));
    assert_eq!(fused_into(&report), fused);
}

#[test]
fn gpu_work_of_chapter_11_component_example() {
    let stages = [("Camera1", 2.0), ("Camera2", 2.0), ("MeanFilter1", 6.0), ("Viewer1", 6.0)];
    gpu_work("samples/pipelines/ch11_component_example.gudsl", 1, &stages, 1.0, true);
}

/// Frames overlap where no stage needs a frame's reads for the next: such a run writes what it
/// writes one frame at a time (`--one-frame-at-a-time`), byte for byte.
#[test]
fn overlapped_frames_write_what_one_frame_at_a_time_writes() {
    if !gpu() {
        return;
    }
    let samples = ["ch4_motion_compensation", "ch4_motion_taps", "ch4_record_mcap", "ch4_mcap_recording"];
    for sample in samples.into_iter().chain(["ch11_component_example"]) {
        let outputs = [true, false].map(|overlapped| {
            let out = temp_dir(&format!("overlap-{sample}-{overlapped}"));
            let mut args = vec![repo(&format!("samples/pipelines/{sample}.gudsl"))];
            args.extend(["--frames", "3", "-o", out.to_str().unwrap()].map(String::from));
            if !overlapped {
                args.push("--one-frame-at-a-time".into());
            }
            let (code, stdout, stderr) = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
            assert_eq!(code, Some(0), "{sample}: {stdout}\n{stderr}");
            let report: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
            assert_eq!(report["frames_overlapped"], overlapped, "{sample}");
            // Overlapped, frame 1 began (its recording) before frame 0 was done (its sinks).
            let times = |key: &str| -> Vec<f64> {
                report[key].as_array().unwrap().iter().map(|t| t.as_f64().unwrap()).collect()
            };
            let (started, done) = (times("frames_started_ms"), times("frames_done_ms"));
            let frames = report["frames"].as_u64().unwrap() as usize;
            assert!(frames >= 2 && (started.len(), done.len()) == (frames, frames), "{sample}: {report}");
            assert_eq!(started[1] < done[0], overlapped, "{sample}: {started:?} {done:?}");
            files_beneath(&out)
        });
        let names = |files: &[(String, Vec<u8>)]| files.iter().map(|(name, _)| name.clone()).collect::<Vec<_>>();
        assert_eq!(names(&outputs[0]), names(&outputs[1]), "{sample}: the files written");
        assert!(!outputs[0].is_empty(), "{sample} wrote nothing");
        for ((name, overlapped), (_, one_at_a_time)) in outputs[0].iter().zip(&outputs[1]) {
            assert!(overlapped == one_at_a_time, "{sample}: {name} differs");
        }
    }
}

/// A black-image correction that runs inside its demodulation's kernel writes what it writes
/// with every stage running its own kernels (`--unfused`), byte for byte (chapter 5's accuracy
/// table, chapter 6's cloud): the same run with fewer dispatches.
#[test]
fn fused_runs_write_what_unfused_runs_write() {
    if !gpu() {
        return;
    }
    for (sample, frames, fewer) in [("ch5_integration_time", "3", 2.0), ("ch6_object_scan", "4", 3.0)] {
        let [fused, unfused] = [false, true].map(|unfused| {
            let out = temp_dir(&format!("fusion-{sample}-{unfused}"));
            let mut args = vec![repo(&format!("samples/pipelines/{sample}.gudsl"))];
            args.extend(["--frames", frames, "-o", out.to_str().unwrap()].map(String::from));
            if unfused {
                args.push("--unfused".into());
            }
            let (code, stdout, stderr) = run(&args.iter().map(String::as_str).collect::<Vec<_>>());
            assert_eq!(code, Some(0), "{sample}: {stdout}\n{stderr}");
            assert_eq!(stdout.contains("Black") && stdout.contains("runs in"), !unfused, "{sample}: {stdout}");
            let report: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
            assert_eq!(fused_into(&report).is_empty(), unfused, "{sample}");
            (report["dispatches_per_frame"].as_f64().unwrap(), files_beneath(&out), out)
        });
        // Drawn on the diagram, a fused correction says where it ran.
        let pictures = fused.2.join("pictures");
        let report = fused.2.join("report.json").display().to_string();
        let model = repo(&format!("samples/pipelines/{sample}.gudsl"));
        let drawn = gudsl().args(["render", &model, "--with-report", &report, "-o"]).arg(&pictures).output().unwrap();
        assert!(drawn.status.success(), "{}", String::from_utf8_lossy(&drawn.stderr));
        let svg = std::fs::read_dir(&pictures).unwrap().map(|e| std::fs::read_to_string(e.unwrap().path()).unwrap());
        let demodulation = if sample.starts_with("ch5") { "PerPixel" } else { "LeftDemod" };
        let said = format!("runs in {demodulation}&apos;s kernel");
        assert!(svg.into_iter().any(|svg| svg.contains(&said) || svg.contains(&said.replace("&apos;", "'"))), "{said}");
        assert_eq!(unfused.0 - fused.0, fewer, "{sample}: dispatches a frame");
        assert!(!fused.1.is_empty(), "{sample} wrote nothing");
        assert!(fused.1 == unfused.1, "{sample}: the files differ");
    }
}

/// Every file beneath `folder` but `report.json` (its times differ), by path, with its bytes.
fn files_beneath(folder: &std::path::Path) -> Vec<(String, Vec<u8>)> {
    let mut files = Vec::new();
    let mut folders = vec![folder.to_path_buf()];
    while let Some(at) = folders.pop() {
        for entry in std::fs::read_dir(&at).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                folders.push(path);
            } else if path.file_name().is_some_and(|n| n != "report.json") {
                let name = path.strip_prefix(folder).unwrap().display().to_string();
                files.push((name, std::fs::read(&path).unwrap()));
            }
        }
    }
    files.sort();
    files
}
