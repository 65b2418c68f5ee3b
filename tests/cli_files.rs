//! `gudsl check` and `gudsl fmt` on hostile folders and files: a FIFO, symbolic-link loops, a
//! link to `/dev/zero`, an oversized file, text that is not UTF-8, CRLF and lone-CR line ends, a
//! byte-order mark, and a disk that fills up mid-write. Nothing may hang, read a file twice,
//! or lose a byte of what the user wrote.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, run_within, temp_dir};

use std::{
    os::unix::fs::symlink,
    path::Path,
    process::{Command, Output},
};

fn check(dir: &Path) -> Output {
    let mut command = gudsl();
    command.args(["check", "--format", "concise", dir.to_str().unwrap()]);
    run_within(&mut command, 30)
}

const CLASSES: &str = "ClassDiagram D { public class C { public int x; } }\n";

#[test]
fn a_fifo_a_device_link_and_a_huge_file_are_refused_not_read() {
    let dir = temp_dir("special");
    std::fs::write(dir.join("a.gudsl"), CLASSES).unwrap();
    let fifo = dir.join("x.gudsl");
    assert!(Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    symlink("/dev/zero", dir.join("zero.gudsl")).unwrap();
    // Sparse: 17 MiB on paper, nothing on disk.
    std::fs::File::create(dir.join("huge.gudsl")).unwrap().set_len(17 << 20).unwrap();
    let out = check(&dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("x.gudsl: not a regular file"), "{stderr}");
    assert!(stderr.contains("zero.gudsl: not a regular file"), "{stderr}");
    assert!(stderr.contains("huge.gudsl: 17825792 bytes: larger than"), "{stderr}");
    assert!(stderr.contains("checked 1 file: 0 errors"), "the readable file is checked: {stderr}");
}

#[test]
fn symbolic_link_loops_are_cut_and_each_file_read_once() {
    let dir = temp_dir("loops");
    std::fs::write(dir.join("a.gudsl"), CLASSES).unwrap();
    symlink(".", dir.join("loop1")).unwrap();
    symlink(".", dir.join("loop2")).unwrap();
    std::fs::create_dir(dir.join("sub")).unwrap();
    symlink("..", dir.join("sub/up")).unwrap();
    // A link to a file is followed, but the file is read once.
    symlink("a.gudsl", dir.join("alias.gudsl")).unwrap();
    let out = check(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "no E0205 from reading a file twice: {stdout}{stderr}");
    assert!(stderr.contains("checked 1 file"), "{stderr}");
}

#[test]
fn ignored_and_hidden_entries_are_skipped() {
    let dir = temp_dir("ignored");
    std::fs::write(dir.join("a.gudsl"), CLASSES).unwrap();
    for skipped in ["target", "node_modules", ".hidden", "generated"] {
        std::fs::create_dir(dir.join(skipped)).unwrap();
        std::fs::write(dir.join(skipped).join("broken.gudsl"), "ClassDiagram {").unwrap();
    }
    std::fs::write(dir.join(".gitignore"), "generated/\n").unwrap();
    // `.gitignore` counts inside a git repository, as for ripgrep.
    std::fs::create_dir(dir.join(".git")).unwrap();
    let out = check(&dir);
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stdout));
    // Named explicitly, an ignored file is checked.
    let out = check(&dir.join("generated/broken.gudsl"));
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn fmt_refuses_text_that_is_not_utf8() {
    let dir = temp_dir("latin1");
    let file = dir.join("a.gudsl");
    // `é` in Latin-1 in a comment, in an otherwise unformatted file.
    let bytes = b"// caf\xe9\nClassDiagram A{public class C{}}\n".to_vec();
    std::fs::write(&file, &bytes).unwrap();
    let out = run_within(
        &mut {
            let mut c = gudsl();
            c.args(["fmt", file.to_str().unwrap()]);
            c
        },
        30,
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("not UTF-8 (line 1, byte 7 of the line)"), "{stderr}");
    assert!(stderr.contains("iconv"), "the message says how to convert: {stderr}");
    assert_eq!(std::fs::read(&file).unwrap(), bytes, "not a byte changed");
}

/// A few hundred unformatted classes: the formatted text is larger than the original.
fn big_unformatted() -> String {
    let mut text = String::from("ClassDiagram Big{");
    for i in 0..400 {
        text += &format!("public class C{i}{{public int x{i}=1;public void m(int a){{x{i}=a;}}}}");
    }
    text + "}\n"
}

/// `gudsl fmt FILE` with the file size limit at `blocks` KiB; `ignore_signal`: the write fails
/// with EFBIG instead of the process being killed by SIGXFSZ.
fn fmt_with_file_size_limit(file: &Path, blocks: u32, ignore_signal: bool) -> Output {
    let trap = if ignore_signal { "trap '' XFSZ; " } else { "" };
    let mut command = Command::new("bash");
    command
        .arg("-c")
        .arg(format!("{trap}ulimit -f {blocks}; exec \"$0\" fmt \"$1\""))
        .arg(env!("CARGO_BIN_EXE_gudsl"))
        .arg(file);
    run_within(&mut command, 30)
}

#[test]
fn fmt_that_fails_mid_write_leaves_the_original_intact() {
    let dir = temp_dir("full-disk");
    let file = dir.join("big.gudsl");
    let original = big_unformatted();
    assert!(original.len() > 16 << 10);
    for ignore_signal in [true, false] {
        std::fs::write(&file, &original).unwrap();
        let out = fmt_with_file_size_limit(&file, 8, ignore_signal);
        assert!(!out.status.success());
        let after = std::fs::read_to_string(&file).unwrap();
        assert!(
            after == original,
            "the original is whole: {} of {} bytes left (signal ignored: {ignore_signal})",
            after.len(),
            original.len()
        );
        if ignore_signal {
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(stderr.contains("File too large") && stderr.contains("the file is unchanged"), "{stderr}");
            let left: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
            assert_eq!(left.len(), 1, "no temporary file left behind: {left:?}");
        }
    }
    // Without the limit it is formatted, and a link to it stays a link.
    let link = dir.join("link.gudsl");
    symlink("big.gudsl", &link).unwrap();
    let out = run_within(
        &mut {
            let mut c = gudsl();
            c.args(["fmt", link.to_str().unwrap()]);
            c
        },
        60,
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
    assert!(std::fs::read_to_string(&file).unwrap().starts_with("ClassDiagram Big\n{\n    public class C0\n"));
}

#[test]
fn fmt_keeps_crlf_lone_cr_and_the_byte_order_mark() {
    let dir = temp_dir("line-ends");
    let file = dir.join("a.gudsl");
    for (eol, bom) in [("\r\n", ""), ("\r", ""), ("\n", "\u{feff}"), ("\r\n", "\u{feff}")] {
        let input = format!("{bom}ClassDiagram A{{{eol}// c{eol}public class C{{}}}}{eol}");
        std::fs::write(&file, &input).unwrap();
        let out = run_within(
            &mut {
                let mut c = gudsl();
                c.args(["fmt", file.to_str().unwrap()]);
                c
            },
            30,
        );
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let expected = format!("{bom}ClassDiagram A{eol}{{{eol}    // c{eol}    public class C {{ }}{eol}}}{eol}");
        assert_eq!(std::fs::read_to_string(&file).unwrap(), expected, "{eol:?} {bom:?}");
    }
}

#[test]
fn check_reports_lines_and_columns_of_crlf_and_lone_cr_documents() {
    let dir = temp_dir("cr");
    for (name, eol) in [("lf.gudsl", "\n"), ("crlf.gudsl", "\r\n"), ("cr.gudsl", "\r")] {
        let text = format!(
            "\u{feff}ClassDiagram {}{eol}{{{eol}    // note{eol}    public class C {{ public Missing m; }}{eol}}}{eol}",
            name.replace(".gudsl", "")
        );
        std::fs::write(dir.join(name), text).unwrap();
    }
    let out = check(&dir);
    let stdout = String::from_utf8_lossy(&out.stdout);
    for name in ["lf.gudsl", "crlf.gudsl", "cr.gudsl"] {
        assert!(stdout.contains(&format!("{name}:4:29: error[E0201]")), "{stdout}");
    }
    assert_eq!(stdout.lines().count(), 3, "no error for the byte-order mark: {stdout}");
}
