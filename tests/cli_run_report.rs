//! End-to-end tests of what `gudsl run` reports and keeps of a pipeline run (issue 51): a run on
//! the CPU reference says why, `report.json` names its times per frame or over the run, and a
//! sink that fails fails alone — the other sinks write every frame and their end-of-run files.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, gudsl_run as run, repo, temp_dir};
use gudsl_formats::arrays;

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

/// A recording (raw channel files) through black-image correction and demodulation into an
/// accuracy report and an NPY writer.
const RECORDED: &str = r#"ComponentInstanceDiagram Recorded
{
    import ToF.*;
    Recording instantiates RawFrameFile (channelA = "a.npy", channelB = "b.npy")
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Black.In.frame ]
    }
    Black instantiates BlackImageCorrection ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }
    Demod instantiates Demodulation ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Accuracy.In.depth ]
        [ source Out.depth ==> target Writer.In.depth ]
    }
    Accuracy instantiates AccuracyReport ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
    Writer instantiates NpyWriter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#;

/// Issue 51, item 1: what a run of recorded frames would lack — a black image of the frames'
/// own for `BlackImageCorrection( )`, ground truth for `AccuracyReport` — is an error before
/// the run, at the component (`gudsl check`, as the editor shows it), and `run` refuses; with
/// the black image's files and without the report, the same recording runs.
#[test]
fn what_recorded_frames_lack_is_an_error_before_the_run() {
    let dir = temp_dir("recorded-lacks");
    for name in ["a.npy", "b.npy"] {
        let data: Vec<f32> = (0..2 * 4 * 6 * 8).map(|i| (i % 500) as f32).collect();
        arrays::write(&dir.join(name), &[2, 4, 6, 8], &data, arrays::Dtype::U16).unwrap();
        arrays::write(&dir.join(format!("black_{name}")), &[4, 6, 8], &data[..4 * 6 * 8], arrays::Dtype::U16).unwrap();
    }
    let model = dir.join("recorded.gudsl");
    std::fs::write(&model, RECORDED).unwrap();
    let checked = gudsl().args(["check", model.to_str().unwrap()]).output().unwrap();
    let text = String::from_utf8_lossy(&checked.stdout).into_owned() + &String::from_utf8_lossy(&checked.stderr);
    assert_eq!(checked.status.code(), Some(1), "{text}");
    // Each diagnostic with its place: `error[E0405]: message` then `┌─ path:line:column`.
    let at = |line: usize, message: &str| {
        text.split("error[")
            .any(|d| d.starts_with("E0405]") && d.contains(message) && d.contains(&format!("recorded.gudsl:{line}:5")))
    };
    assert!(at(9, "the raw frames from `Recording` have no black image of their own"), "{text}");
    assert!(at(22, "the depth images from `Demod` have no ground truth"), "{text}");
    let out = dir.join("out");
    let (code, _, stderr) = run(&[model.to_str().unwrap(), "--cpu", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("the model has errors; nothing is done"), "{stderr}");
    assert!(!out.exists());

    // The black image from files, no report: it runs.
    let fixed = RECORDED
        .replace("BlackImageCorrection ( )", "BlackImageCorrection (channelA = \"black_a.npy\", channelB = \"black_b.npy\")")
        .replace("        [ source Out.depth ==> target Accuracy.In.depth ]\n", "")
        .replace(
            "    Accuracy instantiates AccuracyReport ( )\n    {\n        In : DepthIn ( processor depth = IDepthImageProcessor() );\n    }\n",
            "",
        );
    std::fs::write(&model, fixed).unwrap();
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(out.join("Writer/distance_0001.npy").is_file(), "{stdout}");
}

/// Issue 51, item 3: recorded frames get an accuracy report from a ground-truth file: the
/// simulator's frames, black image and true distances recorded as `.npy` files, run as a
/// recording; the report's mean error per frame is the one computed here from the written
/// distances and the truth file.
#[test]
fn recorded_frames_get_an_accuracy_report_from_a_ground_truth_file() {
    use gudsl_runtime::sim::{simulate, Camera, Motion, Scene};
    let dir = temp_dir("recorded-truth");
    let camera = Camera::default();
    let frames: Vec<_> = (0..2).map(|f| simulate(&Scene::sphere(), Motion::Still, &camera, f)).collect();
    let (w, h) = (frames[0].raw.width, frames[0].raw.height);
    let channel = |image: &gudsl_runtime::Image, first: usize| -> Vec<f32> {
        (0..4).flat_map(|p| image.plane(2 * p + first).to_vec()).collect()
    };
    for (name, first) in [("a", 0), ("b", 1)] {
        let data: Vec<f32> = frames.iter().flat_map(|f| channel(&f.raw, first)).collect();
        arrays::write(&dir.join(format!("{name}.npy")), &[2, 4, h, w], &data, arrays::Dtype::U16).unwrap();
        let black = channel(&frames[0].black, first);
        arrays::write(&dir.join(format!("black_{name}.npy")), &[4, h, w], &black, arrays::Dtype::U16).unwrap();
    }
    let truth: Vec<f32> = frames.iter().flat_map(|f| f.truth.data.clone()).collect();
    arrays::write(&dir.join("truth.npy"), &[2, h, w], &truth, arrays::Dtype::F32).unwrap();
    let model = dir.join("recorded.gudsl");
    let text = RECORDED
        .replace(
            "BlackImageCorrection ( )",
            "BlackImageCorrection (channelA = \"black_a.npy\", channelB = \"black_b.npy\")",
        )
        .replace("AccuracyReport ( )", "AccuracyReport (groundTruth = \"truth.npy\")");
    std::fs::write(&model, text).unwrap();
    let checked = gudsl().args(["check", model.to_str().unwrap()]).output().unwrap();
    assert_eq!(checked.status.code(), Some(0), "{}", String::from_utf8_lossy(&checked.stdout));
    let out = dir.join("out");
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let csv = std::fs::read_to_string(out.join("Accuracy/accuracy.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "{csv}");
    for (frame, row) in rows.iter().enumerate() {
        let distances = read_npy(&out.join(format!("Writer/distance_{frame:04}.npy")));
        let truth = &frames[frame].truth.data;
        let errors: Vec<f64> = distances
            .iter()
            .zip(truth)
            .filter(|(d, t)| t.is_finite() && **t < 3.85 && **d > 0.0)
            .map(|(d, t)| ((d - t).abs() * 100.0) as f64)
            .collect();
        let mean = errors.iter().sum::<f64>() / errors.len() as f64;
        assert_eq!(row[2].parse::<usize>().unwrap(), errors.len(), "frame {frame}: {csv}");
        assert!((row[3].parse::<f64>().unwrap() - mean).abs() < 1e-3, "frame {frame}: {mean} in {csv}");
        assert!(mean < 5.0, "a still sphere measured within centimetres: {mean} cm");
    }

    // A ground truth of another size cannot meet the depth images (E0405 at `groundTruth`).
    arrays::write(&dir.join("small.npy"), &[4, 4], &[1.0; 16], arrays::Dtype::F32).unwrap();
    std::fs::write(&model, std::fs::read_to_string(&model).unwrap().replace("truth.npy", "small.npy")).unwrap();
    let checked = gudsl().args(["check", model.to_str().unwrap()]).output().unwrap();
    let text = String::from_utf8_lossy(&checked.stdout);
    assert!(text.contains("E0405") && text.contains("the ground truth is 4×4, the depth images it is given"), "{text}");
}

/// The values of a float32 `.npy` file.
fn read_npy(path: &std::path::Path) -> Vec<f32> {
    arrays::read(&gudsl_files::Folder::open(path.parent().unwrap()).unwrap(), path).unwrap().values
}

/// Issue 51, item 5: settings that cannot act are warnings at their parameter (E0406) —
/// ρ in a run of one frame, θ = 0 — and the run goes on.
#[test]
fn settings_that_cannot_act_are_warnings_at_their_parameter() {
    let dir = temp_dir("ineffective");
    let sample = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    let one_frame = sample.replace("speed = 1, frames = 6)", "speed = 1, frames = 1)");
    let zero_theta = sample.replace("threshold = 1,", "threshold = 0,");
    for (name, text, param, words) in [
        ("one.gudsl", one_frame, "directionRestriction = 90", "a run of one frame has no previous frame"),
        ("theta.gudsl", zero_theta, "threshold = 0", "θ = 0 takes every pixel for moving"),
    ] {
        assert!(text.contains(param), "{param}");
        let model = dir.join(name);
        std::fs::write(&model, &text).unwrap();
        let checked = gudsl().args(["check", model.to_str().unwrap()]).output().unwrap();
        let out = String::from_utf8_lossy(&checked.stdout);
        assert_eq!(checked.status.code(), Some(0), "warnings only: {out}");
        let line = text.lines().position(|l| l.contains(param)).unwrap() + 1;
        let column = text.lines().nth(line - 1).unwrap().find(param).unwrap() + 1 + param.find('=').unwrap() + 2;
        let warning = out.split("warning[").find(|w| w.starts_with("E0406]")).unwrap_or_else(|| panic!("{out}"));
        assert!(warning.contains(words), "{warning}");
        assert!(warning.contains(&format!("{name}:{line}:{column}")), "at the value: {warning}");
    }
    // The one-frame run runs, ρ or not.
    let out = dir.join("out");
    let model = dir.join("one.gudsl");
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
}

/// Issue 51, item 1: an accumulated cloud bound into ICP (which registers a camera's clouds)
/// is an error before the run, at the registration.
#[test]
fn an_accumulated_cloud_into_icp_is_an_error_before_the_run() {
    let dir = temp_dir("accumulated-icp");
    let text = std::fs::read_to_string(repo("samples/pipelines/ch6_object_scan.gudsl")).unwrap();
    let into_ply = "        [ source Out.cloud ==> target Ply.In.cloud ]\n";
    assert!(text.contains(into_ply));
    let text = text
        .replace(into_ply, &format!("{into_ply}        [ source Out.cloud ==> target Extra.In.cloud ]\n"))
        .replace(
            "    Ply instantiates PlyWriter ( )",
            "    Extra instantiates IcpRegistration ( )\n    {\n        In : CloudIn ( processor cloud = IPointCloudProcessor() );\n    }\n\n    Ply instantiates PlyWriter ( )",
        );
    let model = dir.join("scan.gudsl");
    std::fs::write(&model, &text).unwrap();
    let checked = gudsl().args(["check", model.to_str().unwrap()]).output().unwrap();
    let out = String::from_utf8_lossy(&checked.stdout);
    assert_eq!(checked.status.code(), Some(1), "{out}");
    let line = text.lines().position(|l| l.contains("Extra instantiates")).unwrap() + 1;
    let error = out.split("error[").find(|e| e.starts_with("E0405]")).unwrap_or_else(|| panic!("{out}"));
    assert!(error.contains("the point clouds from `Model` are accumulated, not on a camera's grid"), "{error}");
    assert!(error.contains(&format!("scan.gudsl:{line}:5")), "{error}");
}

/// Issue 51, item 7: a tap — motion compensation's motion mask, bound from its `MaskOut` to a
/// `MaskWriter` — is written per frame, and is the mask the runtime's motion detection gives
/// for the same frame on the CPU (θ 1 %, black subtracted).
#[test]
fn the_motion_mask_can_be_tapped_and_written() {
    use gudsl_runtime::{
        kernels::{motion::detect, tof::subtract_black},
        sim::{simulate, Camera, Motion, Scene},
    };
    let dir = temp_dir("mask-tap");
    let sample = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    let motion = "        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Compensated.In.frame ]\n";
    assert!(sample.contains(motion), "the sample has changed");
    let text = sample.replace(
        motion,
        &format!("{motion}        Mask : MaskOut ( provider mask = IMaskProvider() );\n        [ source Mask.mask ==> target Masks.In.mask ]\n"),
    );
    let text = text.trim_end().strip_suffix('}').unwrap().to_string()
        + "\n    Masks instantiates MaskWriter ( )\n    {\n        In : MaskIn ( processor mask = IMaskProcessor() );\n    }\n}\n";
    let model = dir.join("tapped.gudsl");
    std::fs::write(&model, &text).unwrap();
    let out = dir.join("out");
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    for frame in 0..2 {
        let written = image::open(out.join(format!("Masks/mask_{frame:04}.png"))).unwrap();
        assert_eq!(written.color(), image::ColorType::L8);
        let simulated = simulate(&Scene::sphere(), Motion::Translation([0.01, 0.0, 0.0]), &Camera::default(), frame);
        let [_, mask] = detect(&subtract_black(&simulated.raw, &simulated.black), 0.01 * 65535.0);
        let expected: Vec<u8> = mask.data.iter().map(|&m| if m > 0.0 { 255 } else { 0 }).collect();
        let moving = expected.iter().filter(|&&m| m == 255).count();
        assert!(moving > 100 && moving < expected.len() / 2, "frame {frame}: {moving} moving pixels");
        assert!(written.to_luma8().into_raw() == expected, "frame {frame}: the mask differs from the runtime's");
    }
}

/// Motion compensation's normalised channels, tapped on `NormalizedOut` and written by a
/// `RawWriter`, are the frame's channels through the calibration's curves (here f(X) = 2X + 10
/// for tap A, 3X for tap B), in the layout `RawFrameFile` reads.
#[test]
fn the_normalised_channels_can_be_tapped_and_written() {
    let dir = temp_dir("normalised-tap");
    let (width, height) = (64, 48);
    let pixels = width * height;
    let planes = [[0.0, 0.0, 2.0, 10.0], [0.0, 0.0, 3.0, 0.0]].concat();
    let calibration: Vec<f32> = planes.iter().flat_map(|&v| vec![v; pixels]).collect();
    arrays::write(&dir.join("calibration.npy"), &[8, height, width], &calibration, arrays::Dtype::F32).unwrap();
    let port = |name: &str, kind: &str, role: &str, interface: &str| {
        format!("        {name} : {kind} ( {role} frame = {interface}() );\n")
    };
    let (raw_in, raw_out) = (
        port("In", "RawIn", "processor", "IRawFrameProcessor"),
        port("Out", "RawOut", "provider", "IRawFrameProvider"),
    );
    let text = format!(
        "ComponentInstanceDiagram Tapped\n{{\n    import ToF.*;\n\n    Camera instantiates SimulatedCamera (motion = Motion.Translation, frames = 1, width = {width}, height = {height})\n    {{\n{raw_out}        [ source Out.frame ==> target Black.In.frame ]\n    }}\n\n    Black instantiates BlackImageCorrection ( )\n    {{\n{raw_in}{raw_out}        [ source Out.frame ==> target Motion.In.frame ]\n        [ source Out.frame ==> target Raws.In.frame ]\n    }}\n\n    Motion instantiates MotionCompensation (phaseCalibration = \"calibration.npy\")\n    {{\n{raw_in}{}        [ source Normalized.frame ==> target Normalised.In.frame ]\n    }}\n\n    Raws instantiates RawWriter ( )\n    {{\n{raw_in}    }}\n\n    Normalised instantiates RawWriter ( )\n    {{\n{raw_in}    }}\n}}\n",
        port("Normalized", "NormalizedOut", "provider", "IRawFrameProvider"),
    );
    let model = dir.join("tapped.gudsl");
    std::fs::write(&model, &text).unwrap();
    let out = dir.join("out");
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{text}\n{stdout}\n{stderr}");
    for (channel, curve) in [("raw_a", (2.0, 10.0)), ("raw_b", (3.0, 0.0))] {
        let raw = read_npy(&out.join(format!("Raws/{channel}_0000.npy")));
        let normalised = read_npy(&out.join(format!("Normalised/{channel}_0000.npy")));
        assert_eq!((raw.len(), normalised.len()), (4 * pixels, 4 * pixels));
        let worst = raw.iter().zip(&normalised).map(|(x, n)| (curve.0 * x + curve.1 - n).abs()).fold(0.0, f32::max);
        assert!(worst < 1e-2, "{channel}: {worst} off the curve");
        assert!(raw.iter().any(|&x| x > 100.0), "{channel}: a frame of light");
    }
}

/// Recorded raw frames through demodulation into `.npy`: the channel files' names are `a.npy`
/// and `b.npy` beside the model.
const DEMODULATED: &str = r#"ComponentInstanceDiagram Demodulated
{
    import ToF.*;
    Recording instantiates RawFrameFile (channelA = "a.npy", channelB = "b.npy")
    {
        Out : RawOut ( provider frame = IRawFrameProvider() );
        [ source Out.frame ==> target Demod.In.frame ]
    }
    Demod instantiates Demodulation ( )
    {
        In : RawIn ( processor frame = IRawFrameProcessor() );
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Writer.In.depth ]
    }
    Writer instantiates NpyWriter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#;

/// Issue 51, item 9: float32 raw frames (averaged or calibrated) are read in the camera's
/// 16-bit units like uint16 ones — the same values give the same distances — and a value
/// that is none (NaN) or outside 0–65535 stops the run at its frame, naming the file.
#[test]
fn float32_raw_frames_read_as_their_16_bit_values() {
    let distances = |dtype: arrays::Dtype, values: &dyn Fn(usize) -> f32| {
        let dir = temp_dir(&format!("raw-{dtype:?}"));
        std::fs::write(dir.join("model.gudsl"), DEMODULATED).unwrap();
        for (name, shift) in [("a.npy", 0), ("b.npy", 11)] {
            let data: Vec<f32> = (0..2 * 4 * 6 * 8).map(|i| values(i + shift)).collect();
            arrays::write(&dir.join(name), &[2, 4, 6, 8], &data, dtype).unwrap();
        }
        let model = dir.join("model.gudsl");
        let (code, stdout, stderr) = run(&[
            model.to_str().unwrap(),
            "--cpu",
            "--root",
            dir.to_str().unwrap(),
            "-o",
            dir.join("out").to_str().unwrap(),
        ]);
        let folder = gudsl_files::Folder::open(&dir).unwrap();
        let read = |frame: usize| arrays::read(&folder, &dir.join(format!("out/Writer/distance_{frame:04}.npy")));
        (code, format!("{stdout}\n{stderr}"), read(1).map(|a| a.values).unwrap_or_default())
    };
    let whole = |i: usize| ((i as f32 * 0.7).sin() * 500.0 + 2000.0).round();
    let (code, text, recorded) = distances(arrays::Dtype::U16, &whole);
    assert_eq!(code, Some(0), "{text}");
    let (code, text, floats) = distances(arrays::Dtype::F32, &whole);
    assert_eq!(code, Some(0), "{text}");
    assert_eq!(floats, recorded, "the same values, the same distances");
    let (code, text, averaged) = distances(arrays::Dtype::F32, &|i| whole(i) + if i % 7 == 0 { 0.25 } else { 0.0 });
    assert_eq!(code, Some(0), "{text}");
    assert!(averaged.iter().all(|d| d.is_finite()) && averaged != recorded, "fractions are kept");
    let (code, text, _) = distances(arrays::Dtype::F32, &|i| if i == 3 { f32::NAN } else { whole(i) });
    assert_eq!(code, Some(1), "{text}");
    assert!(text.contains("a.npy holds NaN at index 3 of frame 0, outside 0..=65535"), "{text}");
}

/// Issue 51, item 7: motion compensation's flow, bound from its `FlowOut` to a `FlowWriter`, is
/// written per frame as `.npy` — the flow the runtime's block matching gives for the same frame
/// on the CPU (MWS 5, θ 1 %, no ρ) — and as a colour wheel: black where nothing moved, the
/// direction's hue where it did (the camera moves sideways: the image along x).
#[test]
fn the_flow_can_be_tapped_and_written_as_arrays_and_a_colour_wheel() {
    use gudsl_runtime::{
        kernels::{
            motion::{detect, match_blocks},
            tof::subtract_black,
        },
        sim::{simulate, Camera, Motion, Scene},
    };
    let dir = temp_dir("flow-tap");
    let sample = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    let motion = "        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Compensated.In.frame ]\n";
    let text = sample.replace("directionRestriction = 90)", "directionRestriction = 0)").replace(
        motion,
        &format!("{motion}        Flow : FlowOut ( provider flow = IFlowProvider() );\n        [ source Flow.flow ==> target Flows.In.flow ]\n"),
    );
    assert!(text.contains("Flows.In.flow") && text.contains("directionRestriction = 0)"), "the sample has changed");
    let text = text.trim_end().strip_suffix('}').unwrap().to_string()
        + "\n    Flows instantiates FlowWriter (maxLength = 1)\n    {\n        In : FlowIn ( processor flow = IFlowProcessor() );\n    }\n}\n";
    let model = dir.join("tapped.gudsl");
    std::fs::write(&model, &text).unwrap();
    let out = dir.join("out");
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "--frames", "2", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let folder = gudsl_files::Folder::open(&dir).unwrap();
    for frame in 0..2 {
        let written = arrays::read(&folder, &out.join(format!("Flows/flow_{frame:04}.npy"))).unwrap();
        let simulated = simulate(&Scene::sphere(), Motion::Translation([0.01, 0.0, 0.0]), &Camera::default(), frame);
        let raw = subtract_black(&simulated.raw, &simulated.black);
        let [_, mask] = detect(&raw, 0.01 * 65535.0);
        let expected = match_blocks(&raw, &mask, 5, None, false);
        assert_eq!(written.shape, [2, expected.height, expected.width]);
        assert!(written.values == expected.data, "frame {frame}: the flow differs from the runtime's");
        let n = expected.pixels();
        let picture = image::open(out.join(format!("Flows/flow_{frame:04}.png"))).unwrap().to_rgb8();
        let (mut still, mut sideways) = (0, 0);
        for (i, pixel) in picture.pixels().enumerate() {
            let (u, v) = (expected.data[i], expected.data[n + i]);
            if (u, v) == (0.0, 0.0) {
                assert_eq!(pixel.0, [0, 0, 0], "frame {frame}, pixel {i}: no motion is black");
                still += 1;
            } else if v == 0.0 {
                let expected = if u > 0.0 { [255, 0, 0] } else { [0, 255, 255] };
                assert_eq!(pixel.0, expected, "frame {frame}, pixel {i}: ({u}, {v})");
                sideways += 1;
            }
        }
        assert!(still > 0 && sideways > 50, "frame {frame}: {still} still, {sideways} sideways");
    }
}

/// Issue 51: a ground-truth file of fewer images than the run has frames is E0404 at
/// `groundTruth` before the run (`check` says so), not an error at the first frame without one;
/// one image a frame, or one for all, runs.
#[test]
fn too_few_ground_truth_images_are_an_error_before_the_run() {
    let dir = temp_dir("truth-short");
    let model = DEMODULATED.replace(
        "        [ source Out.depth ==> target Writer.In.depth ]\n",
        "        [ source Out.depth ==> target Writer.In.depth ]\n        [ source Out.depth ==> target Accuracy.In.depth ]\n",
    );
    let model = model.trim_end().strip_suffix('}').unwrap().to_string()
        + "    Accuracy instantiates AccuracyReport (groundTruth = \"truth.npy\")\n    {\n        In : DepthIn ( processor depth = IDepthImageProcessor() );\n    }\n}\n";
    std::fs::write(dir.join("model.gudsl"), model).unwrap();
    for name in ["a.npy", "b.npy"] {
        let data: Vec<f32> = (0..3 * 4 * 48).map(|i| ((i as f32 * 0.3).sin() * 400.0 + 2000.0).round()).collect();
        arrays::write(&dir.join(name), &[3, 4, 6, 8], &data, arrays::Dtype::U16).unwrap();
    }
    let path = dir.join("model.gudsl");
    let run_with = |images: usize| {
        let shape: Vec<usize> = if images == 1 { vec![6, 8] } else { vec![images, 6, 8] };
        arrays::write(&dir.join("truth.npy"), &shape, &vec![1.5; images * 48], arrays::Dtype::F32).unwrap();
        let root = dir.to_str().unwrap();
        let checked = gudsl().current_dir(&dir).args(["check", "model.gudsl"]).output().unwrap();
        let ran = run(&[path.to_str().unwrap(), "--cpu", "--root", root, "-o", dir.join("out").to_str().unwrap()]);
        (checked.status.code(), String::from_utf8_lossy(&checked.stdout).into_owned(), ran)
    };
    let (checked, report, (code, _, stderr)) = run_with(2);
    assert_eq!((checked, code), (Some(1), Some(2)), "{report}\n{stderr}");
    assert!(
        report.contains("error[E0404]") && report.contains("holds 2 ground-truth images, but the run has 3 frames"),
        "{report}"
    );
    for images in [1, 3] {
        let (checked, report, (code, stdout, stderr)) = run_with(images);
        assert_eq!((checked, code), (Some(0), Some(0)), "{images} images: {report}\n{stdout}\n{stderr}");
    }
}

/// Issue 52: `report.json` says what each binding carried, and `gudsl render --with-report`
/// draws it on the pipeline — each instance's time per frame and share, the slowest marked,
/// each binding labelled with what flowed through it; a report of another diagram, or no
/// report, is refused.
#[test]
fn a_run_s_report_is_drawn_on_its_diagram() {
    let out = temp_dir("pipeline-drawn-report");
    let (code, stdout, stderr) = run(&[&repo(SAMPLE), "--cpu", "--frames", "1", "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let report_path = out.join("report.json");
    let report: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&report_path).unwrap()).unwrap();
    let camera = report["bindings"].as_array().unwrap().iter().find(|b| b["provider"] == "Camera").unwrap();
    assert_eq!(camera["provider_port"], "Out.frame");
    assert_eq!((camera["processor"].as_str(), camera["processor_port"].as_str()), (Some("Black"), Some("In.frame")));
    assert_eq!((camera["items"].as_u64(), camera["carries"].as_str()), (Some(1), Some("4×2×200×200 f32 raw")));

    let pictures = out.join("pictures");
    let render = |report: &std::path::Path| {
        let args = [repo(SAMPLE), "--with-report".into(), report.display().to_string(), "-o".into()];
        gudsl().arg("render").args(args).arg(&pictures).output().unwrap()
    };
    let drawn = render(&report_path);
    assert!(drawn.status.success(), "{}", String::from_utf8_lossy(&drawn.stderr));
    let svg = std::fs::read_to_string(pictures.join("MotionCompensationPipeline.svg")).unwrap();
    for label in ["4×2×200×200 f32 raw", "200×200 f32 depth", "ms/frame (GPU", "«slowest»"] {
        assert!(svg.contains(label), "`{label}` is not drawn");
    }
    let drawn_lines = svg.split("<text").filter(|text| text.split("</text>").next().unwrap().contains("ms/frame (GPU"));
    assert_eq!(drawn_lines.count(), 8, "one line drawn for each instance");

    // A report of another pipeline, and a file that is no report.
    let other = out.join("other.json");
    std::fs::write(&other, serde_json::to_string(&serde_json::json!({"diagram": "Elsewhere", "stages": []})).unwrap())
        .unwrap();
    let refused = render(&other);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("the report is of `Elsewhere`"));
    std::fs::write(&other, "{\"frames\": 1}").unwrap();
    let refused = render(&other);
    assert_eq!(refused.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("is not a pipeline run's report.json"));
}

/// A library sink on a port of the user's own (an `async` one) measures what it measures in
/// order: its figures reach `report.json` (before, the stage's wrapper dropped them).
#[test]
fn a_library_sink_on_a_port_of_your_own_keeps_its_figures() {
    let dir = temp_dir("pipeline-async-accuracy");
    let port = "    Accuracy instantiates AccuracyReport (maxTrueDistance = 3.85)\n    {\n        In : DepthIn (";
    let mut text = std::fs::read_to_string(repo(SAMPLE)).unwrap();
    assert!(text.contains(port));
    text = text.replace(port, &port.replace("DepthIn", "AsyncDepthIn"));
    text += "
ComponentDiagram AsyncAccuracy
{
    sink ToF.AccuracyReport
    {
        async port AsyncDepthIn ( processor depth : ToF.IDepthImageProcessor );
    }

    filter ToF.Demodulation
    {
        port DepthOut ( provider depth : ToF.IDepthImageProvider );
        [ToAsync source DepthOut.depth ==> target AsyncDepthIn.depth]
    }
}
";
    let apart = dir.join("async.gudsl");
    std::fs::write(&apart, text).unwrap();
    let figures = |model: &str, out: &str| {
        let out = dir.join(out);
        let mut args = vec![model, "--frames", "2", "-o", out.to_str().unwrap()];
        if !gpu() {
            args.push("--cpu");
        }
        let (code, stdout, stderr) = run(&args);
        assert_eq!(code, Some(0), "{stdout}\n{stderr}");
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("report.json")).unwrap()).unwrap();
        (report["figures"].clone(), stdout)
    };
    let (in_order, _) = figures(&repo(SAMPLE), "in-order");
    let (on_its_port, stdout) = figures(apart.to_str().unwrap(), "async");
    assert!(stdout.lines().any(|l| l.starts_with("Accuracy ") && l.contains("(async)")), "{stdout}");
    assert!(in_order.as_array().is_some_and(|f| !f.is_empty()), "{in_order}");
    assert_eq!(on_its_port, in_order);
}
