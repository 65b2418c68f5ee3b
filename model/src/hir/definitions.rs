//! Definition map: every fully qualified name of the workspace and what it names, and the
//! per-name `lookup` query through which all cross-file resolution goes.
//!
//! `def_map` changes whenever any declaration changes, but `lookup(name)` is backdated when the
//! answer for that one name stays the same, so a file is re-checked only when a name it
//! actually uses changes meaning.

use std::{collections::BTreeMap, sync::Arc};

use super::items::{item_tree, ActivitySignature, DiagramItem, DiagramKind, ImportItem, TypeItem};
use crate::db::{Db, SourceFile, Workspace};

/// A fully qualified name, interned: the key of [`lookup`].
#[salsa::interned(debug)]
pub struct Fqn<'db> {
    #[returns(ref)]
    pub text: String,
}

/// What a name defines.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum DefKind {
    /// A class diagram (a namespace).
    ClassDiagram,
    ComponentDiagram,
    ComponentInstanceDiagram,
    Activity(Arc<ActivitySignature>),
    Type(Arc<TypeItem>),
}

/// One definition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Definition {
    pub fqn: String,
    pub file: SourceFile,
    pub kind: DefKind,
    /// The imports in force where it is declared (for resolving the names it uses).
    pub imports: Arc<[ImportItem]>,
}

/// Every definition of the workspace by fully qualified name (several when duplicated), and
/// the fully qualified names of the types by their simple name.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DefMap {
    pub definitions: BTreeMap<String, Vec<Definition>>,
    pub types_by_simple_name: BTreeMap<String, Vec<String>>,
}

/// The definition map of the workspace.
#[salsa::tracked(returns(ref))]
pub fn def_map(db: &dyn Db, workspace: Workspace) -> DefMap {
    let mut map = DefMap::default();
    for &file in workspace.files(db) {
        for diagram in &item_tree(db, file).diagrams {
            collect(&mut map, file, "", &[], diagram);
        }
    }
    map
}

fn collect(map: &mut DefMap, file: SourceFile, prefix: &str, outer_imports: &[ImportItem], diagram: &DiagramItem) {
    let fqn = join(prefix, &diagram.name);
    let imports: Arc<[ImportItem]> = outer_imports.iter().chain(&diagram.imports).cloned().collect();
    let kind = match (&diagram.kind, &diagram.activity) {
        (DiagramKind::Activity, Some(signature)) => DefKind::Activity(signature.clone()),
        (DiagramKind::Component, _) => DefKind::ComponentDiagram,
        (DiagramKind::ComponentInstance, _) => DefKind::ComponentInstanceDiagram,
        _ => DefKind::ClassDiagram,
    };
    map.definitions.entry(fqn.clone()).or_default().push(Definition {
        fqn: fqn.clone(),
        file,
        kind,
        imports: imports.clone(),
    });
    for ty in &diagram.types {
        let type_fqn = join(&fqn, &ty.name);
        map.types_by_simple_name.entry(ty.name.clone()).or_default().push(type_fqn.clone());
        map.definitions.entry(type_fqn.clone()).or_default().push(Definition {
            fqn: type_fqn,
            file,
            kind: DefKind::Type(ty.clone()),
            imports: imports.clone(),
        });
    }
    for nested in &diagram.diagrams {
        collect(map, file, &fqn, &imports, nested);
    }
}

/// `prefix.name`, or `name` at the top.
pub fn join(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// The definitions of one fully qualified name.
#[salsa::tracked(returns(ref))]
pub fn lookup<'db>(db: &'db dyn Db, workspace: Workspace, fqn: Fqn<'db>) -> Vec<Definition> {
    def_map(db, workspace).definitions.get(fqn.text(db)).cloned().unwrap_or_default()
}

/// The fully qualified names of the types whose simple name is `name` (for names used without
/// qualification or import, as the dissertation's listings do across diagrams).
#[salsa::tracked(returns(ref))]
pub fn types_named<'db>(db: &'db dyn Db, workspace: Workspace, name: Fqn<'db>) -> Vec<String> {
    def_map(db, workspace).types_by_simple_name.get(name.text(db)).cloned().unwrap_or_default()
}
