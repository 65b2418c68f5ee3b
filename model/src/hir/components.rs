//! Workspace indexes for component-based checks: which classes are components (with their
//! ports and connections), and which `process…` signatures processor interfaces offer.

use std::collections::{BTreeMap, BTreeSet};

use super::{
    definitions::{definitions_named, file_types, join, DefKind, Fqn},
    items::{item_tree, ComponentItem, DiagramItem, DiagramKind, ImportItem, InterfaceRole, TypeKind, TypeSignature},
    scope::resolve_path,
};
use crate::db::{Db, SourceFile, Workspace};

/// A component as the component diagrams define it, keyed by its class's fully qualified name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ComponentInfo {
    /// The component diagram that declares it.
    pub diagram: String,
    pub item: ComponentItem,
}

/// A component as a file declares it, with the scope its class name is resolved from.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DeclaredComponent {
    /// The enclosing namespaces, innermost last (the component diagram's own is the last).
    pub namespaces: Vec<String>,
    pub imports: Vec<ImportItem>,
    pub item: ComponentItem,
}

/// The components one file's component diagrams declare: equal, so backdated, unless a
/// component diagram changed.
#[salsa::tracked(returns(ref))]
pub fn file_components(db: &dyn Db, file: SourceFile) -> Vec<DeclaredComponent> {
    let mut out = Vec::new();
    for diagram in &item_tree(db, file).diagrams {
        collect(&mut Vec::new(), &mut Vec::new(), diagram, &mut out);
    }
    out
}

fn collect(
    namespaces: &mut Vec<String>,
    imports: &mut Vec<ImportItem>,
    diagram: &DiagramItem,
    out: &mut Vec<DeclaredComponent>,
) {
    let fqn = join(namespaces.last().map_or("", |s| s.as_str()), &diagram.name);
    namespaces.push(fqn);
    let imports_before = imports.len();
    imports.extend(diagram.imports.iter().cloned());
    if diagram.kind == DiagramKind::Component {
        for component in &diagram.components {
            out.push(DeclaredComponent {
                namespaces: namespaces.clone(),
                imports: imports.clone(),
                item: component.clone(),
            });
        }
    }
    for nested in &diagram.diagrams {
        collect(namespaces, imports, nested, out);
    }
    imports.truncate(imports_before);
    namespaces.pop();
}

/// Every component of the workspace by the fully qualified name of its class (a class can be
/// a component in several component diagrams). Class names are resolved through
/// [`definitions_named`], so a class edit re-runs it only when a component's class changes
/// meaning.
#[salsa::tracked(returns(ref))]
pub fn component_index(db: &dyn Db, workspace: Workspace) -> BTreeMap<String, Vec<ComponentInfo>> {
    let mut index: BTreeMap<String, Vec<ComponentInfo>> = BTreeMap::new();
    for &file in workspace.files(db) {
        for declared in file_components(db, file) {
            let exists = |c: &str| !definitions_named(db, workspace, c).is_empty();
            let class = resolve_path(&declared.namespaces, &declared.imports, &declared.item.class, exists)
                .unwrap_or_else(|| declared.item.class.clone());
            let diagram = declared.namespaces.last().cloned().unwrap_or_default();
            index.entry(class).or_default().push(ComponentInfo { diagram, item: declared.item.clone() });
        }
    }
    index
}

/// The components built on the class `class` (a fully qualified name); empty if none.
#[salsa::tracked(returns(ref))]
pub fn component_info<'db>(db: &'db dyn Db, workspace: Workspace, class: Fqn<'db>) -> Vec<ComponentInfo> {
    component_index(db, workspace).get(class.text(db)).cloned().unwrap_or_default()
}

/// The connections (`port.connector` to `port.connector`) each component diagram declares, by
/// the diagram's fully qualified name: a binding between instances of the diagram's
/// components is allowed by any of them, whichever component declares it.
#[salsa::tracked(returns(ref))]
pub fn diagram_connections(db: &dyn Db, workspace: Workspace) -> BTreeMap<String, BTreeSet<(String, String)>> {
    let mut connections: BTreeMap<String, BTreeSet<(String, String)>> = BTreeMap::new();
    for info in component_index(db, workspace).values().flatten() {
        let entry = connections.entry(info.diagram.clone()).or_default();
        entry.extend(info.item.connections.iter().map(|c| (c.source.clone(), c.target.clone())));
    }
    connections
}

/// A method signature reduced to what must match between a provider and a processor:
/// `Image(ref Image)` for `provideImage(ref Image image)` and `processImage(ref Image image)`.
pub fn signature_key(suffix: &str, params: &[TypeSignature]) -> String {
    let params: Vec<String> = params.iter().map(type_key).collect();
    format!("{suffix}({})", params.join(", "))
}

fn type_key(ty: &TypeSignature) -> String {
    let name = ty.builtin.clone().or_else(|| ty.path.as_ref().map(|p| p.rsplit('.').next().unwrap_or(p).to_string()));
    let mut key = String::new();
    if ty.is_ref {
        key.push_str("ref ");
    }
    if ty.is_unsigned {
        key.push_str("unsigned ");
    }
    key.push_str(name.as_deref().unwrap_or("?"));
    key
}

/// The `process…` signatures of one file's processor interfaces, as [`signature_key`]s.
#[salsa::tracked(returns(ref))]
pub fn file_processor_signatures(db: &dyn Db, file: SourceFile) -> BTreeSet<String> {
    let mut keys = BTreeSet::new();
    for def in file_types(db, file).values().flatten() {
        let DefKind::Type(ty) = &def.kind else { continue };
        if ty.kind != TypeKind::Interface(InterfaceRole::Processor) {
            continue;
        }
        for method in &ty.methods {
            if let Some(suffix) = method.name.strip_prefix("process") {
                let params: Vec<TypeSignature> = method.params.iter().map(|p| p.ty.clone()).collect();
                keys.insert(signature_key(suffix, &params));
            }
        }
    }
    keys
}

/// The `process…` signatures of every processor interface of the workspace.
#[salsa::tracked(returns(ref))]
pub fn processor_signatures(db: &dyn Db, workspace: Workspace) -> BTreeSet<String> {
    workspace.files(db).iter().flat_map(|&file| file_processor_signatures(db, file).iter().cloned()).collect()
}
