//! Graphs of the sample diagrams: ids, stereotypes, compartments, ports and edge ends.

use super::*;
use salsa::Setter;

use crate::db::RootDatabase;

fn seed(name: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/seed").join(name))
        .unwrap()
}

fn graphs_of(files: &[(&str, String)]) -> Vec<Graph> {
    let db = RootDatabase::default();
    let inputs: Vec<SourceFile> = files.iter().map(|(p, t)| SourceFile::new(&db, p.to_string(), t.clone())).collect();
    let ws = Workspace::new(&db, inputs.clone());
    file_graphs(&db, ws, inputs[0]).clone()
}

#[test]
fn class_graph_of_listing26() {
    let g = &graphs_of(&[
        ("a", seed("listing26_component_classes_example.gudsl")),
        ("b", seed("listing01_type_definitions.gudsl")),
    ])[0];
    assert_eq!(g.id, "ComponentClassDefinitions");
    let camera = g.nodes.iter().find(|n| n.id == "ComponentClassDefinitions.Camera").unwrap();
    assert_eq!(camera.stereotype.as_deref(), Some("source"));
    assert_eq!(camera.compartments[0].lines, ["+ width : int", "+ height : int"]);
    let realizes: Vec<&str> =
        g.edges.iter().filter(|e| e.kind == EdgeKind::Realization).map(|e| e.id.as_str()).collect();
    assert!(
        realizes.contains(&"ComponentClassDefinitions.Camera->ComponentClassDefinitions.IImageProvider#0"),
        "{realizes:?}"
    );
}

#[test]
fn activity_graph_ids_survive_whitespace_and_comment_edits() {
    let text = seed("listing08_member_access.gudsl");
    let before = &graphs_of(&[("a", text.clone())])[0];
    let edited =
        text.replace("    swimlane", "  // a comment\n\n    swimlane").replace("=> filterImage;", "=>   filterImage ;");
    let after = &graphs_of(&[("a", edited)])[0];
    let ids = |g: &Graph| {
        (
            g.nodes.iter().map(|n| n.id.clone()).collect::<Vec<_>>(),
            g.edges.iter().map(|e| e.id.clone()).collect::<Vec<_>>(),
        )
    };
    assert_eq!(ids(before), ids(after));
    assert!(before.nodes.iter().any(|n| n.id == "AdMemberAccess/Swimlane1/load"));
    assert!(before
        .edges
        .iter()
        .any(|e| e.id == "AdMemberAccess/Swimlane1/filterImage->AdMemberAccess/Swimlane1/filterImage#0"
            && e.label.as_deref() == Some("[i < 10]")));
    assert_eq!(before.groups[0].owner.as_deref(), Some("TypeDefinitions.Image"));
}

#[test]
fn component_and_instance_graphs() {
    let defs = seed("listing26_component_classes_example.gudsl");
    let g = &graphs_of(&[("c", seed("listing27_component_example.gudsl")), ("d", defs.clone())])[0];
    let camera = g.nodes.iter().find(|n| n.id == "ComponentClassDefinitions.Camera").unwrap();
    assert_eq!(camera.ports[0].id, "ComponentClassDefinitions.Camera.CameraImageProviderPort.CameraImageProviderPort");
    assert_eq!(camera.ports[0].provider, Some(true));
    let connection = g.edges.iter().find(|e| e.label.as_deref() == Some("CameraToFilter")).unwrap();
    assert_eq!(
        connection.target.id(),
        "ComponentClassDefinitions.MeanFilter.MeanImageProcessorPort.FilterImageProcessorPort"
    );
    let g = &graphs_of(&[("i", seed("listing28_component_instance_example.gudsl"))])[0];
    assert_eq!(
        g.nodes.iter().map(|n| n.label.as_str()).collect::<Vec<_>>(),
        ["Camera1 : Camera", "Camera2 : Camera", "MeanFilter1 : MeanFilter", "Viewer1 : Viewer"]
    );
    assert_eq!(g.nodes[0].compartments[0].lines, ["width = 640", "height = 480"]);
    assert!(g.edges.iter().any(|e| e.source.id() == "Camera1.Camera1ProviderPort.CameraImageProviderPort"
        && e.target.id() == "MeanFilter1.MeanProcessorPort.MeanImageProcessorPort"));
}

#[test]
fn every_sample_diagram_has_a_graph() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples");
    let db = RootDatabase::default();
    let mut files = Vec::new();
    for dir in ["seed", "framework"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap().flatten() {
            let path = entry.path();
            if path.extension().is_some_and(|e| e == "gudsl") {
                files.push(SourceFile::new(&db, path.display().to_string(), std::fs::read_to_string(&path).unwrap()));
            }
        }
    }
    let ws = Workspace::new(&db, files.clone());
    let mut total = 0;
    for file in &files {
        let diagrams =
            parse(&db, *file).syntax_node().descendants().filter(|n| ast::Diagram::can_cast(n.kind())).count();
        let graphs = file_graphs(&db, ws, *file);
        assert_eq!(graphs.len(), diagrams, "{}", file.path(&db));
        for graph in graphs {
            let mut ids: Vec<&str> = graph.nodes.iter().map(|n| n.id.as_str()).collect();
            ids.sort();
            ids.dedup();
            assert_eq!(ids.len(), graph.nodes.len(), "duplicate node ids in {}", graph.id);
        }
        total += diagrams;
    }
    assert!(total > 40, "{total}");
}

#[test]
fn edges_of_different_kinds_between_two_classes_have_ids_of_their_own() {
    let g = &graphs_of(&[("a", seed("appendixA_associations.gudsl"))])[0];
    let ids: Vec<&str> = g.edges.iter().map(|e| e.id.as_str()).collect();
    let unique: std::collections::BTreeSet<&str> = ids.iter().copied().collect();
    assert_eq!(unique.len(), ids.len(), "{ids:?}");
    // Image has a composition (pixel) and an association (contains) to Pixel.
    assert!(ids.contains(&"Associations.Image->Associations.Pixel#0"), "{ids:?}");
    assert!(ids.contains(&"Associations.Image->Associations.Pixel#1"), "{ids:?}");
}

/// The graphs of `files` (computed once), the database logging what it executes.
fn logged(files: &[(&str, &str)]) -> (RootDatabase, Workspace, Vec<SourceFile>) {
    let db = RootDatabase::with_execution_log();
    let inputs: Vec<SourceFile> =
        files.iter().map(|(p, t)| SourceFile::new(&db, p.to_string(), t.to_string())).collect();
    let ws = Workspace::new(&db, inputs.clone());
    for &file in &inputs {
        file_graphs(&db, ws, file);
    }
    db.take_executions();
    (db, ws, inputs)
}

fn graphs_executed(db: &RootDatabase) -> usize {
    db.take_executions().iter().filter(|e| e.starts_with("file_graphs(")).count()
}

const SHAPES: &str = "ClassDiagram Shapes
{
    public class Shape { public float area() { return 0.0; } }
    public class Circle extends Shape { public float radius; }
}
";
const USES: &str = "ClassDiagram Drawing
{
    public class Canvas { self [0 .. *] shapes : Shapes.Shape; }
}
";
const ALONE: &str = "ClassDiagram Alone
{
    public class Lonely { public int n; }
}
";

#[test]
fn a_graph_is_recomputed_by_edits_that_change_it_only() {
    let (mut db, ws, files) = logged(&[("shapes.gudsl", SHAPES), ("uses.gudsl", USES), ("alone.gudsl", ALONE)]);
    let edit = |db: &mut RootDatabase, file: SourceFile, from: &str, to: &str| {
        let text = file.text(db).replacen(from, to, 1);
        file.set_text(db).to(text);
    };
    let all = |db: &RootDatabase| files.iter().map(|&f| file_graphs(db, ws, f).len()).sum::<usize>();

    // A method body elsewhere: no graph is recomputed (the item trees are backdated).
    edit(&mut db, files[0], "return 0.0;", "return 1.0;");
    assert_eq!(all(&db), 3);
    assert_eq!(graphs_executed(&db), 1, "only the edited file's graph is looked at again");

    // A class added to `Alone`: its graph, and no other.
    edit(&mut db, files[2], "public class Lonely", "public class Other { } public class Lonely");
    assert_eq!(all(&db), 3);
    assert_eq!(graphs_executed(&db), 1);
    assert!(file_graphs(&db, ws, files[2])[0].nodes.iter().any(|n| n.id == "Alone.Other"));

    // `Shape` renamed: its own graph and the graph whose association reaches it.
    edit(&mut db, files[0], "public class Shape ", "public class Figure ");
    assert_eq!(all(&db), 3);
    assert_eq!(graphs_executed(&db), 2, "shapes.gudsl and uses.gudsl; not alone.gudsl");
}

#[test]
fn activity_graph_has_the_frame_heading_parameters_owner_and_variables() {
    let text = seed("listing08_member_access.gudsl");
    let g = &graphs_of(&[("a", text.clone())])[0];
    assert_eq!(g.parameters, ["string filenameLoad", "string filenameSave"]);
    assert_eq!(g.owner, None);
    // The comments above the variable are not part of it.
    assert_eq!(g.variables, ["+ i : int"]);
    let edited = text
        .replace(
            "AdMemberAccess(string filenameLoad, string filenameSave)",
            "AdMemberAccess(), owner TypeDefinitions.Image",
        )
        .replace("public int i;", "public int i;\n    var int k = 2 * 3; // two\n    const float c = 1.5;");
    let g = &graphs_of(&[("a", edited)])[0];
    assert!(g.parameters.is_empty());
    assert_eq!(g.owner.as_deref(), Some("TypeDefinitions.Image"));
    assert_eq!(g.variables, ["+ i : int", "k : int = 2 * 3", "c : float = 1.5 {readOnly}"]);
}

#[test]
fn component_ports_are_named_once_with_their_mode_and_commented_components_keep_their_kind() {
    let g = &graphs_of(&[("a", seed("listing22_ports_and_connections.gudsl"))])[0];
    let labels: Vec<&str> = g.nodes.iter().flat_map(|n| n.ports.iter().map(|p| p.label.as_str())).collect();
    assert_eq!(
        labels,
        [
            "CameraPort.ImageOut : IImageProvider",
            "FilterPort.ImageIn : IImageProcessor {async, buffered}",
            "FilterPort.ImageOut : IImageProvider {async, buffered}",
            "ViewerPort.ImageIn : IImageProcessor {async}",
        ]
    );
    // A comment above a nested component does not hide its keyword.
    let g = &graphs_of(&[("a", seed("listing20_nested_components.gudsl"))])[0];
    let camera = g.nodes.iter().find(|n| n.label == "Camera").unwrap();
    assert_eq!(camera.stereotype.as_deref(), Some("source"));
}

/// An instance's ports are named as short as the dissertation draws them: the port instance
/// (`Camera1ProviderPort`, not `Camera1ProviderPort.CameraImageProviderPort : IImageProvider`),
/// its connector added only where it has several.
#[test]
fn instance_ports_are_named_by_their_port_instances() {
    let g = &graphs_of(&[("a", seed("listing28_component_instance_example.gudsl"))])[0];
    let camera = g.nodes.iter().find(|n| n.id == "Camera1").unwrap();
    assert_eq!(camera.ports.iter().map(|p| p.label.as_str()).collect::<Vec<_>>(), ["Camera1ProviderPort"]);
    assert_eq!(camera.ports[0].id, "Camera1.Camera1ProviderPort.CameraImageProviderPort", "ids keep the connector");
    let text = "ComponentInstanceDiagram D\n{\n    A instantiates C\n    {\n        P : Q ( provider x = I(), processor y = J() );\n    }\n}\n";
    let g = &graphs_of(&[("a", text.to_string())])[0];
    assert_eq!(g.nodes[0].ports.iter().map(|p| p.label.as_str()).collect::<Vec<_>>(), ["P.x", "P.y"]);
}

#[test]
fn class_members_show_their_qualifiers_as_uml_does_and_applied_attributes_their_usage() {
    // Listing 3: constants are {readOnly} with their values, references `ref type`, statics
    // (`global`) flagged for underlining.
    let g = &graphs_of(&[("a", seed("listing03_qualifiers.gudsl"))])[0];
    let memory = &g.nodes[0];
    let (fields, methods) = (&memory.compartments[0], &memory.compartments[1]);
    assert_eq!(
        fields.lines,
        ["+ i : int = 0 {readOnly}", "# j : ref real", "- g : int = 100", "+ k : ref int = ref g {readOnly}"]
    );
    assert_eq!(fields.statics, [false, false, true, true]);
    assert_eq!(methods.lines, ["+ memcpy(dst : ref void, src : ref void, numBytes : int) : void"]);
    assert_eq!(methods.statics, [true]);
    // Listing 5: an applied generator attribute shows as written beside the type's kind.
    let g = &graphs_of(&[("a", seed("listing05_attribute_usage.gudsl")), ("b", seed("listing04_attributes.gudsl"))])[0];
    let image = g.nodes.iter().find(|n| n.id == "AttributeUsage.Image").unwrap();
    assert_eq!(image.stereotype.as_deref(), Some("Attributes.GeneratorVisibility(visible = false)"));
    // Listing 8's activity variables: a `ref` modifier shows in the type.
    let g = &graphs_of(&[("a", "ActivityDiagram A() { public ref int r; var ref Image im; }".to_string())])[0];
    assert_eq!(g.variables, ["+ r : ref int", "im : ref Image"]);
}

#[test]
fn loop_headers_show_the_dissertations_setup_test_and_increment_areas() {
    let text = "ActivityDiagram L(int n) { swimlane Lane {
        start s { => a; }
        loop a(var int i = 0; i < n; i = i + 1) { n = n; => b; }
        loop b(i < n) { => c; }
        loopWindow c(var int u = 0, var int v = 0; u < n, v < n; u = u + 1, v = v + 1) { => d; }
        loop d(i < n; i) { => f; }
        final f;
    } }";
    let g = &graphs_of(&[("a", text.to_string())])[0];
    let header = |name: &str| {
        let node = g.nodes.iter().find(|n| n.id == format!("L/Lane/{name}")).unwrap();
        assert_eq!(node.stereotype.as_deref(), Some(if name == "c" { "loopWindow" } else { "loop" }));
        node.compartments[0].lines.clone()
    };
    assert_eq!(header("a"), ["setup: var int i = 0", "test: i < n", "increment: i = i + 1"]);
    assert_eq!(header("b"), ["test: i < n"]);
    assert_eq!(
        header("c"),
        ["setup: var int u = 0, var int v = 0", "test: u < n, v < n", "increment: u = u + 1, v = v + 1"]
    );
    // A header the validator rejects is shown as written.
    assert_eq!(header("d"), ["i < n", "i"]);
}

#[test]
fn listing28_without_instance_braces_draws_as_with_them() {
    let braced = seed("listing28_component_instance_example.gudsl");
    // The flat form the listing is printed in: the instances' braces removed.
    let flat = without_instance_braces(&braced);
    assert_ne!(flat, braced);
    let shape = |g: &Graph| {
        let nodes: Vec<(String, Vec<String>)> =
            g.nodes.iter().map(|n| (n.id.clone(), n.ports.iter().map(|p| p.id.clone()).collect())).collect();
        let edges: Vec<(String, String)> =
            g.edges.iter().map(|e| (e.source.id().to_string(), e.target.id().to_string())).collect();
        (nodes, edges)
    };
    let (braced, flat) = (&graphs_of(&[("i", braced)])[0], &graphs_of(&[("i", flat)])[0]);
    assert_eq!(shape(flat), shape(braced));
    assert_eq!(braced.edges.len(), 3);
}

/// A file's instances written as Listing 28 prints them: their port instances and bindings
/// without braces (the braces of a braced instance at four spaces, each on its own line).
pub(crate) fn without_instance_braces(text: &str) -> String {
    text.lines().filter(|l| !matches!(*l, "    {" | "    }")).map(|l| format!("{l}\n")).collect()
}
