//! `gudsl check` and `gudsl run` on a cloned repository that attacks its user (issue 48): a
//! committed link in `gudsl-out/` pointing at a file of the user's, inputs naming files outside
//! the repository, the server's own streams, a FIFO and a device. Nothing is written through a
//! link, nothing outside the workspace folder is read, and nothing hangs.

#[path = "support/cli.rs"]
mod cli;

use std::{
    os::unix::fs::symlink,
    path::Path,
    process::{Command, Output},
    time::{Duration, Instant},
};

use cli::{gudsl, temp_dir};
use gudsl_formats::arrays;

/// Runs `command` in `dir` (see `cli::run_within`).
fn run_within(command: &mut Command, dir: &Path, seconds: u64) -> Output {
    cli::run_within(command.current_dir(dir), seconds)
}

/// A pipeline that reads the depth images `path` names and writes them as `.npy` files.
fn model(path: &str) -> String {
    format!(
        r#"ComponentInstanceDiagram P
{{
    import ToF.*;
    Source instantiates DepthFile (path = "{path}")
    {{
        Out : DepthOut ( provider depth = IDepthImageProvider() );
        [ source Out.depth ==> target Writer.In.depth ]
    }}
    Writer instantiates NpyWriter ( )
    {{
        In : DepthIn ( processor depth = IDepthImageProcessor() );
    }}
}}
"#
    )
}

/// A repository holding `model.gudsl` (reading `path`) and a 2×3 depth image `depth.npy`.
fn repository(name: &str, path: &str) -> std::path::PathBuf {
    let repo = temp_dir(name);
    std::fs::write(repo.join("model.gudsl"), model(path)).unwrap();
    arrays::write(&repo.join("depth.npy"), &[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0], arrays::Dtype::F32).unwrap();
    repo
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn a_link_committed_in_gudsl_out_is_never_written_through() {
    let repo = repository("untrusted-link", "depth.npy");
    let home = temp_dir("untrusted-home");
    let keys = home.join("authorized_keys");
    std::fs::write(&keys, "ssh-ed25519 AAAA the-users-own-key\n").unwrap();
    let planted = repo.join("gudsl-out/P/Writer");
    std::fs::create_dir_all(&planted).unwrap();
    symlink(&keys, planted.join("distance_0000.npy")).unwrap();

    let out = run_within(gudsl().args(["run", "model.gudsl", "--cpu"]), &repo, 60);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("holds links") && stderr.contains("distance_0000.npy"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&keys).unwrap(), "ssh-ed25519 AAAA the-users-own-key\n");

    // The link gone, the same run writes its file (a regular file, not a link).
    std::fs::remove_file(planted.join("distance_0000.npy")).unwrap();
    let out = run_within(gudsl().args(["run", "model.gudsl", "--cpu"]), &repo, 60);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let written = std::fs::symlink_metadata(planted.join("distance_0000.npy")).unwrap();
    assert!(written.is_file());
}

#[test]
fn an_output_folder_reached_through_a_committed_link_is_refused() {
    let repo = repository("untrusted-out-link", "depth.npy");
    let elsewhere = temp_dir("untrusted-elsewhere");
    symlink(&elsewhere, repo.join("gudsl-out")).unwrap();
    let out = run_within(gudsl().args(["run", "model.gudsl", "--cpu"]), &repo, 60);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("holds links") && stderr.contains("gudsl-out"), "{stderr}");
    assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 0, "nothing written where the link points");
}

#[test]
fn inputs_outside_the_workspace_the_servers_streams_fifos_and_devices_are_refused_without_hanging() {
    let outside = temp_dir("untrusted-outside");
    arrays::write(&outside.join("secret.npy"), &[2, 2], &[7.0; 4], arrays::Dtype::F32).unwrap();
    let cases = [
        ("/dev/stdin", "lies outside"),
        ("/dev/stdout", "lies outside"),
        ("/dev/zero", "lies outside"),
        (&*outside.join("secret.npy").display().to_string(), "lies outside"),
        ("../untrusted-outside/secret.npy", "lies outside"),
        ("escape.npy", "lies outside"),
        ("fifo.npy", "is a FIFO, not a regular file"),
        ("zero.npy", "lies outside"),
    ];
    for (path, why) in cases {
        let repo = repository("untrusted-inputs", path);
        assert!(Command::new("mkfifo").arg(repo.join("fifo.npy")).status().unwrap().success());
        symlink(outside.join("secret.npy"), repo.join("escape.npy")).unwrap();
        symlink("/dev/zero", repo.join("zero.npy")).unwrap();
        for command in ["check", "run"] {
            let args: &[&str] =
                if command == "check" { &["check", "model.gudsl"] } else { &["run", "model.gudsl", "--cpu"] };
            let out = run_within(gudsl().args(args), &repo, 20);
            let report = text(&out.stdout) + &text(&out.stderr);
            assert_ne!(out.status.code(), Some(0), "{command} {path}: {report}");
            assert!(report.contains("E0404") && report.contains(why), "{command} {path}: {report}");
        }
    }
}

/// A `.npz` member `(frames, 4, height, width)` of uint16 zeros, deflated: a few hundred
/// kilobytes on disk that claim `frames × 4 × height × width × 2` bytes.
fn zeros_npz(path: &Path, frames: usize, height: usize, width: usize) {
    use std::io::Write;
    let mut header = format!("{{'descr': '<u2', 'fortran_order': False, 'shape': ({frames}, 4, {height}, {width}), }}");
    header.push_str(&" ".repeat(63 - (10 + header.len()) % 64));
    header.push('\n');
    let mut zip = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let options =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated).large_file(true);
    zip.start_file("a.npy", options).unwrap();
    zip.write_all(b"\x93NUMPY\x01\x00").unwrap();
    zip.write_all(&(header.len() as u16).to_le_bytes()).unwrap();
    zip.write_all(header.as_bytes()).unwrap();
    let frame = vec![0u8; 4 * height * width * 2];
    for _ in 0..frames {
        zip.write_all(&frame).unwrap();
    }
    zip.finish().unwrap();
}

/// The most memory any child of this test process has held, in bytes.
fn children_peak_memory() -> u64 {
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    assert_eq!(unsafe { libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage) }, 0);
    usage.ru_maxrss as u64 * 1024
}

#[test]
fn a_run_of_one_frame_reads_one_frame_of_a_recording_however_large_it_claims_to_be() {
    let repo = temp_dir("untrusted-zeros");
    // 2 048 frames of 4 × 128 × 128: 256 MiB of uint16 a channel (1 GiB as the f32 it became).
    zeros_npz(&repo.join("zeros.npz"), 2048, 128, 128);
    let on_disk = std::fs::metadata(repo.join("zeros.npz")).unwrap().len();
    assert!(on_disk < 2 << 20, "{on_disk} bytes on disk");
    let model = model("").replace(
        "Source instantiates DepthFile (path = \"\")\n    {\n        Out : DepthOut ( provider depth = IDepthImageProvider() );",
        "Source instantiates RawFrameFile (channelA = \"zeros.npz\", channelB = \"zeros.npz\")\n    {\n        Out : RawOut ( provider frame = IRawFrameProvider() );\n        [ source Out.frame ==> target Demod.In.frame ]\n    }\n    Demod instantiates Demodulation ( )\n    {\n        In : RawIn ( processor frame = IRawFrameProcessor() );\n        Out : DepthOut ( provider depth = IDepthImageProvider() );",
    );
    assert!(model.contains("RawFrameFile"), "{model}");
    std::fs::write(repo.join("model.gudsl"), model).unwrap();

    let started = Instant::now();
    let out = run_within(gudsl().args(["run", "model.gudsl", "--cpu", "--frames", "1"]), &repo, 60);
    assert_eq!(out.status.code(), Some(0), "{}{}", text(&out.stdout), text(&out.stderr));
    assert!(
        text(&out.stdout).contains("(1 frames)") || text(&out.stdout).contains("(1 frame)"),
        "{}",
        text(&out.stdout)
    );
    let peak = children_peak_memory();
    assert!(peak < 300 << 20, "a run of one frame held {} MiB", peak >> 20);
    assert!(started.elapsed() < Duration::from_secs(20), "took {:?}", started.elapsed());
}

#[test]
fn root_names_the_folder_a_models_files_are_read_beneath() {
    let outside = temp_dir("untrusted-data");
    arrays::write(&outside.join("depth.npy"), &[2, 2], &[7.0; 4], arrays::Dtype::F32).unwrap();
    let named = outside.join("depth.npy").display().to_string();
    let repo = repository("untrusted-root", &named);
    let refused = run_within(gudsl().args(["check", "model.gudsl"]), &repo, 20);
    assert_eq!(refused.status.code(), Some(1), "{}", text(&refused.stdout));
    assert!(text(&refused.stdout).contains("lies outside"), "{}", text(&refused.stdout));
    let data = std::env::temp_dir();
    let root = data.to_str().unwrap();
    let checked = run_within(gudsl().args(["check", "model.gudsl", "--root", root]), &repo, 20);
    assert_eq!(checked.status.code(), Some(0), "{}", text(&checked.stdout));
    let ran = run_within(gudsl().args(["run", "model.gudsl", "--cpu", "--root", root]), &repo, 60);
    assert_eq!(ran.status.code(), Some(0), "{}", text(&ran.stderr));
    assert!(repo.join("gudsl-out/P/Writer/distance_0000.npy").is_file(), "outputs stay in the current folder");
}
