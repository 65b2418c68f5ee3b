//! The typed AST file: a struct per node with its accessors, an enum per alternation of nodes,
//! their `AstNode` casts and the `HasName` / `HasModifiers` impls the fields imply.

use std::fmt::Write;

use super::{
    grammar::{flatten, AstSrc, EnumSrc, Field, NodeSrc},
    kinds::Tokens,
    upper_snake, PREAMBLE,
};

fn docs(out: &mut String, doc: &[String]) {
    for line in doc {
        if line.is_empty() {
            out.push_str("///\n");
        } else {
            let _ = writeln!(out, "/// {line}");
        }
    }
}

/// Words joined by `, ` in lines of at most `width` characters.
fn wrap(words: &[String], width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in words {
        match lines.last_mut() {
            Some(line) if line.len() + 2 + word.len() <= width => {
                line.push_str(", ");
                line.push_str(word);
            }
            _ => lines.push(word.clone()),
        }
    }
    lines
}

fn trait_impls(out: &mut String, name: &str, traits: &[&str]) {
    for t in traits {
        let _ = writeln!(out, "impl {t} for {name} {{}}");
    }
    if !traits.is_empty() {
        out.push('\n');
    }
}

fn node(out: &mut String, tokens: &Tokens, node: &NodeSrc) {
    let name = &node.name;
    let kind = upper_snake(name);
    docs(out, &node.doc);
    let _ = write!(
        out,
        "#[derive(Debug, Clone, PartialEq, Eq, Hash)]\n\
         pub struct {name} {{\n    pub(crate) syntax: SyntaxNode,\n}}\n\n\
         impl AstNode for {name} {{\n\
        \x20   fn can_cast(kind: SyntaxKind) -> bool {{\n        kind == {kind}\n    }}\n\
        \x20   fn cast(syntax: SyntaxNode) -> Option<Self> {{\n        Self::can_cast(syntax.kind()).then_some({name} {{ syntax }})\n    }}\n\
        \x20   fn syntax(&self) -> &SyntaxNode {{\n        &self.syntax\n    }}\n}}\n\n"
    );
    trait_impls(out, name, &node.traits);
    if node.fields.is_empty() {
        return;
    }
    let _ = writeln!(out, "impl {name} {{");
    for field in &node.fields {
        match field {
            Field::Node { name, ty, many: true } => {
                let _ = writeln!(
                    out,
                    "    pub fn {name}(&self) -> AstChildren<{ty}> {{\n        support::children(&self.syntax)\n    }}"
                );
            }
            Field::Node { name, ty, many: false } => {
                let _ = writeln!(
                    out,
                    "    pub fn {name}(&self) -> Option<{ty}> {{\n        support::child(&self.syntax)\n    }}"
                );
            }
            Field::Token { token } => {
                let _ = writeln!(
                    out,
                    "    pub fn {}_token(&self) -> Option<SyntaxToken> {{\n        support::token(&self.syntax, {})\n    }}",
                    tokens.stem(token),
                    tokens.kind(token)
                );
            }
            Field::TokenSet { name, tokens: set } => {
                let kinds: Vec<String> = set.iter().map(|t| tokens.kind(t)).collect();
                let _ = writeln!(out, "    /// The first token of these kinds:");
                for line in wrap(&set.iter().map(|t| format!("`{t}`")).collect::<Vec<_>>(), 90) {
                    let _ = writeln!(out, "    /// {line}");
                }
                let _ = writeln!(out, "    pub fn {name}(&self) -> Option<SyntaxToken> {{");
                let _ = writeln!(
                    out,
                    "        support::token_of(\n            &self.syntax,\n            &[{}],\n        )\n    }}",
                    kinds.join(", ")
                );
            }
        }
    }
    out.push_str("}\n\n");
}

fn enumeration(out: &mut String, ast: &AstSrc, en: &EnumSrc) {
    let name = &en.name;
    docs(out, &en.doc);
    let _ = writeln!(out, "#[derive(Debug, Clone, PartialEq, Eq, Hash)]\npub enum {name} {{");
    for variant in &en.variants {
        let _ = writeln!(out, "    {variant}({variant}),");
    }
    out.push_str("}\n\n");
    let kinds_of = |ty: &str| -> Vec<String> { flatten(ast, ty).iter().map(|n| upper_snake(n)).collect() };
    let all: Vec<String> = en.variants.iter().flat_map(|v| kinds_of(v)).collect();
    let _ = writeln!(out, "impl AstNode for {name} {{");
    let _ = writeln!(
        out,
        "    fn can_cast(kind: SyntaxKind) -> bool {{\n        matches!(\n            kind,\n            {}\n        )\n    }}",
        all.join("\n                | ")
    );
    out.push_str("    fn cast(syntax: SyntaxNode) -> Option<Self> {\n        Some(match syntax.kind() {\n");
    for variant in &en.variants {
        let is_enum = ast.enums.iter().any(|e| &e.name == variant);
        let pattern = kinds_of(variant).join(" | ");
        if is_enum {
            let _ = writeln!(out, "            {pattern} => {name}::{variant}({variant}::cast(syntax)?),");
        } else {
            let _ = writeln!(out, "            {pattern} => {name}::{variant}({variant} {{ syntax }}),");
        }
    }
    out.push_str("            _ => return None,\n        })\n    }\n");
    out.push_str("    fn syntax(&self) -> &SyntaxNode {\n        match self {\n");
    for variant in &en.variants {
        let _ = writeln!(out, "            {name}::{variant}(it) => it.syntax(),");
    }
    out.push_str("        }\n    }\n}\n\n");
    for variant in &en.variants {
        let _ = writeln!(
            out,
            "impl From<{variant}> for {name} {{\n    fn from(node: {variant}) -> {name} {{\n        {name}::{variant}(node)\n    }}\n}}\n"
        );
    }
    trait_impls(out, name, &en.traits);
}

/// The AST source file.
pub(crate) fn generate(tokens: &Tokens, ast: &AstSrc) -> String {
    let mut out = format!("//! {PREAMBLE}\n\n");
    out.push_str(
        "use crate::{\n    ast::{support, AstChildren, AstNode, HasModifiers, HasName},\n    \
         syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken},\n};\n\n",
    );
    for n in &ast.nodes {
        node(&mut out, tokens, n);
    }
    for en in &ast.enums {
        enumeration(&mut out, ast, en);
    }
    while out.ends_with("\n\n") {
        out.pop();
    }
    out
}
