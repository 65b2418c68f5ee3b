//! Every editor feature answers, without panicking, at positions all over broken documents:
//! truncated samples, samples with garbage inserted, and half-typed constructs.

use gudsl_model::{
    syntax::{TextRange, TextSize},
    AnalysisHost,
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
    let framework = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../samples/framework/framework.gudsl"),
    )
    .unwrap();
    for (i, text) in documents().into_iter().enumerate() {
        let (host, files) = AnalysisHost::with_files([
            (format!("doc{i}.gudsl"), text.clone()),
            ("framework.gudsl".to_string(), framework.clone()),
        ]);
        let (analysis, file) = (host.analysis(), files[0]);
        analysis.diagnostics(file).unwrap();
        analysis.document_symbols(file).unwrap();
        analysis.folding_ranges(file).unwrap();
        analysis.semantic_tokens(file).unwrap();
        analysis.format(file).unwrap();
        analysis.graphs(file).unwrap();
        let whole = TextRange::up_to((text.len() as u32).into());
        analysis.quick_fixes(file, whole).unwrap();
        analysis.inlay_hints(file, whole).unwrap();
        let step = (text.len() / 60).max(1);
        let offsets: Vec<TextSize> = (0..=text.len())
            .step_by(step)
            .filter(|&o| text.is_char_boundary(o))
            .map(|o| TextSize::from(o as u32))
            .collect();
        analysis.selection_ranges(file, &offsets).unwrap();
        for &at in &offsets {
            analysis.completions(file, at).unwrap();
            analysis.goto_definition(file, at).unwrap();
            analysis.goto_type_definition(file, at).unwrap();
            analysis.hover(file, at).unwrap();
            analysis.find_references(file, at, true).unwrap();
            let _ = analysis.prepare_rename(file, at).unwrap();
            let _ = analysis.rename(file, at, "renamed").unwrap();
            analysis.signature_help(file, at).unwrap();
        }
    }
    let (host, _) = AnalysisHost::with_files([("framework.gudsl".to_string(), framework)]);
    host.analysis().workspace_symbols("", 100).unwrap();
}
