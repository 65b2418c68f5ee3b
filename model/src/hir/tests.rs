//! Tests of the semantic layer: incrementality (counted query executions) and rule behaviour.

use salsa::Setter;

use super::*;
use crate::ast::AstNode;
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
    let db = RootDatabase::with_execution_log();
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
    f.db.take_executions();
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
    f.db.take_executions();
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
    f.db.take_executions();
    f.edit(0, "public class Image", "public class Picture");
    let diagnostics = f.check_all();
    let log = f.executions();
    // No workspace-wide map is rebuilt: only the namespace `Defs` is re-read.
    assert_eq!(count(&log, "def_map"), 0, "{log:#?}");
    assert_eq!(count(&log, "namespace_files"), 0, "{log:#?}");
    assert_eq!(count(&log, "namespace_definitions"), 1, "{log:#?}");
    // defs.gudsl (edited) and user.gudsl (uses Defs.Image) are re-checked; other.gudsl is not.
    assert_eq!(count(&log, "check_file"), 2, "{log:#?}");
    assert_eq!(diagnostics, 1, "the owner Defs.Image no longer resolves");
}

#[test]
fn renaming_an_unused_class_rechecks_only_its_file() {
    let mut f = fixture();
    f.check_all();
    f.db.take_executions();
    f.edit(0, "public class Unused", "public class NoLongerUsed");
    f.check_all();
    assert_eq!(f.executed("check_file"), 1);
}

#[test]
fn editing_one_file_keeps_the_other_files_diagnostics() {
    let mut f = fixture();
    f.check_all();
    f.db.take_executions();
    f.edit(2, "public bool flag;", "public bool flag; public int count;");
    f.check_all();
    let log = f.executions();
    // A declaration changed, so its namespace is re-read; no name the other files use changed.
    assert_eq!(count(&log, "namespace_definitions"), 1, "{log:#?}");
    assert_eq!(count(&log, "check_file"), 1, "{log:#?}");
}

#[test]
fn a_caller_of_a_behavior_is_rechecked_when_its_result_changes_not_on_every_edit() {
    let db = RootDatabase::with_execution_log();
    let callee = "ActivityDiagram AdCount(int n)
{
    var int count = 0;
    swimlane L
    {
        start S { => work; }
        action work { count = n * 2; => done; }
        final done return count;
    }
}
";
    let caller = "ActivityDiagram AdUse()
{
    var int total;
    swimlane L
    {
        start S { => use; }
        action use { total = call behavior AdCount(3); => done; }
        final done;
    }
}
";
    let files = vec![
        SourceFile::new(&db, "callee.gudsl".into(), callee.into()),
        SourceFile::new(&db, "caller.gudsl".into(), caller.into()),
    ];
    let mut f = Fixture { workspace: Workspace::new(&db, files.clone()), db, files };
    assert_eq!(f.check_all(), 0);
    f.db.take_executions();
    // The callee's body changes, its result (`int`) does not: the caller is not re-checked.
    f.edit(0, "count = n * 2;", "count = n * 3;");
    assert_eq!(f.check_all(), 0);
    let log = f.executions();
    assert_eq!(count(&log, "behavior_result"), 1, "{log:#?}");
    assert_eq!(count(&log, "check_file"), 1, "{log:#?}");
    // The result becomes a string: the caller is re-checked and its assignment is an error.
    f.edit(0, "final done return count;", "final done return \"many\";");
    assert_eq!(f.check_all(), 1);
    let log = f.executions();
    assert_eq!(count(&log, "check_file"), 2, "{log:#?}");
    let messages: Vec<String> =
        file_diagnostics(&f.db, f.workspace, f.files[1]).iter().map(|d| d.message.clone()).collect();
    assert!(messages[0].contains("`total` has type `int`, but the value is `string`"), "{messages:?}");
}

// ---- the Semantics API

/// A database of `files`, and the offset of `needle` in the first one.
fn workspace_of(files: &[(&str, &str)]) -> (RootDatabase, Workspace, Vec<SourceFile>) {
    let db = RootDatabase::default();
    let inputs: Vec<SourceFile> =
        files.iter().map(|(path, text)| SourceFile::new(&db, path.to_string(), text.to_string())).collect();
    let workspace = Workspace::new(&db, inputs.clone());
    (db, workspace, inputs)
}

/// The node of type `N` whose text is `needle` (or the innermost one where it starts).
fn node_at<N: crate::ast::AstNode>(db: &RootDatabase, file: SourceFile, needle: &str) -> N {
    let at = file.text(db).find(needle).unwrap_or_else(|| panic!("`{needle}` not in the file"));
    let token = crate::db::parse(db, file).syntax_node().token_at_offset((at as u32).into()).right_biased().unwrap();
    let candidates: Vec<N> = token.parent_ancestors().filter_map(N::cast).collect();
    let exact = candidates.iter().position(|n| n.syntax().text() == needle.trim_end());
    candidates.into_iter().nth(exact.unwrap_or(0)).unwrap_or_else(|| panic!("no such node at `{needle}`"))
}

#[test]
fn type_of_an_expression_in_its_body() {
    let (db, ws, files) = workspace_of(&[("user.gudsl", USER), ("defs.gudsl", DEFS)]);
    let sema = Semantics::new(&db, ws);
    let ty_of = |needle: &str| sema.type_of_expr(&node_at::<crate::ast::Expr>(&db, files[0], needle)).to_string();
    // A diagram parameter, arithmetic on it, a local declared in the body.
    assert_eq!(ty_of("n + 1"), "int");
    let (db, ws, files) = workspace_of(&[
        (
            "ad.gudsl",
            "ActivityDiagram Ad(Defs.Image img) { swimlane L, owner Defs.Image { start S { var float f = img.width * 0.5; var int a = area(); => f2; } final f2; } }",
        ),
        ("defs.gudsl", DEFS),
    ]);
    let sema = Semantics::new(&db, ws);
    let ty_of = |needle: &str| sema.type_of_expr(&node_at::<crate::ast::Expr>(&db, files[0], needle)).to_string();
    assert_eq!(ty_of("img.width"), "int", "a field of a parameter's class");
    assert_eq!(ty_of("img.width * 0.5"), "float");
    assert_eq!(ty_of("img."), "Defs.Image");
    assert_eq!(ty_of("area()"), "int", "a method of the swimlane's owner");
}

#[test]
fn enum_constants_are_numbered_as_c_numbers_them() {
    let text = "ClassDiagram Defs { public enum Mode { A, B = 4, C, D = -1, E, F = (7), G } }";
    let (db, ws, _) = workspace_of(&[("defs.gudsl", text)]);
    let sema = Semantics::new(&db, ws);
    let values: Vec<Option<i64>> = ["A", "B", "C", "D", "E", "F", "G", "H"]
        .into_iter()
        .map(|member| sema.enum_value("Defs.Mode", member))
        .collect();
    assert_eq!(values, [Some(0), Some(4), Some(5), Some(-1), Some(0), Some(7), Some(8), None]);
    assert_eq!(sema.enum_value("Defs", "A"), None, "a class diagram is no enum");
}

#[test]
fn body_types_give_every_expression_of_a_node_and_its_locals() {
    let text = "ActivityDiagram Ad(int4 pixel, int n)
{
    var float scale = 0.5f;
    swimlane L
    {
        start S { => work; }
        loopWindow work(var int u = -n; u <= n; u = u + 1)
        {
            var float3 f = new float3(pixel._x / 255.0f, pixel.y, 1.0f);
            var int2 xy = pixel.xy;
            var float s = f.s0 * scale + u;
            [u > 0] => done;
        }
        final done;
    }
}
";
    let (db, ws, files) = workspace_of(&[("ad.gudsl", text)]);
    let sema = Semantics::new(&db, ws);
    let body: crate::ast::NodeBody = node_at(&db, files[0], "{\n            var float3");
    let types = sema.body_types(body.syntax());
    let expr = |needle: &str| node_at::<crate::ast::Expr>(&db, files[0], needle);
    let ty = |needle: &str| types.of(&expr(needle)).to_string();
    assert_eq!(ty("pixel._x / 255.0f"), "float");
    assert_eq!(ty("pixel._x"), "int");
    assert_eq!(ty("pixel.xy"), "int2", "a swizzle of two components is a vector");
    assert_eq!(ty("f.s0 * scale + u"), "float");
    assert_eq!(ty("u > 0"), "bool", "guards are typed");
    assert_eq!(ty("-n"), "int", "the loop header is typed");
    assert_eq!(types.locals.get("xy").map(|t| t.to_string()).as_deref(), Some("int2"));
    assert_eq!(types.locals.get("scale").map(|t| t.to_string()).as_deref(), Some("float"));
    assert_eq!(types.of(&expr("0.5f")).to_string(), "?", "the variable section is another body");
    let diagram: crate::ast::ActivityDiagram = node_at(&db, files[0], "ActivityDiagram Ad");
    assert_eq!(sema.body_types(diagram.syntax()).of(&expr("0.5f")).to_string(), "float");
}

#[test]
fn names_classified_where_they_are_written() {
    use crate::{ast, hir::classify::NameRefClass};
    let (db, ws, files) = workspace_of(&[("user.gudsl", USER), ("defs.gudsl", DEFS)]);
    let sema = Semantics::new(&db, ws);
    let class = |needle: &str| sema.classify_name_ref(&node_at::<ast::NameRef>(&db, files[0], needle));
    // `Defs.Image`: the first segment is the class diagram, the second the class.
    assert!(matches!(class("Defs.Image"), Some(NameRefClass::Definition(d)) if d.fqn == "Defs"));
    assert!(matches!(class("Image\n"), Some(NameRefClass::Definition(d)) if d.fqn == "Defs.Image"));
    assert!(matches!(class("work; }"), Some(NameRefClass::Node(n)) if n.kind() == ast::NodeKind::Action));
    assert!(matches!(class("n + 1"), Some(NameRefClass::Local(decl)) if decl.kind() == crate::SyntaxKind::PARAM));
    let (db, ws, files) = workspace_of(&[
        ("ad.gudsl", "ActivityDiagram Ad() { swimlane L, owner Defs.Image { start S { width = 2; => f; } final f; } }"),
        ("defs.gudsl", DEFS),
    ]);
    let sema = Semantics::new(&db, ws);
    match sema.classify_name_ref(&node_at::<ast::NameRef>(&db, files[0], "width")) {
        Some(NameRefClass::Member { owner, member }) => {
            assert_eq!(owner.fqn, "Defs.Image");
            assert_eq!(member.syntax().text().to_string(), "public int width;");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn binding_ends_name_instances_ports_and_connectors() {
    use crate::hir::instances::{BindingEnd, UnresolvedEnd};
    let seed = |name: &str| {
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/seed").join(name))
            .unwrap()
    };
    let instances = seed("listing28_component_instance_example.gudsl");
    let components = seed("listing27_component_example.gudsl");
    let classes = seed("listing26_component_classes_example.gudsl");
    let (db, ws, files) = workspace_of(&[("i.gudsl", &instances), ("c.gudsl", &components), ("k.gudsl", &classes)]);
    let sema = Semantics::new(&db, ws);
    let diagram: crate::ast::ComponentInstanceDiagram = node_at(&db, files[0], "Camera1 instantiates");
    let map = sema.instances(&diagram);
    let camera = map.get("Camera1").unwrap();
    assert_eq!(camera.class.unwrap().fqn, "ComponentClassDefinitions.Camera");
    assert!(!camera.components.is_empty());
    let binding: crate::ast::Binding = node_at(&db, files[0], "source Camera1ProviderPort");
    use crate::ast::HasEnds;
    let source = map.binding_end("Camera1", &binding.source().unwrap()).unwrap();
    let target = map.binding_end("Camera1", &binding.target().unwrap()).unwrap();
    assert_eq!(source.instance, "Camera1");
    assert_eq!(target.instance, "MeanFilter1");
    assert!(map.connects(&source, &target), "{source:?} {target:?}");
    let elsewhere = BindingEnd { connector: "Nothing".into(), ..target.clone() };
    assert!(!map.connects(&source, &elsewhere));
    let missing =
        crate::parse("ComponentInstanceDiagram X { A instantiates B () { [ source Nobody.P.C ==> target Q.C ] } }");
    let path =
        missing.syntax_node().descendants().filter_map(crate::ast::Path::cast).find(|p| p.text() == "Nobody.P.C");
    let path = path.unwrap();
    assert_eq!(map.binding_end("Camera1", &path), Err(UnresolvedEnd::NoInstance("Nobody".into())));
}

#[test]
fn a_duplicate_points_to_the_first_declaration_in_its_file_or_another() {
    let db = RootDatabase::default();
    let a = SourceFile::new(&db, "a.gudsl".into(), "ClassDiagram A { public class C { } public class C { } }".into());
    let b = SourceFile::new(
        &db,
        "b.gudsl".into(),
        "ActivityDiagram Ad() { swimlane L { start S { => f; } final f; } }".into(),
    );
    let c = SourceFile::new(
        &db,
        "c.gudsl".into(),
        "ActivityDiagram Ad() { swimlane L { start S { => f; } final f; } }".into(),
    );
    let workspace = Workspace::new(&db, vec![a, b, c]);
    let in_a = file_diagnostics(&db, workspace, a);
    assert_eq!(in_a.len(), 1, "{in_a:?}");
    let related = &in_a[0].related;
    assert_eq!(related.len(), 1);
    assert_eq!((related[0].file, &a.text(&db)[related[0].range]), (a, "C"));
    assert!(related[0].range.start() < in_a[0].range.start(), "the first one: {in_a:?}");
    let in_b = file_diagnostics(&db, workspace, b);
    let across =
        in_b.iter().find(|d| d.message.contains("also declared in c.gudsl")).expect("a duplicate across files");
    assert_eq!(across.related[0].file, c);
    assert_eq!(&c.text(&db)[across.related[0].range], "Ad");
}
