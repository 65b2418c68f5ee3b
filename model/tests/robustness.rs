//! The parser on hostile input: deep nesting, huge inputs, every prefix of a document.
//! It must return (no panic, no stack overflow, no hang) with a lossless tree.

use gudsl_model::{parse, SyntaxErrorCode};

fn assert_lossless(text: &str) -> gudsl_model::Parse {
    let parsed = parse(text);
    assert_eq!(parsed.syntax_node().to_string(), text);
    for error in parsed.errors() {
        assert!(u32::from(error.range.end()) as usize <= text.len());
        assert!(text.is_char_boundary(u32::from(error.range.start()) as usize));
        assert!(text.is_char_boundary(u32::from(error.range.end()) as usize));
    }
    parsed
}

const DEPTH: usize = 100_000;

#[test]
fn hundred_thousand_nested_braces_at_top_level() {
    let text = "{".repeat(DEPTH);
    let parsed = assert_lossless(&text);
    assert!(!parsed.errors().is_empty());
}

#[test]
fn hundred_thousand_nested_parentheses_in_an_expression() {
    let text = format!(
        "ActivityDiagram A() {{ swimlane L {{ action a {{ x = {}1{}; }} }} }}",
        "(".repeat(DEPTH),
        ")".repeat(DEPTH)
    );
    let parsed = assert_lossless(&text);
    assert_eq!(parsed.errors().len(), 1, "{:?}", parsed.errors());
    assert_eq!(parsed.errors()[0].code, SyntaxErrorCode::NestingTooDeep);
}

#[test]
fn hundred_thousand_unclosed_blocks_in_a_method() {
    let text = format!("ClassDiagram D {{ class C {{ void m() {}", "{".repeat(DEPTH));
    let parsed = assert_lossless(&text);
    // The depth error and one error for the missing closers, not one per level.
    assert!(parsed.errors().len() <= 3, "{:?}", parsed.errors());
}

#[test]
fn hundred_thousand_nested_diagrams_and_brackets() {
    let mut text = "ClassDiagram D { ".repeat(DEPTH / 10);
    text.push_str(&"[".repeat(DEPTH));
    text.push_str(&"} ".repeat(DEPTH / 10));
    assert_lossless(&text);
}

#[test]
fn deeply_nested_unary_and_casts() {
    let text = format!(
        "ActivityDiagram A() {{ swimlane L {{ action a {{ x = {}y; z = {}w; }} }} }}",
        "-".repeat(DEPTH),
        "(float)".repeat(DEPTH / 10)
    );
    assert_lossless(&text);
}

#[test]
fn every_prefix_of_a_document_parses() {
    let text = include_str!("../test_data/parser/ok/01_mixed_constructs.gudsl");
    for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
        assert_lossless(&text[..end]);
    }
}

#[test]
fn huge_attribute_list_before_a_class() {
    let args = (0..5_000).map(|i| format!("A{i}")).collect::<Vec<_>>().join(", ");
    let text = format!("ClassDiagram D {{ [{args}] public class C {{ }} }}");
    let parsed = assert_lossless(&text);
    assert!(parsed.errors().is_empty(), "{:?}", &parsed.errors()[..1]);
}
