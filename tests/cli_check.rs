//! End-to-end tests of `gudsl check`: run the built binary on files and folders, as CI does.

use std::{path::Path, process::Command};

fn gudsl() -> Command {
    Command::new(env!("CARGO_BIN_EXE_gudsl"))
}

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path).to_string_lossy().into_owned()
}

fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("gudsl-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn samples_check_clean() {
    let out = gudsl().args(["check", &repo("samples")]).output().unwrap();
    assert!(out.status.success(), "{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.stdout.is_empty());
    assert!(String::from_utf8_lossy(&out.stderr).contains("0 errors"));
}

#[test]
fn broken_file_reports_path_line_column_code_and_exits_1() {
    let dir = temp_dir("broken");
    let file = dir.join("broken.gudsl");
    std::fs::write(&file, "ClassDiagram D\n{\n    public class C { public int x }\n}\n").unwrap();
    let out = gudsl().args(["check", file.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.trim(), format!("{}:3:34: error[E0001]: expected `;` after the field", file.display()));
}

#[test]
fn json_format_is_machine_readable() {
    let dir = temp_dir("json");
    std::fs::write(dir.join("a.gudsl"), "ClassDiagram A { }\n").unwrap();
    // Columns count characters: the emoji and umlaut are one column each.
    std::fs::write(dir.join("b.gudsl"), "// ä😀\nClassDiagram B { class C { int x } }\n").unwrap();
    let out = gudsl().args(["check", "--format", "json", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["files"], 2);
    assert_eq!(report["errors"], 1);
    let d = &report["diagnostics"][0];
    assert!(d["path"].as_str().unwrap().ends_with("b.gudsl"));
    assert_eq!((d["line"].as_u64(), d["column"].as_u64()), (Some(2), Some(33)));
    assert_eq!(d["code"], "E0001");
    assert_eq!(d["severity"], "error");
}

#[test]
fn missing_path_exits_2() {
    let out = gudsl().args(["check", "/nonexistent/gudsl/path"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent/gudsl/path"));
}

#[test]
fn no_path_is_a_usage_error() {
    let out = gudsl().arg("check").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn semantic_errors_across_files_and_warnings() {
    let dir = temp_dir("semantic");
    std::fs::write(dir.join("defs.gudsl"), "ClassDiagram Defs { public class Image { } }\n").unwrap();
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad()\n{\n    swimlane L, owner Defs.Imag\n    {\n        start S { => done; }\n        action orphan { => done; }\n        final done;\n    }\n}\n",
    )
    .unwrap();
    let out = gudsl().args(["check", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let ad = dir.join("ad.gudsl");
    assert!(
        stdout.contains(&format!("{}:3:23: error[E0202]: unknown owner class `Defs.Imag`", ad.display())),
        "{stdout}"
    );
    assert!(
        stdout.contains(&format!("{}:6:16: warning[E0208]: node `orphan` is never reached", ad.display())),
        "{stdout}"
    );
    assert!(String::from_utf8_lossy(&out.stderr).contains("1 error, 1 warning"));
    // Fixing the owner leaves only the warning: exit 0.
    std::fs::write(dir.join("defs.gudsl"), "ClassDiagram Defs { public class Imag { } }\n").unwrap();
    let out = gudsl().args(["check", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "{}", String::from_utf8_lossy(&out.stdout));
}

#[test]
fn fmt_formats_in_place_and_check_reports() {
    let dir = temp_dir("fmt");
    let file = dir.join("a.gudsl");
    std::fs::write(&file, "ClassDiagram A{public class C{public int x=1;}}\n").unwrap();
    let out = gudsl().args(["fmt", "--check", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stdout).contains("a.gudsl"));
    let out = gudsl().args(["fmt", dir.to_str().unwrap()]).output().unwrap();
    assert!(out.status.success());
    assert_eq!(
        std::fs::read_to_string(&file).unwrap(),
        "ClassDiagram A\n{\n    public class C\n    {\n        public int x = 1;\n    }\n}\n"
    );
    let out = gudsl().args(["fmt", "--check", dir.to_str().unwrap()]).output().unwrap();
    assert!(out.status.success(), "formatted output is stable");
    // A file with syntax errors is left alone and reported.
    std::fs::write(&file, "ClassDiagram A { class C { int x } }\n").unwrap();
    let out = gudsl().args(["fmt", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("syntax error"));
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "ClassDiagram A { class C { int x } }\n");
}

#[test]
fn render_writes_identical_svg_and_png_per_diagram() {
    let out1 = temp_dir("render1");
    let out2 = temp_dir("render2");
    for out in [&out1, &out2] {
        let status = gudsl()
            .args(["render", &repo("samples"), "--diagram", "ComponentExampleDiagram", "-o", out.to_str().unwrap()])
            .status()
            .unwrap();
        assert!(status.success());
    }
    let a = std::fs::read(out1.join("ComponentExampleDiagram.svg")).unwrap();
    let b = std::fs::read(out2.join("ComponentExampleDiagram.svg")).unwrap();
    assert_eq!(a, b, "byte-identical output for identical input");
    assert!(String::from_utf8_lossy(&a).contains("data-id=\"ComponentClassDefinitions.Camera\""));
    let status = gudsl()
        .args([
            "render",
            &repo("samples/seed/listing08_member_access.gudsl"),
            "--format",
            "png",
            "-o",
            out1.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    assert!(std::fs::read(out1.join("AdMemberAccess.png")).unwrap().starts_with(b"\x89PNG"));
    let out = gudsl()
        .args(["render", &repo("samples"), "--diagram", "NoSuchDiagram", "-o", out1.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no diagram named `NoSuchDiagram`"));
    let out = gudsl().args(["render", "no/such/path.gudsl", "-o", out1.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "an unreadable path is exit code 2");
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/path.gudsl"));
}
