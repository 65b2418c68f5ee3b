//! Workspace indexes for component-based checks: which classes are components (with their
//! ports and connections), and which `process…` signatures processor interfaces offer.

use std::collections::{BTreeMap, BTreeSet};

use super::{
    definitions::{def_map, join, DefKind, DefMap, Fqn},
    items::{item_tree, ComponentItem, DiagramItem, DiagramKind, ImportItem, InterfaceRole, TypeKind, TypeSignature},
    scope::resolve_path,
};
use crate::db::{Db, Workspace};

/// A component as the component diagrams define it, keyed by its class's fully qualified name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ComponentInfo {
    /// The component diagram that declares it.
    pub diagram: String,
    pub item: ComponentItem,
}

/// Every component of the workspace by the fully qualified name of its class (a class can be
/// a component in several component diagrams).
#[salsa::tracked(returns(ref))]
pub fn component_index(db: &dyn Db, workspace: Workspace) -> BTreeMap<String, Vec<ComponentInfo>> {
    let defs = def_map(db, workspace);
    let mut index = BTreeMap::new();
    for &file in workspace.files(db) {
        for diagram in &item_tree(db, file).diagrams {
            collect(defs, &mut Vec::new(), &mut Vec::new(), diagram, &mut index);
        }
    }
    index
}

fn collect(
    defs: &DefMap,
    namespaces: &mut Vec<String>,
    imports: &mut Vec<ImportItem>,
    diagram: &DiagramItem,
    index: &mut BTreeMap<String, Vec<ComponentInfo>>,
) {
    let fqn = join(namespaces.last().map_or("", |s| s.as_str()), &diagram.name);
    namespaces.push(fqn.clone());
    let imports_before = imports.len();
    imports.extend(diagram.imports.iter().cloned());
    if diagram.kind == DiagramKind::Component {
        for component in &diagram.components {
            let resolved = resolve_path(namespaces, imports, &component.class, |c| defs.definitions.contains_key(c));
            let class = resolved.unwrap_or_else(|| component.class.clone());
            index.entry(class).or_default().push(ComponentInfo { diagram: fqn.clone(), item: component.clone() });
        }
    }
    for nested in &diagram.diagrams {
        collect(defs, namespaces, imports, nested, index);
    }
    imports.truncate(imports_before);
    namespaces.pop();
}

/// The components built on the class `class` (a fully qualified name); empty if none.
#[salsa::tracked(returns(ref))]
pub fn component_info<'db>(db: &'db dyn Db, workspace: Workspace, class: Fqn<'db>) -> Vec<ComponentInfo> {
    component_index(db, workspace).get(class.text(db)).cloned().unwrap_or_default()
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

/// The `process…` signatures of every processor interface, as [`signature_key`]s.
#[salsa::tracked(returns(ref))]
pub fn processor_signatures(db: &dyn Db, workspace: Workspace) -> BTreeSet<String> {
    let mut keys = BTreeSet::new();
    for definitions in def_map(db, workspace).definitions.values() {
        for def in definitions {
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
    }
    keys
}
