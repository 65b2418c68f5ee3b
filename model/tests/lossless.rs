//! Property: for every input — random, garbage, or a sample document mutated at random — the
//! syntax tree's text equals the input byte for byte, and every error range is inside it.

use proptest::prelude::*;

fn check(text: &str) {
    let parsed = gudsl_model::parse(text);
    assert_eq!(parsed.syntax_node().to_string(), text);
    for error in parsed.errors() {
        let (start, end) = (u32::from(error.range.start()) as usize, u32::from(error.range.end()) as usize);
        assert!(start <= end && end <= text.len(), "{error:?} outside the text");
        assert!(text.is_char_boundary(start) && text.is_char_boundary(end));
    }
}

/// Every `.gudsl` file of the parser tests and the samples.
fn corpus() -> Vec<String> {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut texts = Vec::new();
    let mut dirs = vec![root.join("test_data"), root.join("../samples")];
    while let Some(dir) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&dir) else { continue };
        for entry in entries.flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "gudsl") {
                texts.push(std::fs::read_to_string(path).unwrap());
            }
        }
    }
    texts.sort();
    texts
}

/// Fragments GU-DSL is made of, to build token soups that reach deep into the grammar.
const FRAGMENTS: &[&str] = &[
    "ClassDiagram",
    "ActivityDiagram",
    "ComponentDiagram",
    "ComponentInstanceDiagram",
    "class",
    "interface",
    "provider",
    "processor",
    "source",
    "filter",
    "sink",
    "enum",
    "attribute",
    "public",
    "abstract",
    "extends",
    "implements",
    "self",
    "aggregation",
    "[0 .. *]",
    "swimlane",
    ", owner",
    "start",
    "final",
    "action",
    "decision",
    "fork",
    "join",
    "loop",
    "loopWindow",
    "calc",
    "calcRange",
    "=>",
    "==>",
    "[",
    "]",
    "(",
    ")",
    "{",
    "}",
    "<",
    ">",
    ";",
    ",",
    ".",
    ":",
    "::",
    "=",
    "==",
    "+",
    "-",
    "*",
    "/",
    "&&",
    "||",
    "!",
    "?",
    "var",
    "const",
    "ref",
    "int",
    "unsigned byte",
    "float4",
    "new",
    "as",
    "call",
    "behavior",
    "if",
    "else",
    "for",
    "do",
    "switch",
    "case",
    "default",
    "return",
    "port",
    "async",
    "buffered",
    "target",
    "instantiates",
    "x",
    "Name",
    "A.B",
    "42",
    "1.5f",
    "\"s\"",
    "\"unterminated",
    "'c'",
    "// comment\n",
    "/* block */",
    "/* open",
    "\n",
    " ",
    "\t",
    "ä",
    "😀",
    "#",
    "\\",
    "\0",
];

fn token_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(FRAGMENTS), 0..200).prop_map(|parts| parts.join(" "))
}

#[derive(Debug, Clone)]
enum Mutation {
    Delete { at: usize, len: usize },
    Insert { at: usize, fragment: &'static str },
    Duplicate { at: usize, len: usize },
    Truncate { at: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 1usize..40).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), prop::sample::select(FRAGMENTS)).prop_map(|(at, fragment)| Mutation::Insert { at, fragment }),
        (any::<usize>(), 1usize..80).prop_map(|(at, len)| Mutation::Duplicate { at, len }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
    ]
}

fn floor_char_boundary(text: &str, mut i: usize) -> usize {
    i = i.min(text.len());
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn apply(text: &str, mutation: &Mutation) -> String {
    let pos = |at: usize| if text.is_empty() { 0 } else { floor_char_boundary(text, at % (text.len() + 1)) };
    match *mutation {
        Mutation::Delete { at, len } => {
            let start = pos(at);
            let end = floor_char_boundary(text, start + len);
            format!("{}{}", &text[..start], &text[end..])
        }
        Mutation::Insert { at, fragment } => {
            let at = pos(at);
            format!("{}{fragment}{}", &text[..at], &text[at..])
        }
        Mutation::Duplicate { at, len } => {
            let start = pos(at);
            let end = floor_char_boundary(text, start + len);
            format!("{}{}", &text[..end], &text[start..])
        }
        Mutation::Truncate { at } => text[..pos(at)].to_string(),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn arbitrary_unicode_is_lossless(text in "\\PC{0,400}") {
        check(&text);
    }

    #[test]
    fn arbitrary_bytes_as_text_are_lossless(bytes in prop::collection::vec(any::<u8>(), 0..400)) {
        check(&String::from_utf8_lossy(&bytes));
    }

    #[test]
    fn token_soup_is_lossless(text in token_soup()) {
        check(&text);
    }

    #[test]
    fn mutated_documents_are_lossless(
        index in any::<prop::sample::Index>(),
        mutations in prop::collection::vec(mutation(), 1..8),
    ) {
        let corpus = corpus();
        let mut text = index.get(&corpus).clone();
        for m in &mutations {
            text = apply(&text, m);
        }
        check(&text);
    }
}

#[test]
fn every_corpus_document_is_lossless() {
    let corpus = corpus();
    assert!(corpus.len() >= 20, "corpus too small: {}", corpus.len());
    for text in &corpus {
        check(text);
    }
}
