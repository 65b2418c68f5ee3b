//! The names completion lists: built-in and declared types (those in scope first, then others
//! by their unique simple name), the locals of a body, and a type's members.

use std::collections::HashSet;

use crate::{
    ast::{self, AstNode, HasName},
    hir::{items::ImportItem, DefKind, Definition, Scope, Semantics},
    syntax::{SyntaxKind::*, SyntaxNode},
};

use super::{finish, item, CompletionItem, CompletionKind, Completions};

/// At most this many types of other diagrams are proposed; the names in scope always are.
pub(super) const FAR_TYPES: usize = 100;

const BUILTIN_TYPES: &[&str] = &[
    "bool",
    "byte",
    "char",
    "short",
    "int",
    "long",
    "float",
    "double",
    "real",
    "string",
    "void",
    "unsigned",
    "int2",
    "int4",
    "float2",
    "float3",
    "float4",
    "uchar4",
    "image2D_uc",
    "image2D_f",
    "image3D_f",
    "buffer2D_f4",
    "sampler_t",
];

/// `items` and every type that fits where a type is written at `at`: the built-in ones, then
/// those of [`types_in_scope`].
pub(super) fn with_types(
    sema: &Semantics,
    at: &SyntaxNode,
    typed: &str,
    mut items: Vec<CompletionItem>,
) -> Completions {
    for ty in BUILTIN_TYPES {
        items.push(item(*ty, CompletionKind::Keyword, Some("built-in type".into())));
    }
    let incomplete = types_in_scope(sema, &Scope::at(at), typed, &mut items);
    Completions { incomplete, ..finish(items) }
}

/// The types for a type position: every type the cursor's scope sees by its simple name (its
/// diagrams' and its imports'), then the workspace's other types whose name matches what is
/// typed (`typed` in order, any case), at most [`FAR_TYPES`] of them. Whether some were left out.
fn types_in_scope(sema: &Semantics, scope: &Scope, typed: &str, items: &mut Vec<CompletionItem>) -> bool {
    let mut seen: HashSet<String> = HashSet::new();
    let mut near = |name: &str, def: &Definition, items: &mut Vec<CompletionItem>| {
        if matches!(def.kind, DefKind::Type(_)) && seen.insert(def.fqn.clone()) {
            items.push(item(name, CompletionKind::Type, Some(def.fqn.clone())));
        }
    };
    let wildcards = scope.imports.iter().filter_map(|i| match i {
        ImportItem::Wildcard(prefix) => Some(prefix.as_str()),
        _ => None,
    });
    for namespace in scope.namespaces.iter().map(String::as_str).chain(wildcards) {
        for (name, defs) in sema.namespace_members(namespace) {
            near(name, &defs[0], items);
        }
    }
    for import in &scope.imports {
        if let ImportItem::Name(fqn) = import {
            if let Some(def) = sema.definition(fqn) {
                near(fqn.rsplit('.').next().unwrap_or(fqn), def, items);
            }
        }
    }
    // Names that start with what is typed first, then the others that contain its letters.
    let mut matching: Vec<(bool, &String, &Vec<String>)> = sema
        .types_by_simple_name()
        .filter(|(simple, _)| typed_in(typed, simple))
        .map(|(simple, fqns)| (!starts_with_ignoring_case(simple, typed), simple, fqns))
        .collect();
    // Only the first ones are proposed: each name has a type, and at most `seen.len()` of those
    // are already listed, so the first `FAR_TYPES + seen.len()` names hold every proposal.
    let proposed = FAR_TYPES + seen.len();
    let cut = matching.len() > proposed;
    if cut {
        matching.select_nth_unstable(proposed);
        matching.truncate(proposed);
    }
    matching.sort_unstable();
    let mut far = 0;
    for (_, simple, fqns) in matching {
        for fqn in fqns.iter().filter(|fqn| !seen.contains(*fqn)) {
            if far == FAR_TYPES {
                return true;
            }
            let label = if fqns.len() == 1 { simple.clone() } else { fqn.clone() };
            items.push(CompletionItem { far: true, ..item(label, CompletionKind::Type, Some(fqn.clone())) });
            far += 1;
        }
    }
    cut
}

fn starts_with_ignoring_case(name: &str, typed: &str) -> bool {
    name.get(..typed.len()).is_some_and(|head| head.eq_ignore_ascii_case(typed))
}

/// Whether the characters of `typed` appear in `name` in order, ignoring case (as editors
/// filter completions).
fn typed_in(typed: &str, name: &str) -> bool {
    let mut name = name.chars().flat_map(char::to_lowercase);
    typed.chars().flat_map(char::to_lowercase).all(|t| name.any(|n| n == t))
}

pub(super) fn locals_in_scope(body: &SyntaxNode, items: &mut Vec<CompletionItem>) {
    for ancestor in body.ancestors() {
        for decl in ancestor.children().filter(|c| matches!(c.kind(), VAR_DECL | VARIABLE)) {
            if let Some(name) = decl.children().find(|c| c.kind() == NAME) {
                items.push(item(name.text().to_string(), CompletionKind::Variable, None));
            }
        }
        for param in ancestor.children().filter(|c| c.kind() == PARAM_LIST).flat_map(|l| l.children()) {
            if let Some(name) = ast::Param::cast(param).and_then(|p| p.name()) {
                items.push(item(name.text(), CompletionKind::Variable, Some("parameter".into())));
            }
        }
    }
}

/// The fields and methods of a type and its bases.
pub(super) fn type_members(sema: &Semantics, def: &crate::hir::Definition, items: &mut Vec<CompletionItem>) {
    for def in sema.type_and_bases(def) {
        let DefKind::Type(ty) = &def.kind else { continue };
        for field in &ty.fields {
            items.push(item(field.name.clone(), CompletionKind::Field, Some(def.fqn.clone())));
        }
        for method in &ty.methods {
            let params: Vec<String> =
                method.params.iter().enumerate().map(|(i, p)| format!("${{{}:{}}}", i + 1, p.name)).collect();
            let mut it = item(method.name.clone(), CompletionKind::Method, Some(def.fqn.clone()));
            it.snippet = Some(format!("{}({})", method.name, params.join(", ")));
            items.push(it);
        }
    }
}
