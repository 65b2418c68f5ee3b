//! The folder's promises, each tried as a hostile repository would break it.

use std::{fs, os::unix::fs::symlink, path::Path, time::Instant};

use crate::{Folder, Problem};

fn mkfifo(path: &Path) {
    let made = std::process::Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success());
}

#[test]
fn reads_beneath_its_folder_and_nowhere_else() {
    let root = tempfile::tempdir().unwrap();
    let outside = tempfile::tempdir().unwrap();
    fs::create_dir(root.path().join("data")).unwrap();
    fs::write(root.path().join("data/a.npy"), b"inside").unwrap();
    fs::write(outside.path().join("secret"), b"secret").unwrap();
    symlink("data/a.npy", root.path().join("near")).unwrap();
    symlink(outside.path().join("secret"), root.path().join("far")).unwrap();
    let folder = Folder::open(root.path()).unwrap();

    assert_eq!(folder.read(&root.path().join("data/a.npy"), 100).unwrap(), b"inside");
    assert_eq!(folder.read(&root.path().join("data/../data/a.npy"), 100).unwrap(), b"inside");
    assert_eq!(folder.read(&root.path().join("near"), 100).unwrap(), b"inside", "a link that stays inside is followed");
    for escape in
        [root.path().join("far"), root.path().join("../secret"), outside.path().join("secret"), "/dev/stdout".into()]
    {
        let error = folder.read(&escape, 100).unwrap_err();
        assert!(matches!(error.problem, Problem::Outside { .. }), "{escape:?}: {error}");
        assert!(error.to_string().contains("lies outside"), "{error}");
    }
    assert_eq!(folder.read(&root.path().join("missing"), 100).unwrap_err().problem, Problem::NotFound);
}

#[test]
fn reads_regular_files_only_without_blocking_and_never_more_than_asked() {
    let root = tempfile::tempdir().unwrap();
    mkfifo(&root.path().join("fifo"));
    fs::write(root.path().join("big"), vec![7; 1000]).unwrap();
    let folder = Folder::open(root.path()).unwrap();

    let started = Instant::now();
    let error = folder.read(&root.path().join("fifo"), 100).unwrap_err();
    assert_eq!(error.problem, Problem::NotRegular { kind: "a FIFO" });
    assert!(started.elapsed().as_secs() < 1, "opening a FIFO with no writer must not block");
    assert_eq!(folder.read(root.path(), 100).unwrap_err().problem, Problem::NotRegular { kind: "a folder" });
    let error = folder.read(&root.path().join("big"), 999).unwrap_err();
    assert_eq!(error.problem, Problem::TooLarge { len: 1000, limit: 999 });
    assert_eq!(folder.read(&root.path().join("big"), 1000).unwrap().len(), 1000);
}

#[test]
fn a_write_replaces_a_link_instead_of_writing_through_it() {
    let root = tempfile::tempdir().unwrap();
    let victim = tempfile::tempdir().unwrap();
    let target = victim.path().join("authorized_keys");
    fs::write(&target, b"the user's own keys\n").unwrap();
    symlink(&target, root.path().join("distance_0000.npy")).unwrap();
    let folder = Folder::open(root.path()).unwrap();

    let written = folder.write("distance_0000.npy", b"ssh-ed25519 AAAA attacker\n").unwrap();
    assert_eq!(fs::read(&target).unwrap(), b"the user's own keys\n", "the link's target is untouched");
    let meta = fs::symlink_metadata(&written).unwrap();
    assert!(!meta.file_type().is_symlink());
    assert_eq!(
        std::os::unix::fs::PermissionsExt::mode(&meta.permissions()) & 0o600,
        0o600,
        "the owner reads and writes it"
    );
    assert_eq!(fs::read(&written).unwrap(), b"ssh-ed25519 AAAA attacker\n");
    assert!(matches!(folder.write("../x", b"").unwrap_err().problem, Problem::Outside { .. }));
    assert_eq!(fs::read_dir(root.path()).unwrap().count(), 1, "no temporary file is left behind");
}

#[test]
fn an_output_folder_is_never_reached_through_a_link_and_holds_none() {
    let anchor = tempfile::tempdir().unwrap();
    let victim = tempfile::tempdir().unwrap();
    fs::write(victim.path().join("keep"), b"keep").unwrap();

    let made = Folder::output(anchor.path(), Path::new("gudsl-out/P")).unwrap();
    assert!(made.path().ends_with("gudsl-out/P") && made.path().is_dir());

    symlink(victim.path(), anchor.path().join("gudsl-out/Q")).unwrap();
    let error = Folder::output(anchor.path(), Path::new("gudsl-out/Q")).unwrap_err();
    assert_eq!(error.problem, Problem::Links { links: vec![anchor.path().join("gudsl-out/Q")] });

    fs::create_dir_all(anchor.path().join("gudsl-out/P/Sink")).unwrap();
    symlink(victim.path().join("keep"), anchor.path().join("gudsl-out/P/Sink/distance_0000.npy")).unwrap();
    let error = Folder::output(anchor.path(), Path::new("gudsl-out/P")).unwrap_err();
    assert_eq!(error.problem, Problem::Links { links: vec![anchor.path().join("gudsl-out/P/Sink/distance_0000.npy")] });
    assert!(error.to_string().contains("distance_0000.npy"), "{error}");
    assert!(matches!(
        Folder::output(anchor.path(), Path::new("../elsewhere")).unwrap_err().problem,
        Problem::Outside { .. }
    ));
    assert_eq!(fs::read(victim.path().join("keep")).unwrap(), b"keep");
}

#[test]
fn lists_its_own_regular_files_only() {
    let root = tempfile::tempdir().unwrap();
    let outside = tempfile::tempdir().unwrap();
    fs::write(root.path().join("b.npy"), b"b").unwrap();
    fs::write(root.path().join("a.npy"), b"a").unwrap();
    fs::create_dir(root.path().join("sub")).unwrap();
    fs::write(root.path().join("sub/c.npy"), b"c").unwrap();
    fs::write(outside.path().join("secret.npy"), b"secret").unwrap();
    symlink(outside.path().join("secret.npy"), root.path().join("far.npy")).unwrap();
    symlink("a.npy", root.path().join("near.npy")).unwrap();
    mkfifo(&root.path().join("pipe.npy"));
    let folder = Folder::open(root.path()).unwrap();
    assert_eq!(folder.file_names().unwrap(), ["a.npy", "b.npy"], "no subfolder, link or FIFO");
}

#[test]
fn a_growing_file_appears_whole_when_committed_replaces_a_link_and_vanishes_when_dropped() {
    use std::io::{Seek, SeekFrom, Write};
    let root = tempfile::tempdir().unwrap();
    let victim = tempfile::tempdir().unwrap();
    let target = victim.path().join("authorized_keys");
    fs::write(&target, b"keys\n").unwrap();
    symlink(&target, root.path().join("run.mcap")).unwrap();
    let folder = Folder::open(root.path()).unwrap();

    let mut growing = folder.create("run.mcap").unwrap();
    growing.write_all(b"hello, world").unwrap();
    growing.seek(SeekFrom::Start(0)).unwrap();
    growing.write_all(b"HELLO").unwrap();
    assert!(fs::symlink_metadata(root.path().join("run.mcap")).unwrap().file_type().is_symlink(), "not yet");
    assert_eq!(growing.commit().unwrap(), root.path().join("run.mcap"));
    assert_eq!(fs::read(root.path().join("run.mcap")).unwrap(), b"HELLO, world");
    assert_eq!(fs::read(&target).unwrap(), b"keys\n", "the link was replaced, not written through");

    let dropped = folder.create("half.mcap").unwrap();
    drop(dropped);
    let names: Vec<_> = fs::read_dir(root.path()).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names, vec![std::ffi::OsString::from("run.mcap")], "no temporary file is left");
    assert!(matches!(folder.create("../out.mcap").unwrap_err().problem, Problem::Outside { .. }));
}
