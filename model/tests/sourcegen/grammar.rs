//! Lowering of the ungrammar into what the AST generator writes: node structs with their
//! accessor fields and the traits those imply, and enums over nodes.
//!
//! Rules: a rule that is an alternation of nodes only is an enum; every other rule is a node.
//! A node's child nodes become accessors named by their label, else by the child's name in
//! snake case (plural when repeated); its keyword and punctuation tokens become `…_token`
//! accessors; a labelled alternation of tokens (`op:('+' | '-')`) becomes one accessor for the
//! first of them. A labelled alternation of nodes (`start:(VarDecl | Expr)`), and the labels in
//! [`HAND_WRITTEN`], are accessors written by hand in `src/ast/node_ext.rs`: two children whose
//! kinds can be the same (`lhs:Expr`, `rhs:Expr`) cannot be told apart by kind, so the lowering
//! refuses to generate such a pair.

use std::collections::{BTreeMap, BTreeSet};

use ungrammar::{Grammar, Rule};

use super::lower_snake;

/// Accessors that need the node's structure (position, order), not just a child's kind.
const HAND_WRITTEN: &[(&str, &str)] = &[
    ("BinExpr", "lhs"),
    ("BinExpr", "rhs"),
    ("TernaryExpr", "condition"),
    ("TernaryExpr", "then_expr"),
    ("TernaryExpr", "else_expr"),
    ("IndexExpr", "base"),
    ("IndexExpr", "index"),
    ("Association", "own_multiplicity"),
    ("Association", "target_multiplicity"),
    ("Connection", "source"),
    ("Connection", "target"),
    ("Binding", "source"),
    ("Binding", "target"),
    ("ForStmt", "body"),
    ("LoopWindowDim", "end"),
];

/// A lowered grammar.
pub(crate) struct AstSrc {
    pub(crate) nodes: Vec<NodeSrc>,
    pub(crate) enums: Vec<EnumSrc>,
}

pub(crate) struct NodeSrc {
    pub(crate) name: String,
    pub(crate) doc: Vec<String>,
    pub(crate) fields: Vec<Field>,
    pub(crate) traits: Vec<&'static str>,
}

pub(crate) struct EnumSrc {
    pub(crate) name: String,
    pub(crate) doc: Vec<String>,
    pub(crate) variants: Vec<String>,
    pub(crate) traits: Vec<&'static str>,
}

/// One accessor of a node.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Field {
    /// A child node (`many`: all of them).
    Node { name: String, ty: String, many: bool },
    /// A token of one kind: `…_token()`.
    Token { token: String },
    /// The first token of several kinds.
    TokenSet { name: String, tokens: Vec<String> },
}

/// A field before it is checked: its name, the node types it can hold, and whether it is
/// generated.
struct Raw {
    field: Field,
    node_types: BTreeSet<String>,
    generated: bool,
}

/// The `///` lines directly above each rule of the grammar text.
fn docs(text: &str) -> BTreeMap<String, Vec<String>> {
    let mut docs = BTreeMap::new();
    let mut pending: Vec<String> = Vec::new();
    for line in text.lines() {
        if let Some(doc) = line.strip_prefix("///") {
            pending.push(doc.trim_start().to_string());
        } else if let Some(name) = line.strip_suffix(" =").filter(|n| n.chars().all(|c| c.is_ascii_alphanumeric())) {
            docs.insert(name.to_string(), std::mem::take(&mut pending));
        } else {
            pending.clear();
        }
    }
    docs
}

fn is_enum(grammar: &Grammar, rule: &Rule) -> Option<Vec<String>> {
    let Rule::Alt(alternatives) = rule else { return None };
    alternatives
        .iter()
        .map(|alternative| match alternative {
            Rule::Node(node) => Some(grammar[*node].name.clone()),
            _ => None,
        })
        .collect()
}

/// Lowers the grammar; panics where an accessor would be ambiguous.
pub(crate) fn lower(grammar: &Grammar, text: &str) -> AstSrc {
    let mut docs = docs(text);
    let mut ast = AstSrc { nodes: Vec::new(), enums: Vec::new() };
    for node in grammar.iter() {
        let data = &grammar[node];
        let doc = docs.remove(&data.name).unwrap_or_default();
        if let Some(variants) = is_enum(grammar, &data.rule) {
            ast.enums.push(EnumSrc { name: data.name.clone(), doc, variants, traits: Vec::new() });
            continue;
        }
        let mut raw = Vec::new();
        lower_rule(grammar, &data.name, &data.rule, None, false, &mut raw);
        ast.nodes.push(NodeSrc {
            name: data.name.clone(),
            doc,
            fields: check(grammar, &data.name, raw),
            traits: Vec::new(),
        });
    }
    for node in &mut ast.nodes {
        let has = |ty: &str| node.fields.iter().any(|f| matches!(f, Field::Node { ty: t, .. } if t == ty));
        if node.fields.iter().any(|f| matches!(f, Field::Node { name, ty, .. } if name == "name" && ty == "Name")) {
            node.traits.push("HasName");
        }
        if has("Modifiers") || has("AttributeList") {
            node.traits.push("HasModifiers");
        }
        // What the traits provide is not generated again.
        node.fields.retain(|f| {
            !matches!(f, Field::Node { name, ty, .. }
                if (name == "name" && ty == "Name") || ty == "Modifiers" || ty == "AttributeList")
        });
    }
    for i in 0..ast.enums.len() {
        let variants = flatten(&ast, &ast.enums[i].name);
        let traits = ["HasName", "HasModifiers"]
            .into_iter()
            .filter(|t| variants.iter().all(|v| ast.nodes.iter().any(|n| &n.name == v && n.traits.contains(t))))
            .collect();
        ast.enums[i].traits = traits;
    }
    ast
}

/// The node structs an enum (or a node) stands for.
pub(crate) fn flatten(ast: &AstSrc, name: &str) -> BTreeSet<String> {
    match ast.enums.iter().find(|e| e.name == name) {
        Some(en) => en.variants.iter().flat_map(|v| flatten(ast, v)).collect(),
        None => BTreeSet::from([name.to_string()]),
    }
}

fn lower_rule(grammar: &Grammar, node: &str, rule: &Rule, label: Option<&str>, many: bool, out: &mut Vec<Raw>) {
    match rule {
        Rule::Labeled { label, rule } => lower_rule(grammar, node, rule, Some(label), many, out),
        Rule::Node(child) => {
            let ty = grammar[*child].name.clone();
            let generated = !label.is_some_and(|l| HAND_WRITTEN.contains(&(node, l)));
            // Unlabelled: named after the type once all its occurrences are merged (`check`).
            let name = label.map_or_else(String::new, String::from);
            out.push(Raw {
                node_types: BTreeSet::from([ty.clone()]),
                field: Field::Node { name, ty, many },
                generated,
            });
        }
        Rule::Token(token) => {
            out.push(Raw {
                field: Field::Token { token: grammar[*token].name.clone() },
                node_types: BTreeSet::new(),
                generated: true,
            });
        }
        Rule::Alt(alternatives) if label.is_some() => {
            let label = label.unwrap_or_default().to_string();
            let tokens: Option<Vec<String>> = alternatives
                .iter()
                .map(|a| match a {
                    Rule::Token(t) => Some(grammar[*t].name.clone()),
                    _ => None,
                })
                .collect();
            match tokens {
                Some(tokens) => out.push(Raw {
                    field: Field::TokenSet { name: label, tokens },
                    node_types: BTreeSet::new(),
                    generated: true,
                }),
                None => {
                    // A labelled alternation of nodes: written by hand.
                    let mut inner = Vec::new();
                    for alternative in alternatives {
                        lower_rule(grammar, node, alternative, None, many, &mut inner);
                    }
                    let node_types = inner.into_iter().flat_map(|r| r.node_types).collect();
                    out.push(Raw {
                        field: Field::Node { name: label, ty: String::new(), many },
                        node_types,
                        generated: false,
                    });
                }
            }
        }
        Rule::Alt(rules) | Rule::Seq(rules) => {
            for rule in rules {
                lower_rule(grammar, node, rule, label, many, out);
            }
        }
        Rule::Opt(rule) => lower_rule(grammar, node, rule, label, many, out),
        Rule::Rep(rule) => lower_rule(grammar, node, rule, label, true, out),
    }
}

/// Merges repeated fields and refuses accessors that cannot tell their child from another's.
fn check(grammar: &Grammar, node: &str, raw: Vec<Raw>) -> Vec<Field> {
    let enums: BTreeMap<String, Vec<String>> = grammar
        .iter()
        .filter_map(|n| is_enum(grammar, &grammar[n].rule).map(|v| (grammar[n].name.clone(), v)))
        .collect();
    let kinds_of = |types: &BTreeSet<String>| -> BTreeSet<String> {
        let mut out = BTreeSet::new();
        let mut stack: Vec<String> = types.iter().cloned().collect();
        while let Some(ty) = stack.pop() {
            match enums.get(&ty) {
                Some(variants) => stack.extend(variants.iter().cloned()),
                None => {
                    out.insert(ty);
                }
            }
        }
        out
    };
    // One entry per accessor name: the same name twice means all of them.
    let mut merged: Vec<Raw> = Vec::new();
    for field in raw {
        let key = field_name(&field.field);
        match merged.iter_mut().find(|m| field_name(&m.field) == key) {
            Some(existing) => {
                if let (Field::Node { many, ty, .. }, Field::Node { ty: other, .. }) =
                    (&mut existing.field, &field.field)
                {
                    assert_eq!(ty, other, "{node}: accessor `{key}` names two types");
                    *many = true;
                }
                existing.node_types.extend(field.node_types);
            }
            None => merged.push(field),
        }
    }
    for field in &mut merged {
        if let Field::Node { name, ty, many } = &mut field.field {
            if name.is_empty() {
                *name = lower_snake(ty) + if *many { "s" } else { "" };
            }
        }
    }
    for (i, a) in merged.iter().enumerate() {
        for b in &merged[i + 1..] {
            let overlap = !kinds_of(&a.node_types).is_disjoint(&kinds_of(&b.node_types));
            assert!(
                !overlap || (!a.generated && !b.generated),
                "{node}: `{}` and `{}` can hold the same kind of node; write them by hand (HAND_WRITTEN)",
                field_name(&a.field),
                field_name(&b.field)
            );
        }
    }
    merged.into_iter().filter(|r| r.generated).map(|r| r.field).collect()
}

fn field_name(field: &Field) -> String {
    match field {
        Field::Node { name, ty, .. } if name.is_empty() => format!("type {ty}"),
        Field::Node { name, .. } | Field::TokenSet { name, .. } => name.clone(),
        Field::Token { token } => format!("'{token}'"),
    }
}
