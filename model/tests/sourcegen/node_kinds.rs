//! The activity-node vocabulary, generated from the grammar's `ActivityNode` alternatives: the
//! `NodeKind` enum, each kind's keyword, keyword token and syntax node, and `ActivityNode::kind`.
//! The parser, the graph view, graph edits, completion and the code generator read it, so a
//! node kind added to the grammar is known everywhere (or fails to compile where a `match`
//! must say what it does).

use std::fmt::Write;

use ungrammar::{Grammar, Rule};

use super::{kinds::Tokens, upper_snake, PREAMBLE};

/// Each alternative of `ActivityNode`: its node's name and the keyword it starts with.
fn node_kinds(grammar: &Grammar) -> Vec<(String, String)> {
    let activity = grammar.iter().find(|&n| grammar[n].name == "ActivityNode").expect("ActivityNode in the grammar");
    let Rule::Alt(alternatives) = &grammar[activity].rule else { panic!("ActivityNode is an alternation") };
    alternatives
        .iter()
        .map(|alternative| {
            let Rule::Node(node) = alternative else { panic!("ActivityNode alternates nodes") };
            let name = grammar[*node].name.clone();
            let first = match &grammar[*node].rule {
                Rule::Seq(rules) => rules.first(),
                other => Some(other),
            };
            let Some(Rule::Token(keyword)) = first else { panic!("{name} starts with its keyword") };
            (name, grammar[*keyword].name.clone())
        })
        .collect()
}

/// `StartNode` → `Start`.
fn variant(node: &str) -> String {
    node.trim_end_matches("Node").to_string()
}

/// `syntax/node_kind.rs`: the enum and what each kind is in the syntax.
pub(crate) fn generate(grammar: &Grammar, tokens: &Tokens) -> String {
    let kinds = node_kinds(grammar);
    let mut out = format!(
        "//! {PREAMBLE}\n//!\n//! The kinds of activity node, one vocabulary from the grammar's `ActivityNode`.\n\n"
    );
    out.push_str("use super::SyntaxKind::{self, *};\n\n");
    out.push_str(
        "/// The kind of an activity node.\n#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]\npub enum NodeKind {\n",
    );
    for (node, _) in &kinds {
        let _ = writeln!(out, "    {},", variant(node));
    }
    out.push_str("}\n\nimpl NodeKind {\n    /// Every kind, in the grammar's order.\n");
    let _ = writeln!(out, "    pub const ALL: [NodeKind; {}] = [", kinds.len());
    for (node, _) in &kinds {
        let _ = writeln!(out, "        NodeKind::{},", variant(node));
    }
    out.push_str("    ];\n\n");
    let table = |out: &mut String, doc: &str, signature: &str, value: &dyn Fn(&str, &str) -> String| {
        let _ = writeln!(out, "    /// {doc}\n    pub fn {signature} {{\n        match self {{");
        for (node, keyword) in &kinds {
            let _ = writeln!(out, "            NodeKind::{} => {},", variant(node), value(node, keyword));
        }
        out.push_str("        }\n    }\n\n");
    };
    table(
        &mut out,
        "The keyword a node of this kind starts with (`loopWindow`).",
        "keyword(self) -> &'static str",
        &|_, k| format!("{k:?}"),
    );
    table(&mut out, "The keyword's token kind.", "keyword_kind(self) -> SyntaxKind", &|_, k| tokens.kind(k));
    table(&mut out, "The syntax node a node of this kind is.", "syntax_kind(self) -> SyntaxKind", &|n, _| {
        upper_snake(n)
    });
    out.push_str("    /// The kind of node a keyword token starts, if it starts one.\n    pub fn of_keyword(kind: SyntaxKind) -> Option<NodeKind> {\n        NodeKind::ALL.into_iter().find(|k| k.keyword_kind() == kind)\n    }\n}\n");
    out
}

/// `ast/node_kind.rs`: `ActivityNode::kind`.
pub(crate) fn generate_ast(grammar: &Grammar) -> String {
    let kinds = node_kinds(grammar);
    let mut out = format!("//! {PREAMBLE}\n//!\n//! The kind of each activity node (`syntax::NodeKind`).\n\n");
    out.push_str("use super::ActivityNode;\nuse crate::syntax::NodeKind;\n\n");
    out.push_str(
        "impl ActivityNode {\n    /// Its kind.\n    pub fn kind(&self) -> NodeKind {\n        match self {\n",
    );
    for (node, _) in &kinds {
        let _ = writeln!(out, "            ActivityNode::{node}(_) => NodeKind::{},", variant(node));
    }
    out.push_str("        }\n    }\n}\n");
    out
}
