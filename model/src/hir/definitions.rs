//! Definitions: what every fully qualified name of the workspace names, and the per-name
//! `lookup` query through which all cross-file resolution goes.
//!
//! The layers keep a declaration edit's cost to what it changes: a file's diagrams
//! (`file_diagrams`) and types (`file_types`) feed the namespaces it declares into
//! (`namespace_definitions`, which read only the files of that namespace), and `lookup(name)`
//! reads its namespace only and is backdated when the answer for that one name stays the same —
//! so a file is re-checked only when a name it uses changes meaning, and no edit rebuilds a
//! workspace-wide map on the way.
//! `def_map` assembles everything for listings (completion, symbol search); resolution never
//! reads it.

use std::{
    collections::{BTreeMap, HashMap},
    sync::Arc,
};

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
/// the fully qualified names of the types by their simple name: for listings (completion,
/// symbol search, "did you mean"), not for resolution.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DefMap {
    pub definitions: BTreeMap<String, Vec<Definition>>,
    pub types_by_simple_name: BTreeMap<String, Vec<String>>,
}

/// The definition map of the workspace, assembled from every file's definitions. It changes
/// with any declaration; resolution never reads it (see [`lookup`]).
#[salsa::tracked(returns(ref))]
pub fn def_map(db: &dyn Db, workspace: Workspace) -> DefMap {
    let mut map = DefMap::default();
    for &file in workspace.files(db) {
        let diagrams = file_diagrams(db, file).iter().map(|(_, def)| def);
        for def in diagrams.chain(file_types(db, file).values().flatten()) {
            map.definitions.entry(def.fqn.clone()).or_default().push(def.clone());
        }
    }
    map.types_by_simple_name = type_names(db, workspace).clone();
    map
}

/// The diagrams one file declares (nested ones too), each with the namespace it is declared in
/// ("" at the top). Equal, so backdated, when an edit changed only what is inside diagrams:
/// then nothing that depends on the workspace's namespaces runs again.
#[salsa::tracked(returns(ref))]
pub fn file_diagrams(db: &dyn Db, file: SourceFile) -> Vec<(String, Definition)> {
    let mut out = Vec::new();
    walk_diagrams(file, "", &[], &item_tree(db, file).diagrams, &mut |namespace, def, _| {
        out.push((namespace.to_string(), def));
    });
    out
}

/// The types one file declares, by the diagram (namespace) that declares them.
#[salsa::tracked(returns(ref))]
pub fn file_types(db: &dyn Db, file: SourceFile) -> BTreeMap<String, Vec<Definition>> {
    let mut map: BTreeMap<String, Vec<Definition>> = BTreeMap::new();
    walk_diagrams(file, "", &[], &item_tree(db, file).diagrams, &mut |_, diagram, item| {
        let types = item.types.iter().map(|ty| Definition {
            fqn: join(&diagram.fqn, &ty.name),
            file,
            kind: DefKind::Type(ty.clone()),
            imports: diagram.imports.clone(),
        });
        map.entry(diagram.fqn.clone()).or_default().extend(types);
    });
    map
}

/// Calls `visit(namespace, definition, item)` for every diagram of `diagrams` and the diagrams
/// nested in them, outer ones first.
fn walk_diagrams(
    file: SourceFile,
    namespace: &str,
    outer_imports: &[ImportItem],
    diagrams: &[DiagramItem],
    visit: &mut dyn FnMut(&str, Definition, &DiagramItem),
) {
    for diagram in diagrams {
        let fqn = join(namespace, &diagram.name);
        let imports: Arc<[ImportItem]> = outer_imports.iter().chain(&diagram.imports).cloned().collect();
        let kind = match (&diagram.kind, &diagram.activity) {
            (DiagramKind::Activity, Some(signature)) => DefKind::Activity(signature.clone()),
            (DiagramKind::Component, _) => DefKind::ComponentDiagram,
            (DiagramKind::ComponentInstance, _) => DefKind::ComponentInstanceDiagram,
            _ => DefKind::ClassDiagram,
        };
        visit(namespace, Definition { fqn: fqn.clone(), file, kind, imports: imports.clone() }, diagram);
        walk_diagrams(file, &fqn, &imports, &diagram.diagrams, visit);
    }
}

/// The files that declare something in each namespace, in workspace order: a file declares
/// into the namespace each of its diagrams is declared in, and into each of its diagrams. It
/// reads only the files' diagrams, so a class edit never re-runs it.
#[salsa::tracked(returns(ref))]
pub fn namespace_files(db: &dyn Db, workspace: Workspace) -> HashMap<String, Vec<SourceFile>> {
    let mut map: HashMap<String, Vec<SourceFile>> = HashMap::new();
    for &file in workspace.files(db) {
        for (namespace, diagram) in file_diagrams(db, file) {
            for declared in [namespace, &diagram.fqn] {
                let files = map.entry(declared.clone()).or_default();
                if files.last() != Some(&file) {
                    files.push(file);
                }
            }
        }
    }
    map
}

/// The definitions declared directly in one namespace, by their last name segment: it reads
/// only the files that declare into that namespace, and the types only of the files whose
/// diagram it is (so the top namespace, the diagrams of every file, ignores class edits).
#[salsa::tracked(returns(ref))]
pub fn namespace_definitions<'db>(
    db: &'db dyn Db,
    workspace: Workspace,
    namespace: Fqn<'db>,
) -> BTreeMap<String, Vec<Definition>> {
    let mut map: BTreeMap<String, Vec<Definition>> = BTreeMap::new();
    let prefix = namespace.text(db);
    let mut add = |def: &Definition| {
        let last = def.fqn.rsplit('.').next().unwrap_or(&def.fqn);
        map.entry(last.to_string()).or_default().push(def.clone());
    };
    let files = namespace_files(db, workspace).get(prefix).map_or(&[][..], |f| f.as_slice());
    for &file in files {
        let diagrams = file_diagrams(db, file);
        if diagrams.iter().any(|(_, d)| d.fqn == *prefix) {
            file_types(db, file).get(prefix).into_iter().flatten().for_each(&mut add);
        }
        diagrams.iter().filter(|(namespace, _)| namespace == prefix).for_each(|(_, def)| add(def));
    }
    map
}

/// The last segments of the names one namespace declares in more than one file. Each diagram
/// of a file asks whether its name is among them — one set for the whole namespace, backdated
/// unless the set changes, instead of a `lookup` memo per diagram (a file of 100 000 diagrams).
#[salsa::tracked(returns(ref))]
pub fn names_declared_in_several_files<'db>(
    db: &'db dyn Db,
    workspace: Workspace,
    namespace: Fqn<'db>,
) -> std::collections::BTreeSet<String> {
    let definitions = namespace_definitions(db, workspace, namespace);
    let in_several_files = |defs: &Vec<Definition>| defs.iter().any(|d| d.file != defs[0].file);
    definitions.iter().filter(|(_, defs)| in_several_files(defs)).map(|(name, _)| name.clone()).collect()
}

/// Type names are indexed in this many buckets by a hash of the simple name: a renamed type
/// re-reads the names of its bucket, not every type name of the workspace.
pub const TYPE_NAME_BUCKETS: u32 = 64;

/// The bucket of a simple name (FNV-1a: the same in every run, on every machine).
fn bucket_of(name: &str) -> u32 {
    let hash = name.bytes().fold(0x811c_9dc5_u32, |hash, byte| (hash ^ u32::from(byte)).wrapping_mul(0x0100_0193));
    hash % TYPE_NAME_BUCKETS
}

/// The types a file declares: (bucket, simple name, fully qualified name), by bucket and else in
/// declaration order. Equal, so backdated, unless a type is added, removed or renamed.
#[salsa::tracked(returns(ref))]
pub fn file_type_names(db: &dyn Db, file: SourceFile) -> Vec<(u32, String, String)> {
    let mut names: Vec<(u32, String, String)> = file_types(db, file)
        .values()
        .flatten()
        .map(|def| {
            let simple = def.fqn.rsplit('.').next().unwrap_or(&def.fqn).to_string();
            (bucket_of(&simple), simple, def.fqn.clone())
        })
        .collect();
    names.sort_by_key(|(bucket, _, _)| *bucket);
    names
}

/// The fully qualified names of the workspace's types whose simple name falls in `bucket`, by
/// simple name (in workspace order).
#[salsa::tracked(returns(ref))]
pub fn type_names_in_bucket(db: &dyn Db, workspace: Workspace, bucket: u32) -> BTreeMap<String, Vec<String>> {
    let mut map: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for &file in workspace.files(db) {
        let names = file_type_names(db, file);
        let start = names.partition_point(|(b, _, _)| *b < bucket);
        for (_, simple, fqn) in names[start..].iter().take_while(|(b, _, _)| *b == bucket) {
            map.entry(simple.clone()).or_default().push(fqn.clone());
        }
    }
    map
}

/// The fully qualified names of every type of the workspace by simple name, for listings (it
/// merges every bucket; resolution reads one bucket through [`types_named`]).
#[salsa::tracked(returns(ref))]
pub fn type_names(db: &dyn Db, workspace: Workspace) -> BTreeMap<String, Vec<String>> {
    let buckets = (0..TYPE_NAME_BUCKETS).map(|bucket| type_names_in_bucket(db, workspace, bucket));
    buckets.flat_map(|names| names.iter().map(|(simple, fqns)| (simple.clone(), fqns.clone()))).collect()
}

/// `prefix.name`, or `name` at the top.
pub fn join(prefix: &str, name: &str) -> String {
    if prefix.is_empty() {
        name.to_string()
    } else {
        format!("{prefix}.{name}")
    }
}

/// The definitions of one fully qualified name: it depends on the definitions of its namespace
/// only, and is backdated when the answer for this name stays the same.
#[salsa::tracked(returns(ref))]
pub fn lookup<'db>(db: &'db dyn Db, workspace: Workspace, fqn: Fqn<'db>) -> Vec<Definition> {
    let text = fqn.text(db);
    let (namespace, last) = text.rsplit_once('.').unwrap_or(("", text));
    let definitions = namespace_definitions(db, workspace, Fqn::new(db, namespace.to_string()));
    definitions.get(last).cloned().unwrap_or_default()
}

/// The definitions of `fqn`, without making a query of a name whose namespace does not exist
/// (most candidates a qualified name is tried as, `Here.Other.Name` for `Other.Name`): those
/// depend on the one map of namespaces instead of a memo each.
pub fn definitions_named<'db>(db: &'db dyn Db, workspace: Workspace, fqn: &str) -> &'db [Definition] {
    let namespace = fqn.rsplit_once('.').map_or("", |(namespace, _)| namespace);
    if !namespace_files(db, workspace).contains_key(namespace) {
        return &[];
    }
    lookup(db, workspace, Fqn::new(db, fqn.to_string()))
}

/// The fully qualified names of the types whose simple name is `name` (for names used without
/// qualification or import, as the dissertation's listings do across diagrams).
#[salsa::tracked(returns(ref))]
pub fn types_named<'db>(db: &'db dyn Db, workspace: Workspace, name: Fqn<'db>) -> Vec<String> {
    let name = name.text(db);
    type_names_in_bucket(db, workspace, bucket_of(name)).get(name).cloned().unwrap_or_default()
}
