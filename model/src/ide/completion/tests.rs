//! Tests of completion: what is proposed where the cursor is.

use super::{names::FAR_TYPES, *};

fn labels(files: &[(&str, &str)]) -> Vec<String> {
    let (db, ws, inputs, cursor) = super::super::test_fixture::with_cursor(files);
    completions(&db, ws, inputs[0], cursor).items.into_iter().map(|i| i.label).collect()
}

#[test]
fn node_names_after_a_transition_arrow() {
    let found =
        labels(&[("a.gudsl", "ActivityDiagram Ad() { swimlane L { start S { => $0 } action work { } final done; } }")]);
    assert_eq!(found, ["S", "done", "work"]);
}

#[test]
fn qualified_names_after_a_dot_and_enum_values() {
    let defs = ("d.gudsl", "ClassDiagram Defs { class Image { } enum Mode { Fast, Slow } ClassDiagram Inner { } }");
    let found = labels(&[("a.gudsl", "ClassDiagram U { class C { public Defs.$0 x; } }"), defs]);
    assert_eq!(found, ["Image", "Inner", "Mode"]);
    let found = labels(&[
        ("a.gudsl", "ActivityDiagram Ad() { swimlane L { start S { var Defs.Mode m = Defs.Mode.$0 } } }"),
        defs,
    ]);
    assert_eq!(found, ["Fast", "Slow"]);
}

#[test]
fn owner_members_and_locals_in_an_action() {
    let found = labels(&[
        ("a.gudsl", "ActivityDiagram Ad(int n) { swimlane L, owner Defs.Image { start S { => a; } action a(int k) { var int x = 1; $0 } } }"),
        ("d.gudsl", "ClassDiagram Defs { class Base { public int width; } class Image extends Base { public void grow(int by); } }"),
    ]);
    for expected in ["width", "grow", "x", "k", "n", "var", "=> transition"] {
        assert!(found.contains(&expected.to_string()), "{expected} missing from {found:?}");
    }
}

#[test]
fn members_of_a_variable_after_a_dot() {
    let found = labels(&[
        ("a.gudsl", "ActivityDiagram Ad() { swimlane L { start S { var Defs.Image img = null; img.$0 } } }"),
        ("d.gudsl", "ClassDiagram Defs { class Base { public int id; } class Image extends Base { public int width; public void grow(int by); } }"),
    ]);
    assert_eq!(found, ["grow", "id", "width"]);
}

#[test]
fn interfaces_after_a_connector_colon_and_fields_in_instantiates() {
    let defs = (
        "d.gudsl",
        "ClassDiagram Defs { interface provider Out { } interface processor In { } source Camera { public int width; public int height; } }",
    );
    let found =
        labels(&[("a.gudsl", "ComponentDiagram C { source Defs.Camera { port P ( provider p : $0 ) } }"), defs]);
    assert_eq!(found, ["Defs.Out"]);
    let found = labels(&[("a.gudsl", "ComponentInstanceDiagram I { C1 instantiates Defs.Camera ($0) }"), defs]);
    assert_eq!(found, ["height", "width"]);
}

#[test]
fn port_instances_and_connectors_in_bindings() {
    let doc = |cursor: &str| {
        format!(
            "ComponentInstanceDiagram I {{ C1 instantiates D.Camera ( ) {{ Out : OutPort ( provider Img = IOut() ); [ source {cursor} ] }} V1 instantiates D.Viewer ( ) {{ In : InPort ( processor Img2 = IIn() ); }} }}"
        )
    };
    assert_eq!(labels(&[("a.gudsl", &doc("$0"))]), ["C1", "Out", "V1"]);
    assert_eq!(labels(&[("a.gudsl", &doc("Out.$0"))]), ["Img"]);
    assert_eq!(labels(&[("a.gudsl", &doc("Out.Img ==> target V1.$0"))]), ["In"]);
    assert_eq!(labels(&[("a.gudsl", &doc("Out.Img ==> target V1.In.$0"))]), ["Img2"]);
}

#[test]
fn snippets_by_level_and_types_in_type_positions() {
    assert!(labels(&[("a.gudsl", "$0")]).contains(&"ActivityDiagram".to_string()));
    let found = labels(&[("a.gudsl", "ClassDiagram D { $0 }")]);
    assert!(found.contains(&"class".to_string()) && found.contains(&"provider interface".to_string()));
    let found = labels(&[("a.gudsl", "ActivityDiagram A() { swimlane L { $0 } }")]);
    assert!(found.contains(&"calcRange".to_string()) && found.contains(&"loopWindow".to_string()));
    let found = labels(&[("a.gudsl", "ClassDiagram D { class Image { } class C { public $0 } }")]);
    assert!(found.contains(&"Image".to_string()) && found.contains(&"float4".to_string()));
}

#[test]
fn types_in_scope_first_then_a_bounded_list_of_the_workspaces_others() {
    let many: String = (0..150).map(|i| format!("class Far{i} {{ }} ")).collect();
    let far = format!("ClassDiagram B {{ {many} }}");
    let near = ("a.gudsl", "ClassDiagram A { class Near { } }");
    let complete = |doc: &str| {
        let files = [("u.gudsl", doc), near, ("b.gudsl", far.as_str())];
        let (db, ws, inputs, cursor) = super::super::test_fixture::with_cursor(&files);
        completions(&db, ws, inputs[0], cursor)
    };
    let found = complete("ClassDiagram U { import A.*; class C { public $0 } }");
    let near: Vec<&str> =
        found.items.iter().filter(|i| i.kind == CompletionKind::Type && !i.far).map(|i| i.label.as_str()).collect();
    assert_eq!(near, ["C", "Near"], "the diagram's own and the imported types");
    assert_eq!(found.items.iter().filter(|i| i.far).count(), FAR_TYPES);
    assert!(found.incomplete, "150 other types, cut to {FAR_TYPES}");
    // What is typed narrows the others to the names that have its letters in order:
    // `Far14`, `Far140`…`Far149`, `Far104`, `Far114`, `Far124`, `Far134`.
    let found = complete("ClassDiagram U { import A.*; class C { public Far14$0 } }");
    let far: Vec<&str> = found.items.iter().filter(|i| i.far).map(|i| i.label.as_str()).collect();
    assert_eq!(far.len(), 15, "{far:?}");
    assert!(!found.incomplete);
}
