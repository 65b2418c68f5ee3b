//! Every editor feature answers, without panicking, at positions all over broken documents:
//! truncated samples, samples with garbage inserted, and half-typed constructs.

use gudsl_model::{
    db::{parse, RootDatabase, SourceFile, Workspace},
    hir::file_diagnostics,
    ide,
    syntax::{TextRange, TextSize},
    text::LineIndex,
};

fn documents() -> Vec<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/seed");
    let mut out = Vec::new();
    for name in [
        "listing15_mean_filter.gudsl",
        "listing27_component_example.gudsl",
        "listing28_component_instance_example.gudsl",
        "listing26_component_classes_example.gudsl",
    ] {
        let text = std::fs::read_to_string(root.join(name)).unwrap();
        for cut in [text.len() / 5, text.len() / 3, text.len() / 2, text.len() * 4 / 5] {
            let cut = (0..=cut).rev().find(|&c| text.is_char_boundary(c)).unwrap();
            out.push(text[..cut].to_string());
        }
        let middle = (0..=text.len() / 2).rev().find(|&c| text.is_char_boundary(c)).unwrap();
        for garbage in ["=> ", "[ ", "}}", "(", "call ", "ActivityDiagram ", ". "] {
            out.push(format!("{}{garbage}{}", &text[..middle], &text[middle..]));
        }
    }
    out.push("ActivityDiagram A() { swimlane L, owner { start S { => ; } action a( { x = ; [ => a(1, ; } }".into());
    out.push("ComponentInstanceDiagram I { X instantiates ( a = , ) { P : ( provider = ( ; [ source ==> ] }".into());
    out
}

#[test]
fn every_feature_answers_everywhere_on_broken_documents() {
    let db = RootDatabase::default();
    let support = SourceFile::new(
        &db,
        "framework.gudsl".into(),
        std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/framework/framework.gudsl"),
        )
        .unwrap(),
    );
    for (i, text) in documents().into_iter().enumerate() {
        let file = SourceFile::new(&db, format!("doc{i}.gudsl"), text.clone());
        let workspace = Workspace::new(&db, vec![file, support]);
        let _ = file_diagnostics(&db, workspace, file);
        let tree = parse(&db, file);
        let _ = ide::document_symbols(&tree.source_file());
        let _ = ide::folding_ranges(&tree.syntax_node(), &LineIndex::new(&text));
        let _ = ide::semantic_tokens(&db, file);
        let _ = gudsl_model::format::format(tree);
        let whole = TextRange::up_to((text.len() as u32).into());
        let _ = ide::quick_fixes(&db, workspace, file, whole);
        let _ = ide::inlay_hints(&db, file, whole);
        let step = (text.len() / 60).max(1);
        for offset in (0..=text.len()).step_by(step).filter(|&o| text.is_char_boundary(o)) {
            let at = TextSize::from(offset as u32);
            let _ = ide::completions(&db, workspace, file, at);
            let _ = ide::goto_definition(&db, workspace, file, at);
            let _ = ide::hover(&db, workspace, file, at);
            let _ = ide::find_references(&db, workspace, file, at, true);
            let _ = ide::prepare_rename(&db, workspace, file, at);
            let _ = ide::rename(&db, workspace, file, at, "renamed");
            let _ = ide::signature_help(&db, workspace, file, at);
            let _ = ide::selection_ranges(&tree.syntax_node(), at);
        }
    }
}
