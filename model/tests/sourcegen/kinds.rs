//! The token table (what the grammar's quoted tokens are: punctuation, literals, reserved or
//! contextual keywords) and the `SyntaxKind` file generated from it and the grammar's nodes.

use std::fmt::Write;

use super::{
    grammar::{flatten, AstSrc},
    lower_snake, upper_snake, PREAMBLE,
};

/// Tokens that no grammar rule names (trivia, errors, the end), with how a message reads them.
const SPECIAL_TOKENS: &[(&str, &str, &str)] = &[
    ("WHITESPACE", "whitespace", ""),
    ("LINE_COMMENT", "comment", ""),
    ("BLOCK_COMMENT", "comment", ""),
    ("UNKNOWN", "unknown character", "A character that starts no token."),
    ("EOF", "end of file", ""),
];

/// Literal tokens, written `'@name'` in the grammar.
const LITERALS: &[(&str, &str, &str)] = &[
    ("@ident", "IDENT", "identifier"),
    ("@int_number", "INT_NUMBER", "integer"),
    ("@float_number", "FLOAT_NUMBER", "number"),
    ("@string", "STRING", "string"),
    ("@char", "CHAR", "character literal"),
];

/// Punctuation: spelling, kind, documentation.
const PUNCTUATION: &[(&str, &str, &str)] = &[
    (";", "SEMICOLON", ""),
    (",", "COMMA", ""),
    (".", "DOT", ""),
    ("..", "DOT2", ""),
    (":", "COLON", ""),
    ("::", "COLON2", ""),
    ("(", "L_PAREN", ""),
    (")", "R_PAREN", ""),
    ("{", "L_CURLY", ""),
    ("}", "R_CURLY", ""),
    ("[", "L_BRACK", ""),
    ("]", "R_BRACK", ""),
    ("<", "L_ANGLE", ""),
    (">", "R_ANGLE", ""),
    ("=", "EQ", ""),
    ("==", "EQ2", ""),
    ("!", "BANG", ""),
    ("!=", "NEQ", ""),
    ("<=", "LTEQ", ""),
    (">=", "GTEQ", "`>=`: composed by the parser from `>` `=`."),
    ("+", "PLUS", ""),
    ("-", "MINUS", ""),
    ("*", "STAR", ""),
    ("/", "SLASH", ""),
    ("%", "PERCENT", ""),
    ("&", "AMP", ""),
    ("&&", "AMP2", ""),
    ("|", "PIPE", ""),
    ("||", "PIPE2", ""),
    ("^", "CARET", ""),
    ("~", "TILDE", ""),
    ("?", "QUESTION", ""),
    ("=>", "FAT_ARROW", "`=>`: a transition."),
    ("==>", "LONG_FAT_ARROW", "`==>`: a connection or binding."),
    ("+=", "PLUSEQ", ""),
    ("-=", "MINUSEQ", ""),
    ("*=", "STAREQ", ""),
    ("/=", "SLASHEQ", ""),
    ("%=", "PERCENTEQ", ""),
    ("&=", "AMPEQ", ""),
    ("|=", "PIPEEQ", ""),
    ("^=", "CARETEQ", ""),
    ("<<", "SHL", ""),
    ("<<=", "SHLEQ", ""),
    (">>", "SHR", "`>>`: composed by the parser from two `>`."),
    (">>=", "SHREQ", "`>>=`: composed by the parser from `>` `>` `=`."),
    ("++", "PLUS2", ""),
    ("--", "MINUS2", ""),
];

/// Keywords that name built-in types.
const BUILTIN_TYPES: &[&str] =
    &["bool", "byte", "char", "double", "float", "int", "long", "real", "short", "string", "void"];

/// Keywords only where the grammar expects them (lexed as identifiers, remapped by the parser).
const CONTEXTUAL_KEYWORDS: &[&str] = &[
    "ClassDiagram",
    "ActivityDiagram",
    "ComponentDiagram",
    "ComponentInstanceDiagram",
    "source",
    "filter",
    "sink",
    "provider",
    "processor",
    "self",
    "aggregation",
    "composition",
    "global",
    "shared",
    "out",
    "read",
    "write",
    "static",
    "swimlane",
    "owner",
    "start",
    "final",
    "action",
    "decision",
    "fork",
    "join",
    "loopWindow",
    "calc",
    "calcRange",
    "behavior",
    "loopwindow2D",
    "loopwindow3D",
    "port",
    "async",
    "buffered",
    "target",
    "instantiates",
];

/// The grammar's tokens sorted into the table's classes.
pub(crate) struct Tokens {
    /// Reserved keywords other than built-in types, sorted.
    reserved: Vec<String>,
}

impl Tokens {
    /// Classifies every quoted token of the grammar; panics on one the table does not know.
    pub(crate) fn of(grammar: &ungrammar::Grammar) -> Tokens {
        let mut reserved = Vec::new();
        let mut words = Vec::new();
        for token in grammar.tokens() {
            let name = &grammar[token].name;
            if PUNCTUATION.iter().any(|(p, _, _)| p == name) || LITERALS.iter().any(|(l, _, _)| l == name) {
                continue;
            }
            assert!(
                name.chars().all(|c| c.is_ascii_alphanumeric()),
                "token '{name}' is neither punctuation nor a literal of the table in tests/sourcegen/kinds.rs"
            );
            words.push(name.clone());
            if !BUILTIN_TYPES.contains(&name.as_str()) && !CONTEXTUAL_KEYWORDS.contains(&name.as_str()) {
                reserved.push(name.clone());
            }
        }
        for keyword in BUILTIN_TYPES.iter().chain(CONTEXTUAL_KEYWORDS) {
            assert!(words.iter().any(|w| w == keyword), "keyword `{keyword}` of the table is used by no rule");
        }
        reserved.sort();
        Tokens { reserved }
    }

    /// The kind of a quoted token of the grammar.
    pub(crate) fn kind(&self, token: &str) -> String {
        if let Some((_, kind, _)) = PUNCTUATION.iter().chain(LITERALS).find(|(t, _, _)| *t == token) {
            return kind.to_string();
        }
        format!("{}_KW", upper_snake(token))
    }

    /// The snake-case accessor stem of a quoted token: `semicolon`, `ident`, `class`.
    pub(crate) fn stem(&self, token: &str) -> String {
        self.kind(token).trim_end_matches("_KW").to_ascii_lowercase()
    }

    fn keywords(&self) -> impl Iterator<Item = &str> {
        self.reserved
            .iter()
            .map(String::as_str)
            .chain(BUILTIN_TYPES.iter().copied())
            .chain(CONTEXTUAL_KEYWORDS.iter().copied())
    }
}

fn doc(out: &mut String, text: &str) {
    if !text.is_empty() {
        let _ = writeln!(out, "    /// {text}");
    }
}

fn matches_fn(out: &mut String, doc_lines: &str, name: &str, kinds: &[String]) {
    for line in doc_lines.lines() {
        let _ = writeln!(out, "    /// {line}");
    }
    let _ = writeln!(out, "    pub fn {name}(self) -> bool {{");
    let _ = writeln!(
        out,
        "        matches!(\n            self,\n            {}\n        )",
        kinds.join("\n                | ")
    );
    out.push_str("    }\n\n");
}

fn keyword_match(out: &mut String, doc_line: &str, name: &str, words: &[&str], tokens: &Tokens) {
    let _ = writeln!(out, "    /// {doc_line}");
    let _ = writeln!(out, "    pub fn {name}(text: &str) -> Option<SyntaxKind> {{");
    out.push_str("        Some(match text {\n");
    for word in words {
        let _ = writeln!(out, "            \"{word}\" => {},", tokens.kind(word));
    }
    out.push_str("            _ => return None,\n        })\n    }\n\n");
}

/// The `SyntaxKind` enum, its table of all kinds and its predicates.
pub(crate) fn generate(tokens: &Tokens, ast: &AstSrc) -> String {
    let mut out = format!("//! {PREAMBLE}\n\n");
    out.push_str(
        "/// Every kind of token and node in a GU-DSL syntax tree.\n\
         ///\n\
         /// Tokens come first (trivia, literals, punctuation, keywords), then composite nodes.\n\
         /// Contextual keywords (`swimlane`, `source`, `provider`, …) are lexed as [`SyntaxKind::IDENT`]\n\
         /// and remapped by the parser where the grammar expects them.\n\
         #[allow(non_camel_case_types, clippy::upper_case_acronyms)]\n\
         #[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]\n\
         #[repr(u16)]\n\
         pub enum SyntaxKind {\n",
    );
    let mut all: Vec<String> = Vec::new();
    let section = |out: &mut String, title: &str| {
        let _ = writeln!(out, "    // --- {title}");
    };
    section(&mut out, "trivia and special tokens");
    for (kind, _, text) in SPECIAL_TOKENS {
        doc(&mut out, text);
        let _ = writeln!(out, "    {kind},");
        all.push(kind.to_string());
    }
    section(&mut out, "literals and names");
    for (_, kind, _) in LITERALS {
        let _ = writeln!(out, "    {kind},");
        all.push(kind.to_string());
    }
    section(&mut out, "punctuation");
    for (_, kind, text) in PUNCTUATION {
        doc(&mut out, text);
        let _ = writeln!(out, "    {kind},");
        all.push(kind.to_string());
    }
    section(&mut out, "reserved keywords, built-in type keywords, contextual keywords");
    for keyword in tokens.keywords() {
        let _ = writeln!(out, "    {},", tokens.kind(keyword));
        all.push(tokens.kind(keyword));
    }
    section(&mut out, "nodes");
    out.push_str("    /// Text the parser could not place; always accompanied by a diagnostic.\n    ERROR,\n");
    all.push("ERROR".to_string());
    for node in &ast.nodes {
        let _ = writeln!(out, "    {},", upper_snake(&node.name));
        all.push(upper_snake(&node.name));
    }
    out.push_str("}\n\nuse SyntaxKind::*;\n\n");
    out.push_str("/// Every variant in order, so a raw `u16` maps back without `unsafe`.\n");
    let _ = writeln!(out, "pub(super) const ALL_KINDS: &[SyntaxKind] = &[\n    {},\n];\n", all.join(",\n    "));

    out.push_str("impl SyntaxKind {\n");
    let trivia: Vec<String> = ["WHITESPACE", "LINE_COMMENT", "BLOCK_COMMENT"].map(String::from).to_vec();
    matches_fn(&mut out, "Whitespace and comments: kept in the tree, skipped by the parser.", "is_trivia", &trivia);
    let keywords: Vec<String> = tokens.keywords().map(|k| tokens.kind(k)).collect();
    matches_fn(&mut out, "Reserved or contextual keyword.", "is_keyword", &keywords);
    let contextual: Vec<String> = CONTEXTUAL_KEYWORDS.iter().map(|k| tokens.kind(k)).collect();
    matches_fn(
        &mut out,
        "Contextual keyword: a name everywhere the grammar does not expect it as a keyword.",
        "is_contextual_keyword",
        &contextual,
    );
    let builtin: Vec<String> = BUILTIN_TYPES.iter().map(|k| tokens.kind(k)).collect();
    matches_fn(&mut out, "Built-in type keyword (`int`, `float`, …).", "is_builtin_type", &builtin);
    for en in &ast.enums {
        let kinds: Vec<String> = flatten(ast, &en.name).iter().map(|n| upper_snake(n)).collect();
        let what = if en.doc.is_empty() { format!("A `{}` node.", en.name) } else { en.doc.join("\n") };
        matches_fn(&mut out, &what, &format!("is_{}", lower_snake(&en.name)), &kinds);
    }
    out.push_str(
        "    /// Leaf kind (token) rather than a node.\n    pub fn is_token(self) -> bool {\n        (self as u16) < ERROR as u16\n    }\n\n",
    );
    let reserved: Vec<&str> = tokens.keywords().filter(|k| !CONTEXTUAL_KEYWORDS.contains(k)).collect();
    keyword_match(&mut out, "The reserved keyword spelled `text`, if any.", "from_keyword", &reserved, tokens);
    keyword_match(
        &mut out,
        "The contextual keyword spelled `text`, if any.",
        "from_contextual_keyword",
        CONTEXTUAL_KEYWORDS,
        tokens,
    );
    out.push_str("    /// How the kind reads in a diagnostic: `` `;` ``, `identifier`, `` `class` ``.\n");
    out.push_str("    pub fn describe(self) -> &'static str {\n        match self {\n");
    for (kind, text, _) in SPECIAL_TOKENS {
        let _ = writeln!(out, "            {kind} => \"{text}\",");
    }
    for (_, kind, text) in LITERALS {
        let _ = writeln!(out, "            {kind} => \"{text}\",");
    }
    for (spelling, kind, _) in PUNCTUATION {
        let _ = writeln!(out, "            {kind} => \"`{spelling}`\",");
    }
    for keyword in tokens.keywords() {
        let _ = writeln!(out, "            {} => \"`{keyword}`\",", tokens.kind(keyword));
    }
    out.push_str("            _ => \"syntax\",\n        }\n    }\n}\n");
    out
}
