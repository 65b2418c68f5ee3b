//! Tests of the semantic layer: incrementality (counted query executions) and rule behaviour.

use salsa::Setter;

use super::*;
use crate::db::{RootDatabase, SourceFile, Workspace};

const DEFS: &str = "ClassDiagram Defs
{
    public class Image
    {
        public int width;
        public int area() { return width * width; }
    }
    public class Unused { }
}
";

const USER: &str = "ActivityDiagram Ad(int n)
{
    swimlane Lane, owner Defs.Image
    {
        start S { => work; }
        action work { var int x = n + 1; => done; }
        final done;
    }
}
";

const OTHER: &str = "ClassDiagram Other
{
    public class Standalone { public bool flag; }
}
";

struct Fixture {
    db: RootDatabase,
    workspace: Workspace,
    files: Vec<SourceFile>,
}

fn fixture() -> Fixture {
    let db = RootDatabase::default();
    let files: Vec<SourceFile> = [("defs.gudsl", DEFS), ("user.gudsl", USER), ("other.gudsl", OTHER)]
        .iter()
        .map(|(path, text)| SourceFile::new(&db, path.to_string(), text.to_string()))
        .collect();
    let workspace = Workspace::new(&db, files.clone());
    Fixture { db, workspace, files }
}

impl Fixture {
    fn check_all(&self) -> usize {
        self.files.iter().map(|&f| file_diagnostics(&self.db, self.workspace, f).len()).sum()
    }

    fn edit(&mut self, file: usize, from: &str, to: &str) {
        let text = self.files[file].text(&self.db).replacen(from, to, 1);
        assert_ne!(&text, self.files[file].text(&self.db), "edit did not apply");
        self.files[file].set_text(&mut self.db).to(text);
    }

    fn executed(&self, query: &str) -> usize {
        self.db.take_executions().iter().filter(|e| e.starts_with(&format!("{query}("))).count()
    }

    fn executions(&self) -> Vec<String> {
        self.db.take_executions()
    }
}

fn count(executions: &[String], query: &str) -> usize {
    executions.iter().filter(|e| e.starts_with(&format!("{query}("))).count()
}

#[test]
fn fixture_checks_clean() {
    let f = fixture();
    for &file in &f.files {
        assert_eq!(file_diagnostics(&f.db, f.workspace, file), &Vec::new(), "{}", file.path(&f.db));
    }
}

#[test]
fn typing_in_a_method_body_reruns_no_def_map_and_no_other_file() {
    let mut f = fixture();
    f.check_all();
    f.db.record_executions();
    f.edit(0, "return width * width;", "return width * width + 1;");
    f.check_all();
    let log = f.executions();
    assert_eq!(count(&log, "parse"), 1, "{log:#?}");
    // The edited file's item tree runs once, finds it unchanged and is backdated ...
    assert_eq!(count(&log, "item_tree"), 1, "{log:#?}");
    // ... so the definition map, every lookup and the other files' checks are reused.
    assert_eq!(count(&log, "def_map"), 0, "{log:#?}");
    assert_eq!(count(&log, "lookup"), 0, "{log:#?}");
    assert_eq!(count(&log, "check_file"), 1, "{log:#?}");
}

#[test]
fn typing_in_an_action_body_reruns_no_def_map_and_no_other_file() {
    let mut f = fixture();
    f.check_all();
    f.db.record_executions();
    f.edit(1, "var int x = n + 1;", "var int x = n + 2; // tweak");
    f.check_all();
    let log = f.executions();
    assert_eq!(count(&log, "def_map"), 0, "{log:#?}");
    assert_eq!(count(&log, "check_file"), 1, "{log:#?}");
    assert_eq!(count(&log, "file_diagnostics"), 1, "{log:#?}");
}

#[test]
fn renaming_a_class_rechecks_exactly_its_dependents() {
    let mut f = fixture();
    f.check_all();
    f.db.record_executions();
    f.edit(0, "public class Image", "public class Picture");
    let diagnostics = f.check_all();
    let log = f.executions();
    assert_eq!(count(&log, "def_map"), 1, "{log:#?}");
    // defs.gudsl (edited) and user.gudsl (uses Defs.Image) are re-checked; other.gudsl is not.
    assert_eq!(count(&log, "check_file"), 2, "{log:#?}");
    assert_eq!(diagnostics, 1, "the owner Defs.Image no longer resolves");
}

#[test]
fn renaming_an_unused_class_rechecks_only_its_file() {
    let mut f = fixture();
    f.check_all();
    f.db.record_executions();
    f.edit(0, "public class Unused", "public class NoLongerUsed");
    f.check_all();
    assert_eq!(f.executed("check_file"), 1);
}

#[test]
fn editing_one_file_keeps_the_other_files_diagnostics() {
    let mut f = fixture();
    f.check_all();
    f.db.record_executions();
    f.edit(2, "public bool flag;", "public bool flag; public int count;");
    f.check_all();
    let log = f.executions();
    // A declaration changed, so the def map runs; no name the other files use changed.
    assert_eq!(count(&log, "def_map"), 1, "{log:#?}");
    assert_eq!(count(&log, "check_file"), 1, "{log:#?}");
}
