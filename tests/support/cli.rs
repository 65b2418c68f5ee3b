//! What the end-to-end tests of the binary share: the built `gudsl`, paths in the repository,
//! and a fresh scratch folder per test.

#![allow(dead_code)] // each test binary takes what it needs

use std::{
    path::PathBuf,
    process::{Command, Output, Stdio},
    time::{Duration, Instant},
};

/// The built binary, ready for arguments.
pub fn gudsl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gudsl"))
}

/// `path` (relative to the repository root) as an absolute path.
pub fn repo(path: &str) -> String {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path).to_string_lossy().into_owned()
}

/// `gudsl run ARGS` as on a headless machine (no Wayland session: what Mesa prints then must
/// not show): its exit code, stdout and stderr.
pub fn gudsl_run(args: &[&str]) -> (Option<i32>, String, String) {
    let out =
        gudsl().arg("run").args(args).env_remove("XDG_RUNTIME_DIR").env_remove("NODEVICE_SELECT").output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// An empty folder of its own for the test `name` of this test binary and process.
pub fn temp_dir(name: &str) -> PathBuf {
    let binary = env!("CARGO_CRATE_NAME");
    let dir = std::env::temp_dir().join(format!("gudsl-{binary}-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `command` (no input; its output captured), failing the test if it takes longer than
/// `seconds` (a hang).
pub fn run_within(command: &mut Command, seconds: u64) -> Output {
    let mut child = command.stdin(Stdio::null()).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
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
