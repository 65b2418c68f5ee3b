//! End-to-end tests of `gudsl check`: run the built binary on files and folders, as CI does.

#[path = "support/cli.rs"]
mod cli;

use cli::{gudsl, repo, temp_dir};

use std::process::Command;

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
    let out = gudsl().args(["check", "--format", "concise", file.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.trim(), format!("{}:3:34: error[E0001]: expected `;` after the field", file.display()));
    // By default, the source line with the spot marked under it; no colour off a terminal.
    let out = gudsl().args(["check", file.to_str().unwrap()]).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let expected = format!(
        "error[E0001]: expected `;` after the field\n  ┌─ {}:3:34\n  │\n3 │     public class C {{ public int x }}\n  │                                  ^\n",
        file.display()
    );
    assert!(stdout.starts_with(&expected), "{stdout}");
    assert!(!stdout.contains('\x1b'), "no colour when stdout is not a terminal");
}

#[test]
fn colour_follows_the_flag_and_no_color() {
    let dir = temp_dir("colour");
    std::fs::write(dir.join("a.gudsl"), "ClassDiagram D { class C { int x } }\n").unwrap();
    let run = |color: &str, no_color: Option<&str>| {
        let mut command = gudsl();
        command.args(["check", "--color", color, dir.to_str().unwrap()]);
        command.env_remove("NO_COLOR");
        if let Some(value) = no_color {
            command.env("NO_COLOR", value);
        }
        String::from_utf8_lossy(&command.output().unwrap().stdout).into_owned()
    };
    assert!(run("always", None).contains("\x1b["), "--color always colours a pipe");
    assert!(run("always", Some("1")).contains("\x1b["), "an explicit flag beats NO_COLOR");
    assert!(!run("never", None).contains('\x1b'));
    assert!(!run("auto", None).contains('\x1b'), "auto: no colour into a pipe");
}

#[test]
fn check_defaults_to_the_current_folder() {
    let dir = temp_dir("default-folder");
    std::fs::create_dir_all(dir.join("sub")).unwrap();
    std::fs::write(dir.join("sub/a.gudsl"), "ClassDiagram D { class C { int x } }\n").unwrap();
    let out = gudsl().args(["check", "--format", "concise"]).current_dir(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&out.stdout).starts_with("sub/a.gudsl:1:"),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn every_path_is_reported_even_when_another_fails() {
    let dir = temp_dir("partial");
    std::fs::write(dir.join("a.gudsl"), "ClassDiagram D { class C { int x } }\n").unwrap();
    std::fs::write(dir.join("NOTES.md"), "# notes\n\nClassDiagram is not here.\n").unwrap();
    let out = gudsl()
        .args([
            "check",
            "--format",
            "concise",
            dir.to_str().unwrap(),
            "/nonexistent/gudsl",
            dir.join("NOTES.md").to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2), "an unreadable path is exit code 2");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stdout.lines().count(), 1, "the folder is still checked: {stdout}");
    assert!(stdout.contains("a.gudsl:1:"), "{stdout}");
    assert!(stderr.contains("/nonexistent/gudsl: No such file"), "{stderr}");
    assert!(stderr.contains("NOTES.md: not a `.gudsl` file"), "a named non-GU-DSL file is not parsed: {stderr}");
    assert!(stderr.contains("2 paths could not be read"), "{stderr}");
}

#[test]
fn deny_warnings_fails_on_warnings() {
    let dir = temp_dir("warnings");
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad()\n{\n    swimlane L\n    {\n        start S { => done; }\n        action orphan() { => done; }\n        final done;\n    }\n}\n",
    )
    .unwrap();
    let out = gudsl().args(["check", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(0), "warnings alone pass");
    assert!(String::from_utf8_lossy(&out.stdout).contains("warning[E0208]"));
    let out = gudsl().args(["check", "--deny-warnings", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn github_format_annotates_with_escaped_messages() {
    let dir = temp_dir("github");
    std::fs::write(dir.join("a.gudsl"), "ClassDiagram D { public class C { public Missing m; } }\n").unwrap();
    let out = gudsl().args(["check", "--format", "github", "a.gudsl"]).current_dir(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.starts_with("::error file=a.gudsl,line=1,col=42,endLine=1,endColumn=49,title=E0201 unknown or ambiguous type::unknown type `Missing`"),
        "{stdout}"
    );
}

/// Runs `tests/sarif/validate.py` (the SARIF 2.1.0 schema, formats included) on `sarif`.
fn sarif_violations(sarif: &[u8]) -> (bool, String) {
    let mut child = Command::new("python3")
        .arg(repo("tests/sarif/validate.py"))
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("python3 runs (the SARIF test needs Python 3 with jsonschema)");
    std::io::Write::write_all(&mut child.stdin.take().unwrap(), sarif).unwrap();
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("No module named 'jsonschema'") && out.status.code() != Some(2),
        "jsonschema is not installed: `python3 -m pip install 'jsonschema[format-nongpl]'` ({stderr}{})",
        String::from_utf8_lossy(&out.stdout)
    );
    (out.status.success(), format!("{}{stderr}", String::from_utf8_lossy(&out.stdout)))
}

#[test]
fn sarif_output_is_valid_sarif_2_1_0() {
    let dir = temp_dir("sarif");
    std::fs::create_dir_all(dir.join("with space")).unwrap();
    std::fs::write(dir.join("with space/ä.gudsl"), "ClassDiagram D { public class C { public Missing m; } }\n")
        .unwrap();
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad()\n{\n    swimlane L\n    {\n        start S { => done; }\n        action orphan() { => done; }\n        final done;\n    }\n}\n",
    )
    .unwrap();
    let out = gudsl()
        .args(["check", "--format", "sarif", ".", dir.join("ad.gudsl").to_str().unwrap(), "missing.gudsl"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let (valid, report) = sarif_violations(&out.stdout);
    assert!(valid, "{report}");
    let log: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let run = &log["runs"][0];
    assert_eq!(run["tool"]["driver"]["name"], "gudsl");
    let results = run["results"].as_array().unwrap();
    assert_eq!(results.len(), 2, "one file reached twice is checked once");
    let unknown = results.iter().find(|r| r["ruleId"] == "E0201").unwrap();
    let location = &unknown["locations"][0]["physicalLocation"];
    assert_eq!(location["artifactLocation"]["uri"], "with%20space/%C3%A4.gudsl");
    assert_eq!(location["artifactLocation"]["uriBaseId"], "%SRCROOT%");
    assert_eq!(location["region"]["startColumn"], 42);
    assert_eq!(run["tool"]["driver"]["rules"][unknown["ruleIndex"].as_u64().unwrap() as usize]["id"], "E0201");
    assert_eq!(run["invocations"][0]["executionSuccessful"], false);
    assert!(run["invocations"][0]["toolExecutionNotifications"][0]["message"]["text"]
        .as_str()
        .unwrap()
        .contains("missing.gudsl"));
    // The control: the validator does reject a broken log.
    let mut broken = log.clone();
    broken["runs"][0]["results"][0]["level"] = "fatal".into();
    assert!(!sarif_violations(&serde_json::to_vec(&broken).unwrap()).0);
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
fn semantic_errors_across_files_and_warnings() {
    let dir = temp_dir("semantic");
    std::fs::write(dir.join("defs.gudsl"), "ClassDiagram Defs { public class Image { } }\n").unwrap();
    std::fs::write(
        dir.join("ad.gudsl"),
        "ActivityDiagram Ad()\n{\n    swimlane L, owner Defs.Imag\n    {\n        start S { => done; }\n        action orphan { => done; }\n        final done;\n    }\n}\n",
    )
    .unwrap();
    let out = gudsl().args(["check", "--format", "concise", dir.to_str().unwrap()]).output().unwrap();
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
    // A file with syntax errors: what parsed is drawn, and the run says so and fails.
    let broken = temp_dir("render-broken");
    std::fs::write(broken.join("b.gudsl"), "ClassDiagram B { public class C { public int x } }\n").unwrap();
    let out = gudsl().args(["render", broken.to_str().unwrap(), "-o", out1.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr)
        .contains("b.gudsl: 1 syntax error(s); its diagrams are drawn from what parsed"));
    assert!(out1.join("B.svg").exists());
    let out = gudsl().args(["render", "no/such/path.gudsl", "-o", out1.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "an unreadable path is exit code 2");
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/path.gudsl"));
}

#[test]
fn a_duplicate_across_files_shows_where_the_other_declaration_is() {
    let dir = temp_dir("duplicate");
    std::fs::write(dir.join("a.gudsl"), "ActivityDiagram Ad()\n{\n    swimlane L { start S { => f; } final f; }\n}\n")
        .unwrap();
    std::fs::write(dir.join("b.gudsl"), "ActivityDiagram Ad()\n{\n    swimlane L { start S { => f; } final f; }\n}\n")
        .unwrap();
    let out = gudsl().args(["check", dir.to_str().unwrap()]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stdout = String::from_utf8_lossy(&out.stdout);
    // Each report points to the other file's declaration with a secondary label.
    assert!(stdout.contains("also declared in"), "{stdout}");
    assert_eq!(stdout.matches("`Ad` is also declared here").count(), 2, "{stdout}");
    assert!(stdout.contains(&format!("┌─ {}:1:17", dir.join("a.gudsl").display())), "{stdout}");
    assert!(stdout.contains(&format!("┌─ {}:1:17", dir.join("b.gudsl").display())), "{stdout}");

    // SARIF: the other declaration is a related location (valid SARIF 2.1.0).
    let out = gudsl().args(["check", "--format", "sarif", "."]).current_dir(&dir).output().unwrap();
    let (valid, report) = sarif_violations(&out.stdout);
    assert!(valid, "{report}");
    let log: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let results = log["runs"][0]["results"].as_array().unwrap();
    assert_eq!(results.len(), 2);
    for result in results {
        let own = &result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"];
        let related = &result["relatedLocations"][0];
        let other = &related["physicalLocation"]["artifactLocation"]["uri"];
        assert_ne!(own, other, "{result}");
        assert_eq!(related["physicalLocation"]["region"]["startLine"], 1, "{result}");
        assert_eq!(related["physicalLocation"]["region"]["startColumn"], 17, "{result}");
        assert!(related["message"]["text"].as_str().unwrap().contains("`Ad`"), "{result}");
    }

    // JSON: the same, as `related`.
    let out = gudsl().args(["check", "--format", "json", "."]).current_dir(&dir).output().unwrap();
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let first = &report["diagnostics"][0];
    assert!(first["path"].as_str().unwrap().ends_with("a.gudsl"), "{first}");
    let related = &first["related"][0];
    assert!(related["path"].as_str().unwrap().ends_with("b.gudsl"), "{first}");
    assert_eq!((related["line"].as_u64(), related["column"].as_u64()), (Some(1), Some(17)), "{first}");
}

#[test]
fn render_fits_a_long_flow_to_the_page_or_aspect_asked() {
    let out = temp_dir("render-page");
    let flow = repo("render/tests/reference/models/LongFlow.gudsl");
    let size = |args: &[&str]| {
        let mut all = vec!["render", flow.as_str(), "--format", "layout-json", "-o", out.to_str().unwrap()];
        all.extend_from_slice(args);
        let status = gudsl().args(&all).status().unwrap();
        assert!(status.success(), "{args:?}");
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("LongFlow.json")).unwrap()).unwrap();
        let nodes = json["nodes"].as_array().unwrap();
        let reach = |at: &str, size: &str| {
            nodes.iter().map(|n| n[at].as_f64().unwrap() + n[size].as_f64().unwrap()).fold(0.0, f64::max)
        };
        (reach("x", "w"), reach("y", "h"))
    };
    let screen = size(&[]);
    assert!(screen.0 > screen.1, "wrapped into columns for a landscape screen: {screen:?}");
    let wide = size(&["--aspect", "3:1"]);
    assert!(wide.0 / wide.1 > screen.0 / screen.1, "{wide:?} vs {screen:?}");
    let a4 = size(&["--page", "A4"]);
    assert!(a4.0 < a4.1, "upright on A4: {a4:?}");
    for (flag, value, said) in
        [("--aspect", "16x10", "W:H"), ("--aspect", "0:1", "no aspect ratio"), ("--page", "B5", "no paper")]
    {
        let run = gudsl().args(["render", flow.as_str(), flag, value, "-o", out.to_str().unwrap()]).output().unwrap();
        assert_eq!(run.status.code(), Some(2), "{flag} {value}");
        assert!(String::from_utf8_lossy(&run.stderr).contains(said), "{}", String::from_utf8_lossy(&run.stderr));
    }
}

#[test]
fn render_remember_keeps_the_rows_and_the_next_render_keeps_the_drawing() {
    let dir = temp_dir("render-remember");
    let model = dir.join("classes.gudsl");
    std::fs::copy(repo("render/tests/reference/models/Classes200.gudsl"), &model).unwrap();
    let sidecar = dir.join("classes.gudsl.layout");
    let render = |out: &str, remember: bool| {
        let mut args = vec!["render", model.to_str().unwrap(), "--format", "layout-json", "-o", out];
        if remember {
            args.push("--remember");
        }
        let run = gudsl().args(&args).current_dir(&dir).output().unwrap();
        (run.status.code(), String::from_utf8_lossy(&run.stderr).into_owned())
    };
    // Rendering alone writes nothing beside the model.
    assert_eq!(render("plain", false).0, Some(0));
    assert!(!sidecar.exists());
    assert_eq!(render("first", true).0, Some(0));
    let written = std::fs::read_to_string(&sidecar).unwrap();
    let layout: serde_json::Value = serde_json::from_str(&written).unwrap();
    let rows = layout["rows"]["Classes200"].as_array().unwrap();
    assert!(rows.iter().flat_map(|r| r.as_array().unwrap()).any(|e| e.as_str().unwrap().starts_with("Classes200.C0 ")));
    // Drawn again from its rows: the same bytes, and the rows as they were.
    assert_eq!(render("second", true).0, Some(0));
    let drawing = |out: &str| std::fs::read(dir.join(out).join("Classes200.json")).unwrap();
    assert_eq!(drawing("second"), drawing("first"));
    assert_eq!(drawing("first"), drawing("plain"));
    assert_eq!(std::fs::read_to_string(&sidecar).unwrap(), written);
    // A sidecar that is no layout is said and never overwritten.
    std::fs::write(&sidecar, "{ broken").unwrap();
    let (code, stderr) = render("third", true);
    assert_eq!(code, Some(2), "{stderr}");
    assert!(stderr.contains("classes.gudsl.layout") && stderr.contains("not overwritten"), "{stderr}");
    assert_eq!(std::fs::read_to_string(&sidecar).unwrap(), "{ broken");
}
