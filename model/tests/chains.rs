//! Long chains in one expression (`1 + 1 + …`, `y.b.b…`, `a[0][0]…`, `f()()…`, `- - …1`,
//! `x = x = …`) at 100 000 links: every analysis answers on a test thread's small stack (no
//! stack overflow), the tree stays lossless and no deeper than the parser's limit allows, and the
//! chain is reported once (E0006) without swallowing the statements after it.

use gudsl_model::{syntax::TextSize, AnalysisHost, SyntaxErrorCode, SyntaxNode};

const LINKS: usize = 100_000;

/// The deepest nesting of the tree, counted without recursion.
fn depth(root: &SyntaxNode) -> usize {
    let (mut deepest, mut current) = (0, 0);
    for event in root.preorder() {
        match event {
            rowan::WalkEvent::Enter(_) => {
                current += 1;
                deepest = deepest.max(current);
            }
            rowan::WalkEvent::Leave(_) => current -= 1,
        }
    }
    deepest
}

fn chains() -> Vec<(&'static str, String)> {
    vec![
        ("binary", format!("x = {};", vec!["1"; LINKS].join(" + "))),
        ("member", format!("x = y{};", ".b".repeat(LINKS))),
        ("index", format!("x = y{};", "[0]".repeat(LINKS))),
        ("call", format!("x = f{};", "()".repeat(LINKS))),
        ("prefix", format!("x = {}1;", "-".repeat(LINKS))),
        ("assignment", format!("x = {} = 1;", vec!["x"; LINKS].join(" = "))),
    ]
}

#[test]
fn hundred_thousand_links_are_reported_once_and_analysed_without_overflow() {
    for (what, statement) in chains() {
        let text = format!(
            "ActivityDiagram A(int x, int y)\n{{\n    swimlane L\n    {{\n        start S\n        {{\n            {statement}\n            => done;\n        }}\n        final done;\n    }}\n}}\n"
        );
        let (host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), text.clone())]);
        let (analysis, file) = (host.analysis(), files[0]);
        let parse = analysis.parse(file).unwrap();
        let root = parse.syntax_node();
        assert_eq!(root.to_string(), text, "{what}: not lossless");
        assert!(depth(&root) <= 2 * 192 + 32, "{what}: the tree is {} levels deep", depth(&root));
        let too_deep: Vec<_> = parse.errors().iter().filter(|e| e.code == SyntaxErrorCode::NestingTooDeep).collect();
        assert_eq!(too_deep.len(), 1, "{what}: {:?}", parse.errors());
        // The transition after the chain is still read: no unreachable node, no missing `;`.
        let (diagnostics, _) = analysis.diagnostics(file).unwrap();
        let others: Vec<_> =
            diagnostics.iter().filter(|d| !matches!(d.code.as_str(), "E0006" | "E0228" | "E0244" | "E0245")).collect();
        assert!(others.is_empty(), "{what}: {others:?}");
        // `y[0][0]…` of an `int y` indexes a number, said once (at `y`), not once a link;
        // `--(--y)` decrements a value, said once, and a message quotes 40 characters at most.
        for code in ["E0244", "E0245"] {
            let found: Vec<_> = diagnostics.iter().filter(|d| d.code.as_str() == code).collect();
            assert!(found.len() <= 1, "{what}: {} × {code}", found.len());
            assert!(found.iter().all(|d| d.message.len() < 200), "{what}: {found:?}");
        }
        analysis.graphs(file).unwrap();
        analysis.document_symbols(file).unwrap();
        analysis.semantic_tokens(file).unwrap();
        analysis.format(file).unwrap();
        analysis.folding_ranges(file).unwrap();
        let middle = TextSize::from((text.len() / 2) as u32);
        analysis.hover(file, middle).unwrap();
        analysis.completions(file, middle).unwrap();
        analysis.selection_ranges(file, &[middle]).unwrap();
    }
}

#[test]
fn a_chain_just_under_the_limit_is_analysed_in_full() {
    // `z` is the deepest leaf of the left-leaning tree: reported only if typing reaches it.
    let sum = format!("z + {}", vec!["x"; 150].join(" + "));
    let text = format!(
        "ActivityDiagram A(int x)\n{{\n    swimlane L\n    {{\n        start S\n        {{\n            var bool b = {sum};\n            => done;\n        }}\n        final done;\n    }}\n}}\n"
    );
    let (host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), text)]);
    let analysis = host.analysis();
    let (diagnostics, _) = analysis.diagnostics(files[0]).unwrap();
    let codes: Vec<&str> = diagnostics.iter().map(|d| d.code.as_str()).collect();
    assert_eq!(codes, ["E0228"], "{diagnostics:?}");
    assert!(diagnostics[0].message.contains("`z`"), "{diagnostics:?}");
}

#[test]
fn the_deepest_tree_the_parser_builds_is_analysed_on_a_small_stack() {
    // Parentheses nest to just under the limit, and inside them a chain runs to just under it.
    let expression = format!("{}z{}{}", "(".repeat(185), ")".repeat(185), " + x".repeat(190));
    let inner = format!("{}y{}{}", "(".repeat(185), ".b".repeat(190), ")".repeat(185));
    let text = format!(
        "ActivityDiagram A(int x)\n{{\n    swimlane L\n    {{\n        start S\n        {{\n            x = {expression};\n            x = {inner};\n            => done;\n        }}\n        final done;\n    }}\n}}\n"
    );
    let (host, files) = AnalysisHost::with_files([("a.gudsl".to_string(), text.clone())]);
    let analysis = host.analysis();
    analysis.diagnostics(files[0]).unwrap();
    analysis.semantic_tokens(files[0]).unwrap();
    analysis.format(files[0]).unwrap();
    analysis.hover(files[0], TextSize::from(text.find('z').unwrap() as u32)).unwrap();
}
