//! `gudsl check` and `gudsl run` on a cloned repository that attacks its user (issue 48): a
//! committed link in `gudsl-out/` pointing at a file of the user's, inputs naming files outside
//! the repository, the server's own streams, a FIFO and a device. Nothing is written through a
//! link, nothing outside the workspace folder is read, and nothing hangs.

#[path = "support/cli.rs"]
mod cli;

use std::{
    os::unix::fs::symlink,
    path::Path,
    process::{Command, Output, Stdio},
    time::{Duration, Instant},
};

use cli::{gudsl, temp_dir};
use gudsl_runtime::arrays;

/// Runs `command` in `dir`, failing the test if it takes longer than `seconds` (a hang).
fn run_within(command: &mut Command, dir: &Path, seconds: u64) -> Output {
    command.current_dir(dir).stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped());
    let mut child = command.spawn().unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            panic!("still running after {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
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
