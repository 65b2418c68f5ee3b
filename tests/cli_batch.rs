//! End-to-end tests of many recordings (issue 51, item 11): `gudsl run --inputs` runs one job
//! per recording into a folder of its own and a summary of them all; N shards run as separate
//! processes give, file for file, what one process gives, with no recording run twice;
//! `--resume` skips what is done; a recording that cannot run fails alone.

#[path = "support/cli.rs"]
mod cli;

use std::{
    collections::BTreeMap,
    path::{Path, PathBuf},
    process::{Command, Output, Stdio},
};

use cli::{gudsl, temp_dir};
use gudsl_formats::arrays;

/// Raw recorded frames (channel files A and B) demodulated, compared with each recording's
/// ground truth and written as `.npy`; the model's own paths name one recording (a run with
/// `--inputs` gives each its own).
const MODEL: &str = r#"ComponentInstanceDiagram Fleet
{
    import ToF.*;
    Recording instantiates RawFrameFile (channelA = "recordings/rec_00/a.npy", channelB = "recordings/rec_00/b.npy")
    {
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
    Accuracy instantiates AccuracyReport (groundTruth = "recordings/rec_00/truth.npy")
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
    Writer instantiates NpyWriter ( )
    {
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }
}
"#;

const VALUES: [&str; 6] = [
    "--set",
    "Recording.channelA={recording}/a.npy",
    "--set",
    "Recording.channelB={recording}/b.npy",
    "--set",
    "Accuracy.groundTruth={recording}/truth.npy",
];

/// A folder with the model and `count` recordings of two 8×6 frames, each its own.
fn fleet(name: &str, count: usize) -> PathBuf {
    let dir = temp_dir(name);
    std::fs::write(dir.join("model.gudsl"), MODEL).unwrap();
    for k in 0..count {
        let recording = dir.join(format!("recordings/rec_{k:02}"));
        std::fs::create_dir_all(&recording).unwrap();
        for (channel, shift) in [("a.npy", 0), ("b.npy", 7)] {
            let data: Vec<f32> = (0..2 * 4 * 6 * 8).map(|i| ((i * 37 + k * 101 + shift) % 3000 + 500) as f32).collect();
            arrays::write(&recording.join(channel), &[2, 4, 6, 8], &data, arrays::Dtype::U16).unwrap();
        }
        arrays::write(&recording.join("truth.npy"), &[6, 8], &[1.0 + k as f32 * 0.01; 48], arrays::Dtype::F32).unwrap();
    }
    dir
}

fn gudsl_in(dir: &Path, args: &[&str]) -> Command {
    let mut command = gudsl();
    command.current_dir(dir).args(args).env_remove("XDG_RUNTIME_DIR").env_remove("NODEVICE_SELECT");
    command
}

fn batch(dir: &Path, out: &str, more: &[&str]) -> Command {
    let mut args = vec!["run", "model.gudsl", "--cpu", "--inputs", "recordings/*", "-o", out];
    args.extend_from_slice(&VALUES);
    args.extend_from_slice(more);
    gudsl_in(dir, &args)
}

fn text(out: &Output) -> String {
    format!("{}\n{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

/// The recordings a run says it ran (`run k/n: rec_NN` on stderr).
fn ran(out: &Output) -> Vec<String> {
    let stderr = String::from_utf8_lossy(&out.stderr);
    stderr.lines().filter_map(|l| l.strip_prefix("run ")?.split_once(": ").map(|(_, r)| r.to_string())).collect()
}

/// Every file beneath `root`, by path relative to it.
fn files(root: &Path) -> BTreeMap<PathBuf, PathBuf> {
    let mut found = BTreeMap::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                found.insert(path.strip_prefix(root).unwrap().to_path_buf(), path);
            }
        }
    }
    found
}

/// What of a `report.json` does not depend on the machine's speed or the folder it ran in.
fn lasting(report: &Path, root: &Path) -> serde_json::Value {
    let json: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    let prefix = root.to_string_lossy().into_owned();
    let outputs: Vec<String> =
        json["outputs"].as_array().unwrap().iter().map(|p| p.as_str().unwrap().replace(&prefix, "")).collect();
    serde_json::json!([json["setting"], json["figures"], json["frames"], json["error"], outputs])
}

/// `summary.csv` without its times.
fn summary_without_times(path: &Path) -> Vec<Vec<String>> {
    let mut csv = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = csv.headers().unwrap().iter().map(str::to_string).collect();
    let keep: Vec<usize> = (0..header.len()).filter(|&k| !header[k].contains("ms_per_frame")).collect();
    let mut rows = vec![keep.iter().map(|&k| header[k].clone()).collect()];
    rows.extend(csv.records().map(|r| keep.iter().map(|&k| r.as_ref().unwrap()[k].to_string()).collect()));
    rows
}

#[test]
fn four_shards_in_separate_processes_equal_one_process_file_for_file() {
    let dir = fleet("batch-shards", 50);
    let one = batch(&dir, "one", &[]).output().unwrap();
    assert_eq!(one.status.code(), Some(0), "{}", text(&one));
    assert_eq!(ran(&one).len(), 50, "{}", text(&one));
    let shards: Vec<_> = (0..4)
        .map(|k| {
            let mut shard = batch(&dir, "sharded", &["--shard", &format!("{k}/4")]);
            shard.stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap()
        })
        .collect();
    let shards: Vec<Output> = shards.into_iter().map(|child| child.wait_with_output().unwrap()).collect();
    let mut by_shards: Vec<String> = Vec::new();
    for shard in &shards {
        assert_eq!(shard.status.code(), Some(0), "{}", text(shard));
        assert!(text(shard).contains("gudsl summarize"), "a shard says how to merge: {}", text(shard));
        by_shards.extend(ran(shard));
    }
    assert_eq!(by_shards.len(), 50, "no recording run twice");
    by_shards.sort();
    by_shards.dedup();
    assert_eq!(by_shards.len(), 50, "every recording run once");
    let merged = gudsl_in(&dir, &["summarize", "sharded"]).output().unwrap();
    assert_eq!(merged.status.code(), Some(0), "{}", text(&merged));

    let (one, sharded) = (files(&dir.join("one")), files(&dir.join("sharded")));
    assert_eq!(one.keys().collect::<Vec<_>>(), sharded.keys().collect::<Vec<_>>(), "the same files");
    assert!(
        one.contains_key(Path::new("rec_37/Writer/distance_0001.npy")),
        "{:?}",
        one.keys().take(8).collect::<Vec<_>>()
    );
    for (relative, path) in &one {
        let other = &sharded[relative];
        match relative.file_name().unwrap().to_str().unwrap() {
            "report.json" => {
                assert_eq!(lasting(path, &dir.join("one")), lasting(other, &dir.join("sharded")), "{relative:?}")
            }
            "summary.csv" => assert_eq!(summary_without_times(path), summary_without_times(other)),
            "summary.svg" | "summary.png" => {} // they plot the times too
            _ => assert_eq!(std::fs::read(path).unwrap(), std::fs::read(other).unwrap(), "{relative:?}"),
        }
    }
    // The summary: a row a recording, with each one's own error (its truth differs by 1 cm).
    let rows = summary_without_times(&dir.join("one/summary.csv"));
    assert_eq!(rows.len(), 51);
    assert_eq!(rows[0][..2], ["recording", "Accuracy Demod mean_cm"]);
    assert_eq!(rows[1][0], "rec_00");
    assert_eq!(rows[50][0], "rec_49");
    assert!(rows[1..].iter().all(|r| r.contains(&"ok".to_string())));
}

#[test]
fn resume_skips_what_is_done_and_a_broken_recording_fails_alone() {
    let dir = fleet("batch-resume", 4);
    std::fs::remove_file(dir.join("recordings/rec_02/b.npy")).unwrap();
    let first = batch(&dir, "out", &[]).output().unwrap();
    assert_eq!(first.status.code(), Some(2), "a recording's file is missing: {}", text(&first));
    assert!(
        text(&first).contains("rec_02: error[E0404]: --set Recording.channelB="),
        "told with the recording and its value: {}",
        text(&first)
    );
    assert_eq!(ran(&first), ["rec_00", "rec_01", "rec_03"], "the others run");
    let summary = summary_without_times(&dir.join("out/summary.csv"));
    assert_eq!(summary.len(), 4, "{summary:?}");

    // Fixed, resumed: only what is not done runs.
    std::fs::copy(dir.join("recordings/rec_02/a.npy"), dir.join("recordings/rec_02/b.npy")).unwrap();
    std::fs::remove_file(dir.join("out/rec_01/report.json")).unwrap();
    let resumed = batch(&dir, "out", &["--resume"]).output().unwrap();
    assert_eq!(resumed.status.code(), Some(0), "{}", text(&resumed));
    assert!(text(&resumed).contains("--resume: 2 of 4 recordings done already"), "{}", text(&resumed));
    assert_eq!(ran(&resumed), ["rec_01", "rec_02"]);
    assert_eq!(summary_without_times(&dir.join("out/summary.csv")).len(), 5, "the summary has every recording");

    // Without `{recording}` a batch names nothing to read; the placeholder needs --inputs.
    let nameless = gudsl_in(&dir, &["run", "model.gudsl", "--cpu", "--inputs", "recordings/*"]).output().unwrap();
    assert_eq!(nameless.status.code(), Some(1));
    assert!(text(&nameless).contains("no value of --set or --sweep names `{recording}`"), "{}", text(&nameless));
    let alone = gudsl_in(&dir, &["run", "model.gudsl", "--cpu", "--set", "Recording.channelA={recording}/a.npy"])
        .output()
        .unwrap();
    assert!(text(&alone).contains("give the recordings with --inputs"), "{}", text(&alone));
}
