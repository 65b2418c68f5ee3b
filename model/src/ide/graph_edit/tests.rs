//! Graph edits over every listing: each operation's text edits, applied and parsed again, give
//! the graph with exactly that change, touch only what they must, and undo.

use salsa::Setter;

use super::*;
use crate::{db::RootDatabase, text::with_edits};

/// Every listing of the dissertation, as one workspace (as `samples_check_clean_as_one_workspace`).
pub(super) fn listings(db: &RootDatabase) -> (Workspace, Vec<SourceFile>) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/seed");
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "gudsl"))
        .collect();
    paths.sort();
    let mut files: Vec<SourceFile> = paths
        .iter()
        .map(|p| {
            SourceFile::new(db, p.file_name().unwrap().to_string_lossy().into(), std::fs::read_to_string(p).unwrap())
        })
        .collect();
    // Listing 28 as printed too: its instances' port instances and bindings without braces.
    let braced = paths.iter().find(|p| p.ends_with("listing28_component_instance_example.gudsl")).unwrap();
    let renamed = std::fs::read_to_string(braced)
        .unwrap()
        .replace("ComponentInstanceExampleDiagram", "ComponentInstanceExampleDiagramFlat");
    let flat = crate::graph::tests::without_instance_braces(&renamed);
    files.push(SourceFile::new(db, "listing28_flat.gudsl".into(), flat));
    (Workspace::new(db, files.clone()), files)
}

/// Makes `edits` in the files' texts.
pub(super) fn apply(db: &mut RootDatabase, files: &[SourceFile], edits: &[(FileRange, String)]) {
    for &file in files {
        let mine: Vec<(TextRange, &str)> = edits
            .iter()
            .filter(|(place, _)| place.file == file)
            .map(|(place, new)| (place.range, new.as_str()))
            .collect();
        if !mine.is_empty() {
            let text = with_edits(file.text(db), mine);
            file.set_text(db).to(text);
        }
    }
}

pub(super) fn texts(db: &RootDatabase, files: &[SourceFile]) -> Vec<String> {
    files.iter().map(|f| f.text(db).clone()).collect()
}

#[test]
fn renaming_any_node_of_any_listing_renames_exactly_it_and_undoes() {
    let mut db = RootDatabase::default();
    let (ws, files) = listings(&db);
    let original = texts(&db, &files);
    let mut renamed = 0;
    for &file in &files {
        let graphs = file_graphs(&db, ws, file).clone();
        for graph in &graphs {
            for node in graph.nodes.iter().filter(|n| !n.range.is_empty()) {
                let Some(at) = declared_name(&parse(&db, file).syntax_node(), node.range) else { continue };
                let old = file.text(&db)[at].to_string();
                let new = format!("{old}Renamed");
                let op = GraphOp::Rename { element: node.id.clone(), name: new.clone() };
                let edits = match graph_edit(&db, ws, file, &graph.id, std::slice::from_ref(&op)) {
                    Ok(edits) => edits,
                    Err(refused) => panic!("{}: {}: {}", file.path(&db), node.id, refused.0),
                };
                // Only the name, where it is written: the declaration and its references.
                for (range, _) in &edits {
                    assert_eq!(&range.file.text(&db)[range.range], old, "{}", node.id);
                }
                apply(&mut db, &files, &edits);
                let after = file_graphs(&db, ws, file).iter().find(|g| g.id == graph.id).unwrap().clone();
                let new_id = format!("{}{new}", node.id.strip_suffix(&old).unwrap());
                let expected: Vec<String> =
                    graph.nodes.iter().map(|n| if n.id == node.id { new_id.clone() } else { n.id.clone() }).collect();
                let ids: Vec<String> = after.nodes.iter().map(|n| n.id.clone()).collect();
                assert_eq!(ids, expected, "{}: renaming {}", file.path(&db), node.id);
                // Every edge still joins the same nodes: the references were renamed too.
                let ends = |g: &crate::graph::Graph, from: &str, to: &str| -> Vec<(String, String)> {
                    let id = |n: &String| if n == from { to.to_string() } else { n.clone() };
                    g.edges.iter().map(|e| (id(&e.source.node), id(&e.target.node))).collect()
                };
                assert_eq!(ends(&after, "", ""), ends(graph, &node.id, &new_id), "{}: edges", node.id);
                // And back: the text as it was, byte for byte.
                let back = GraphOp::Rename { element: new_id.clone(), name: old.clone() };
                let edits = graph_edit(&db, ws, file, &graph.id, &[back]).unwrap();
                apply(&mut db, &files, &edits);
                assert!(texts(&db, &files) == original, "renaming {} back did not restore the text", node.id);
                renamed += 1;
            }
        }
    }
    assert!(renamed > 100, "{renamed} nodes renamed");
}

#[test]
fn what_cannot_be_done_is_refused_with_the_reason() {
    let db = RootDatabase::default();
    let text = "ClassDiagram Shapes\n{\n    public class Shape { }\n    public class Circle extends Shape { }\n}\n";
    let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
    let ws = Workspace::new(&db, vec![file]);
    let rename = |element: &str, name: &str| GraphOp::Rename { element: element.into(), name: name.into() };
    let refused = |diagram: &str, ops: &[GraphOp]| graph_edit(&db, ws, file, diagram, ops).unwrap_err().0;
    assert_eq!(refused("Circles", &[]), "a.gudsl declares no diagram `Circles` (it declares: Shapes)");
    assert_eq!(refused("Shapes", &[rename("Shapes.Square", "X")]), "operation 0: `Shapes` has no node `Shapes.Square`");
    assert_eq!(refused("Shapes", &[rename("Shapes.Shape", "1st")]), "operation 0: `1st` is not a valid name");
    assert_eq!(
        refused("Shapes", &[rename("Shapes.Shape", "Figure"), rename("Shapes.Shape", "Form")]),
        "operations 0 and 1 edit the same text: send them in separate batches"
    );
    // Two operations on different text in one batch.
    let both =
        graph_edit(&db, ws, file, "Shapes", &[rename("Shapes.Shape", "Figure"), rename("Shapes.Circle", "Disc")]);
    assert_eq!(both.unwrap().len(), 3, "Shape's declaration and reference, Circle's declaration");
}

#[test]
fn operations_the_language_cannot_state_are_refused_with_the_reason() {
    let db = RootDatabase::default();
    let text = "ClassDiagram Shapes\n{\n    public class Shape { }\n    public class Circle extends Shape { }\n}\n\
                ActivityDiagram A()\n{\n    start S { => f; }\n    final f;\n}\n";
    let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
    let ws = Workspace::new(&db, vec![file]);
    let refused = |diagram: &str, op: GraphOp| graph_edit(&db, ws, file, diagram, &[op]).unwrap_err().0;
    let connect = |kind, source: &str, target: &str, properties: Properties| GraphOp::Connect {
        kind,
        source: source.into(),
        target: target.into(),
        properties,
    };
    use crate::graph::EdgeKind::*;
    assert_eq!(
        refused("Shapes", connect(Generalization, "Shapes.Circle", "Shapes.Shape", Properties::new())),
        "operation 0: `Shapes.Circle` already extends `Shape`: a class extends one class (reconnect that generalization)"
    );
    assert_eq!(
        refused("A", connect(Transition, "A/S", "Shapes.Shape", Properties::new())),
        "operation 0: a transition joins nodes of one activity diagram: `A` has no node `Shapes.Shape`"
    );
    assert_eq!(
        refused("A", connect(Transition, "A/f", "A/S", Properties::new())),
        "operation 0: `A/f` is a final node: no transition leaves it"
    );
    let guard = [("guard".to_string(), "x ]; start Z {".to_string())].into_iter().collect();
    assert!(refused("A", connect(Transition, "A/S", "A/f", guard)).starts_with("the edit would not parse: "));
    let create = |kind, parent: Option<&str>| GraphOp::Create {
        kind,
        name: "New".into(),
        parent: parent.map(str::to_string),
        properties: Properties::new(),
    };
    assert_eq!(
        refused("A", create(NewKind::Class, None)),
        "operation 0: a class goes into a class diagram, `A` is an activity diagram"
    );
    assert_eq!(
        refused("Shapes", create(NewKind::Field, Some("Shapes.Nothing"))),
        "operation 0: `Shapes` has no node `Shapes.Nothing`"
    );
    let set =
        GraphOp::SetProperty { element: "Shapes.Shape".into(), property: "guard".into(), value: Some("x".into()) };
    assert_eq!(refused("Shapes", set), "operation 0: `Shapes.Shape` has no property `guard` (it has: none)");
    let reconnect = GraphOp::Reconnect { edge: "A/S->A/f#0".into(), source: None, target: Some("A/f".into()) };
    assert_eq!(
        refused("A", reconnect),
        "operation 0: the edge already joins these ends: give a new `source` or `target`"
    );
}

#[test]
fn a_node_created_in_a_container_is_drawn_inside_it() {
    let mut db = RootDatabase::default();
    let text = "ActivityDiagram A()\n{\n    start S { => work; }\n    action work\n    {\n        var int n = 1;\n        => f;\n    }\n    calc k() { => f; }\n    final f;\n}\n";
    let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
    let ws = Workspace::new(&db, vec![file]);
    let create = |kind, name: &str, parent: &str| GraphOp::Create {
        kind,
        name: name.into(),
        parent: Some(parent.into()),
        properties: Properties::new(),
    };
    let refused = |op: GraphOp| graph_edit(&db, ws, file, "A", &[op]).unwrap_err().0;
    assert_eq!(
        refused(create(NewKind::Node(NodeKind::Start), "s", "A/k")),
        "operation 0: a calc node holds no nodes: only action, decision, loop and loopWindow nodes do (Sec. 9.2.2.3)"
    );
    let edits = graph_edit(&db, ws, file, "A", &[create(NewKind::Node(NodeKind::Start), "inner", "A/work")]).unwrap();
    apply(&mut db, &[file], &edits);
    let written = file.text(&db).clone();
    assert!(written.contains("        var int n = 1;\n        => f;\n        start inner { }\n    }"), "{written}");
    let graph = file_graphs(&db, ws, file).iter().find(|g| g.id == "A").cloned().unwrap();
    let inner = graph.nodes.iter().find(|n| n.id == "A/inner").expect("the new node is drawn");
    assert_eq!(inner.parent.as_deref(), Some("A/work"));
}
