//! End-to-end tests of the recorded formats (issue 51, item 9): a ROS 2 bag (MCAP) read and
//! written by the samples and read back by Python's `mcap` package, depth images read from
//! 16-bit PNG and OpenEXR sequences as the writers wrote them, and the errors a wrong topic,
//! file or pattern gives before anything runs.
//!
//! Needs `python3 -m pip install mcap mcap-ros2-support` (scripts/test installs them).

#[path = "support/cli.rs"]
mod cli;

use std::{
    path::{Path, PathBuf},
    process::Command,
    sync::Arc,
};

use cli::{gudsl, gudsl_run as run, repo, temp_dir};
use gudsl_files::Folder;
use gudsl_formats::{arrays, bag};

const RECORD: &str = "samples/pipelines/ch4_record_mcap.gudsl";
const FROM_BAG: &str = "samples/pipelines/ch4_mcap_recording.gudsl";
const BAG: &str = "samples/pipelines/recordings/sphere_translation.mcap";

/// Every image of a bag's topic, as gudsl reads it.
fn topic_images(file: &Path, topic: &str) -> Vec<Vec<f32>> {
    let folder = Folder::open(file.parent().unwrap()).unwrap();
    let place = bag::Place { file: file.to_path_buf(), topic: topic.to_string() };
    let found = bag::image_topic(&folder, &place).unwrap();
    let stream = bag::images(Arc::new(folder), &place, found.messages, (found.width, found.height));
    (0..found.messages).map(|_| stream.next_frame().unwrap()).collect()
}

/// What Python's `mcap` reader decodes of a bag (`tests/mcap/read_bag.py`).
fn python_reads(file: &Path) -> serde_json::Value {
    let out = Command::new("python3").arg(repo("tests/mcap/read_bag.py")).arg(file).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("No module named 'mcap"),
        "Python's mcap reader is not installed: `python3 -m pip install mcap mcap-ros2-support`"
    );
    assert!(out.status.success(), "{stderr}");
    serde_json::from_slice(&out.stdout).unwrap()
}

fn report(folder: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(folder.join("report.json")).unwrap()).unwrap()
}

fn figure(report: &serde_json::Value, name: &str) -> f64 {
    let figures = report["figures"].as_array().unwrap();
    figures.iter().find(|f| f["name"] == name).unwrap_or_else(|| panic!("no {name} in {report}"))["value"]
        .as_f64()
        .unwrap()
}

/// The recording sample writes the bag committed beside the samples, message for message, and
/// Python decodes its images as gudsl does.
#[test]
fn the_recording_sample_writes_the_committed_bag() {
    let out = temp_dir("record");
    let (code, stdout, stderr) = run(&[&repo(RECORD), "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let written = out.join("Recorder/sphere_translation.mcap");
    let committed = PathBuf::from(repo(BAG));
    for topic in ["/Tof/raw_a", "/Tof/raw_b", "/Tof/truth"] {
        assert_eq!(topic_images(&written, topic), topic_images(&committed, topic), "{topic}");
    }
    let python = python_reads(&committed);
    assert_eq!(python["/Tof/raw_a"]["schema"], "sensor_msgs/msg/Image");
    assert_eq!(python["/Tof/raw_a"]["encoding"], "cdr");
    let raw = &python["/Tof/raw_a"]["messages"][1];
    assert_eq!(
        (raw["width"].as_u64(), raw["height"].as_u64(), raw["encoding"].as_str()),
        (Some(160), Some(480), Some("16UC1"))
    );
    let values: Vec<f32> = raw["values"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
    assert_eq!(values, topic_images(&committed, "/Tof/raw_a")[1], "Python decodes what gudsl reads");
    assert_eq!(raw["stamp"], 33_333_333, "frame 1 at 1/30 s");
}

/// The chapter 4 pipeline reads its raw frames and ground truth from the bag, compensates the
/// motion (the error falls to less than half) and writes a bag of depth images and clouds that
/// Python's `mcap` reader decodes to the values gudsl wrote.
#[test]
fn a_recording_in_a_bag_runs_into_a_bag_python_reads() {
    let out = temp_dir("from-bag");
    let (code, stdout, stderr) = run(&[&repo(FROM_BAG), "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let report = report(&out);
    let (plain, compensated) = (figure(&report, "Uncompensated mean_cm"), figure(&report, "Compensated mean_cm"));
    assert!(compensated < plain / 2.0, "compensated {compensated} cm against {plain} cm");

    let results = out.join("Results/results.mcap");
    let python = python_reads(&results);
    let distance = &python["/Compensated/distance"];
    assert_eq!((distance["schema"].as_str(), distance["count"].as_u64()), (Some("sensor_msgs/msg/Image"), Some(2)));
    let first = &distance["messages"][0];
    assert_eq!(
        (first["encoding"].as_str(), first["width"].as_u64(), first["height"].as_u64()),
        (Some("32FC1"), Some(160), Some(120))
    );
    assert_eq!(first["frame_id"], "tof");
    let values: Vec<f32> = first["values"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap() as f32).collect();
    assert_eq!(values, topic_images(&results, "/Compensated/distance")[0]);
    let truth = &topic_images(&PathBuf::from(repo(BAG)), "/Tof/truth")[0];
    let near = values.iter().zip(truth).filter(|(d, t)| (*d - *t).abs() < 0.05).count();
    assert!(near > values.len() * 4 / 5, "{near} of {} pixels within 5 cm of the truth", values.len());

    let cloud = &python["/Points/cloud"];
    assert_eq!(cloud["schema"], "sensor_msgs/msg/PointCloud2");
    let cloud = &cloud["messages"][1];
    let names: Vec<&str> = cloud["fields"].as_array().unwrap().iter().map(|f| f[0].as_str().unwrap()).collect();
    assert_eq!(names, ["x", "y", "z", "normal_x", "normal_y", "normal_z"]);
    let points = cloud["points"].as_array().unwrap();
    assert!(points.len() > 10_000, "{} points", points.len());
    let z = points.iter().map(|p| p[2].as_f64().unwrap()).fold(f64::NAN, f64::max);
    assert!((3.0..6.0).contains(&z), "the wall is the farthest, at {z} m");
}

/// Frames read from a bag keep the times they were recorded at in the bag a run writes (here
/// 10 frames a second, where the writer's own clock would say 30).
#[test]
fn frames_from_a_bag_keep_their_time_stamps() {
    let dir = temp_dir("stamps");
    let recorded = dir.join("recorded");
    let (code, stdout, stderr) =
        run(&[&repo(RECORD), "--set", "Recorder.frameRate=10", "-o", recorded.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let bag = "recorded/Recorder/sphere_translation.mcap";
    let text = format!(
        "ComponentInstanceDiagram Stamped\n{{\n    import ToF.*;\n\n    Recording instantiates RawFrameFile (channelA = \"{bag}:/Tof/raw_a\", channelB = \"{bag}:/Tof/raw_b\")\n    {{\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Demod.In.frame ]\n    }}\n\n    Demod instantiates Demodulation ( )\n    {{\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n        Out : DepthOut ( provider depth = IDepthImageProvider() );\n        [ source Out.depth ==> target Results.In.depth ]\n    }}\n\n    Results instantiates McapWriter ( )\n    {{\n        In : DepthIn ( processor depth = IDepthImageProcessor() );\n    }}\n}}\n"
    );
    let model = dir.join("stamped.gudsl");
    std::fs::write(&model, &text).unwrap();
    let out = dir.join("out");
    let root = dir.to_str().unwrap();
    let (code, stdout, stderr) = run(&[model.to_str().unwrap(), "--cpu", "--root", root, "-o", out.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    let python = python_reads(&out.join("Results/results.mcap"));
    let messages = python["/Demod/distance"]["messages"].as_array().unwrap();
    let times: Vec<(u64, u64)> =
        messages.iter().map(|m| (m["log_time"].as_u64().unwrap(), m["stamp"].as_u64().unwrap())).collect();
    assert_eq!(times, [(0, 0), (100_000_000, 100_000_000)]);
}

/// A model of `text` in `dir`, checked with `gudsl check`: its exit code and output.
fn check(dir: &Path, text: &str) -> (Option<i32>, String) {
    let model = dir.join("model.gudsl");
    std::fs::write(&model, text).unwrap();
    let out = gudsl().arg("check").arg(&model).arg("--root").arg(dir).output().unwrap();
    let shown = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    (out.status.code(), shown)
}

fn depth_source(path: &str, scale: &str) -> String {
    let source = format!("DepthFile (path = \"{path}\"{scale})");
    source_to_sink(&source, ("Depth", "depth"), "NpyWriter (amplitude = false)")
}

fn distances(folder: &Path) -> Vec<Vec<f32>> {
    let folder_of = Folder::open(folder).unwrap();
    (0..2).map(|k| arrays::read(&folder_of, &folder.join(format!("distance_{k:04}.npy"))).unwrap().values).collect()
}

/// Depth images written as a 16-bit PNG and an OpenEXR sequence read back as a `DepthFile`
/// sequence (`depth_*.exr`) give the distances written as arrays: exactly from EXR, within
/// half a millimetre from PNG.
#[test]
fn picture_sequences_read_back_what_the_writers_wrote() {
    let dir = temp_dir("sequences");
    std::fs::copy(repo(BAG), dir.join("rec.mcap")).unwrap();
    let sink = |name: &str, class: &str| {
        format!("    {name} instantiates {class}\n    {{\n        In : DepthIn ( processor depth = IDepthImageProcessor() );\n    }}\n")
    };
    let text = format!(
        "ComponentInstanceDiagram Writers\n{{\n    import ToF.*;\n\n    Recording instantiates RawFrameFile (channelA = \"rec.mcap:/Tof/raw_a\", channelB = \"rec.mcap:/Tof/raw_b\")\n    {{\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Demod.In.frame ]\n    }}\n\n    Demod instantiates Demodulation (modulationFrequency = 20)\n    {{\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n        Out : DepthOut ( provider depth = IDepthImageProvider() );\n        [ source Out.depth ==> target Exr.In.depth ]\n        [ source Out.depth ==> target Png.In.depth ]\n        [ source Out.depth ==> target Npy.In.depth ]\n    }}\n\n{}{}{}}}\n",
        sink("Exr", "ExrWriter ( )"),
        sink("Png", "PngWriter (preview = false)"),
        sink("Npy", "NpyWriter (amplitude = false)"),
    );
    let model = dir.join("writers.gudsl");
    std::fs::write(&model, &text).unwrap();
    let written = dir.join("written");
    let (code, stdout, stderr) =
        run(&[model.to_str().unwrap(), "--cpu", "--root", dir.to_str().unwrap(), "-o", written.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{text}\n{stdout}\n{stderr}");
    let arrays = distances(&written.join("Npy"));

    for (pattern, scale, tolerance) in
        [("written/Exr/depth_*.exr", "", 0.0), ("written/Png/distance_*.png", ", scale = 0.001", 0.000_51)]
    {
        let model = dir.join("read.gudsl");
        std::fs::write(&model, depth_source(pattern, scale)).unwrap();
        let read = dir.join("read");
        let (code, stdout, stderr) =
            run(&[model.to_str().unwrap(), "--cpu", "--root", dir.to_str().unwrap(), "-o", read.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{pattern}: {stdout}\n{stderr}");
        for (back, wrote) in distances(&read.join("Sink")).iter().zip(&arrays) {
            let worst = back.iter().zip(wrote).map(|(b, w)| (b - w).abs()).fold(0.0, f32::max);
            assert!(worst <= tolerance, "{pattern}: {worst} m off");
        }
    }
}

/// A model of one source bound to one sink.
fn source_to_sink(source: &str, (port, kind): (&str, &str), sink: &str) -> String {
    format!(
        "ComponentInstanceDiagram Copy\n{{\n    import ToF.*;\n\n    Source instantiates {source}\n    {{\n        Out : {port}Out ( provider {kind} = I{provider}Provider() );\n        [ source Out.{kind} ==> target Sink.In.{kind} ]\n    }}\n\n    Sink instantiates {sink}\n    {{\n        In : {port}In ( processor {kind} = I{provider}Processor() );\n    }}\n}}\n",
        provider = if kind == "cloud" { "PointCloud" } else { "DepthImage" },
    )
}

/// The clouds of a run written as PLY, PCD and to a bag read back as a `CloudFile` — a PLY
/// sequence (`cloud_*.ply`), the bag's topic — and written as PCD again: the same points and
/// normals as the run's PCD.
#[test]
fn cloud_sequences_in_ply_and_pcd_read_back_what_the_writers_wrote() {
    let dir = temp_dir("clouds");
    std::fs::copy(repo(BAG), dir.join("rec.mcap")).unwrap();
    let text =
        std::fs::read_to_string(repo(FROM_BAG)).unwrap().replace("recordings/sphere_translation.mcap", "rec.mcap");
    let writers = "Ply instantiates PlyWriter (everyFrame = true)\n    {\n        Clouds : CloudIn ( processor cloud = IPointCloudProcessor() );\n    }\n\n    Pcd instantiates PcdWriter (everyFrame = true)\n    {\n        Clouds : CloudIn ( processor cloud = IPointCloudProcessor() );\n    }\n\n    Results instantiates McapWriter ( )";
    let text = text.replace("Results instantiates McapWriter ( )", writers);
    let text = text.replace(
        "[ source Out.cloud ==> target Results.Clouds.cloud ]",
        "[ source Out.cloud ==> target Results.Clouds.cloud ]\n        [ source Out.cloud ==> target Ply.Clouds.cloud ]\n        [ source Out.cloud ==> target Pcd.Clouds.cloud ]",
    );
    let model = dir.join("clouds.gudsl");
    std::fs::write(&model, &text).unwrap();
    let root = dir.to_str().unwrap();
    let written = dir.join("written");
    let (code, stdout, stderr) =
        run(&[model.to_str().unwrap(), "--cpu", "--root", root, "-o", written.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{text}\n{stdout}\n{stderr}");

    let read = |path: PathBuf| {
        let folder = Folder::open(path.parent().unwrap()).unwrap();
        gudsl_formats::pcd::read(&folder, &path).unwrap()
    };
    for source in ["written/Ply/cloud_*.ply", "written/Results/results.mcap:/Points/cloud"] {
        let model = dir.join("copy.gudsl");
        let source = format!("CloudFile (path = \"{source}\")");
        std::fs::write(&model, source_to_sink(&source, ("Cloud", "cloud"), "PcdWriter (everyFrame = true)")).unwrap();
        let copied = dir.join("copied");
        let (code, stdout, stderr) =
            run(&[model.to_str().unwrap(), "--cpu", "--root", root, "-o", copied.to_str().unwrap()]);
        assert_eq!(code, Some(0), "{stdout}\n{stderr}");
        assert!(stdout.contains("(2 frames)"), "one cloud a frame: {stdout}");
        for k in 0..2 {
            let name = format!("cloud_{k:04}.pcd");
            let (points, normals) = read(written.join("Pcd").join(&name));
            assert!(points.len() > 10_000 && normals.iter().any(|n| n[2] != 0.0), "{} points", points.len());
            assert_eq!(read(copied.join("Sink").join(&name)), (points, normals), "{source}: {name}");
        }
    }
}

/// A topic a bag lacks, a topic of another schema, a file that is no bag and a pattern that
/// matches nothing are each told at the parameter, with what there is, before anything runs.
#[test]
fn wrong_topics_files_and_patterns_are_told_before_the_run() {
    let dir = temp_dir("format-errors");
    std::fs::copy(repo(BAG), dir.join("rec.mcap")).unwrap();
    std::fs::write(dir.join("fake.mcap"), b"not a bag").unwrap();
    let cases = [
        ("rec.mcap:/Tof/depth", "has no topic `/Tof/depth`; its topics: /Tof/raw_a (sensor_msgs/msg/Image), /Tof/raw_b (sensor_msgs/msg/Image), /Tof/truth (sensor_msgs/msg/Image)"),
        ("fake.mcap:/Tof/truth", "fake.mcap: is not a readable MCAP file"),
        ("frames/*.png", "frames/*.png"),
        ("rec.mcap:/Tof/truth", ""),
    ];
    for (path, told) in cases {
        let (code, shown) = check(&dir, &depth_source(path, ""));
        match told {
            "" => assert_eq!(code, Some(0), "{path}: {shown}"),
            told => {
                assert_eq!(code, Some(1), "{path}: {shown}");
                assert!(shown.contains("E0404") && shown.contains(told), "{path}: {shown}");
            }
        }
    }
    std::fs::create_dir(dir.join("frames")).unwrap();
    std::fs::write(dir.join("frames/a.png"), b"").unwrap();
    std::fs::write(dir.join("frames/b.txt"), b"").unwrap();
    let (_, shown) = check(&dir, &depth_source("frames/*", ""));
    assert!(shown.contains("matches") && shown.contains("b.txt, which is no PNG or EXR picture"), "{shown}");
}
