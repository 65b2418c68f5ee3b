//! Scopes: where a name is looked up (the enclosing diagrams, innermost last, with their imports
//! and the template parameters in force), and the one rule that turns a name written in a scope
//! into fully qualified candidates.

use super::{
    definitions::{join, Definition},
    items::{import_item, ImportItem},
};
use crate::{
    ast::{self, AstNode, HasName},
    syntax::SyntaxNode,
};

/// Where names are looked up: the enclosing diagrams (namespaces, innermost last), their imports
/// and the template parameters in scope.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Scope {
    pub namespaces: Vec<String>,
    pub imports: Vec<ImportItem>,
    pub type_params: Vec<String>,
}

impl Scope {
    /// The scope at a syntax node: its enclosing diagrams and their imports.
    pub fn at(node: &SyntaxNode) -> Scope {
        let mut diagrams: Vec<ast::Diagram> = node.ancestors().filter_map(ast::Diagram::cast).collect();
        diagrams.reverse();
        let mut scope = Scope::default();
        for diagram in diagrams {
            let Some(name) = diagram.name().map(|n| n.text()) else { break };
            scope.enter(&name);
            for import in ast::support::children::<ast::Import>(diagram.syntax()) {
                scope.imports.extend(import_item(&import).filter(|i| *i != ImportItem::Header));
            }
        }
        scope
    }

    /// The scope a definition was declared in: its enclosing namespaces and their imports.
    pub fn of(def: &Definition) -> Scope {
        let mut scope = Scope::default();
        let segments: Vec<&str> = def.fqn.split('.').collect();
        for segment in &segments[..segments.len().saturating_sub(1)] {
            scope.enter(segment);
        }
        scope.imports = def.imports.to_vec();
        scope
    }

    /// Enters the diagram `name` (nested in the current innermost one).
    pub fn enter(&mut self, name: &str) {
        let fqn = join(self.innermost(), name);
        self.namespaces.push(fqn);
    }

    /// The innermost namespace's fully qualified name ("" at the top).
    pub fn innermost(&self) -> &str {
        self.namespaces.last().map_or("", |s| s.as_str())
    }

    /// The fully qualified name of `name` declared in the innermost namespace.
    pub fn qualify(&self, name: &str) -> String {
        join(self.innermost(), name)
    }

    /// The first fully qualified candidate for `path` for which `exists` holds: the enclosing
    /// namespaces innermost first, then the imports, then `path` as written.
    pub fn candidate(&self, path: &str, exists: impl FnMut(&str) -> bool) -> Option<String> {
        resolve_path(&self.namespaces, &self.imports, path, exists)
    }
}

/// Resolves `path` from enclosing `namespaces` (innermost last) and `imports` to the first
/// fully qualified candidate for which `exists` holds.
pub fn resolve_path(
    namespaces: &[String],
    imports: &[ImportItem],
    path: &str,
    mut exists: impl FnMut(&str) -> bool,
) -> Option<String> {
    for namespace in namespaces.iter().rev() {
        let candidate = join(namespace, path);
        if exists(&candidate) {
            return Some(candidate);
        }
    }
    for import in imports {
        let candidate = match import {
            ImportItem::Wildcard(prefix) => join(prefix, path),
            ImportItem::Name(name) => {
                let last = name.rsplit('.').next().unwrap_or(name);
                let first = path.split('.').next().unwrap_or(path);
                if last != first {
                    continue;
                }
                format!("{name}{}", &path[first.len()..])
            }
            ImportItem::Header => continue,
        };
        if exists(&candidate) {
            return Some(candidate);
        }
    }
    exists(path).then(|| path.to_string())
}
