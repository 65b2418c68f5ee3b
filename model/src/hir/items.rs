//! Item tree: the declarations of one file without positions or bodies.
//!
//! It is the barrier between editing and resolution (as in rust-analyzer): typing inside a
//! method body, an action body or a comment produces an equal item tree, so salsa backdates it
//! and nothing that depends only on declarations runs again.

use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    db::{parse, Db, SourceFile},
    syntax::SyntaxKind,
};

pub use crate::ast::{ClassKind, ConnectorRole, InterfaceRole, NodeKind};

/// The declarations of one file.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct ItemTree {
    pub diagrams: Vec<DiagramItem>,
}

/// The kind of a diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DiagramKind {
    Class,
    Activity,
    Component,
    ComponentInstance,
}

/// A diagram and what it declares. Diagrams nest: a nested diagram is a namespace.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct DiagramItem {
    pub kind: DiagramKind,
    pub name: String,
    pub imports: Vec<ImportItem>,
    pub types: Vec<std::sync::Arc<TypeItem>>,
    pub diagrams: Vec<DiagramItem>,
    pub activity: Option<std::sync::Arc<ActivitySignature>>,
    /// Components of a component diagram (nested ones flattened, in order).
    pub components: Vec<ComponentItem>,
}

/// A component: the class it is built on, its ports and the connections it declares.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ComponentItem {
    pub kind: ClassKind,
    /// The component class, as written (resolved from the diagram's scope).
    pub class: String,
    pub ports: Vec<PortItem>,
    pub connections: Vec<ConnectionItem>,
}

/// A port and its connectors.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PortItem {
    pub name: String,
    pub is_async: bool,
    pub is_buffered: bool,
    pub connectors: Vec<ConnectorItem>,
}

/// `provider name : Interface`
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ConnectorItem {
    pub role: ConnectorRole,
    pub name: String,
    pub interface: String,
}

/// `[Name source port.connector ==> target port.connector]`
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ConnectionItem {
    pub name: Option<String>,
    pub source: String,
    pub target: String,
}

/// An import.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum ImportItem {
    Name(String),
    Wildcard(String),
    /// A C++ header: accepted, not resolved.
    Header,
}

/// The kind of a type declaration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum TypeKind {
    Class(ClassKind),
    Interface(InterfaceRole),
    Enum,
    Attribute,
}

/// A class, interface, enum or attribute definition.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct TypeItem {
    pub kind: TypeKind,
    pub name: String,
    pub is_abstract: bool,
    pub template_params: Vec<String>,
    pub extends: Vec<TypeSignature>,
    pub implements: Vec<TypeSignature>,
    pub fields: Vec<FieldSignature>,
    pub methods: Vec<MethodSignature>,
    pub enum_values: Vec<String>,
}

impl TypeItem {
    /// Why no object of this type can be made (`new`, a component instance): it is an
    /// interface or an abstract class (Sec. 9.1.1). The one rule for both.
    pub fn why_not_instantiable(&self) -> Option<&'static str> {
        match self.kind {
            TypeKind::Interface(_) => Some("an interface: instantiate a class that implements it"),
            TypeKind::Class(_) if self.is_abstract => Some("abstract: instantiate a class that extends it"),
            _ => None,
        }
    }
}

/// A type as written: built-in or a path, with its qualifiers and arguments.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct TypeSignature {
    /// `int`, `float`, … for built-ins.
    pub builtin: Option<String>,
    /// `A.B.C` for named types.
    pub path: Option<String>,
    /// `ref T`, written in the type or among the declaration's qualifiers (`global ref int p`).
    pub is_ref: bool,
    /// `global` among the declaration's qualifiers: the global memory of a kernel parameter
    /// (`global ref unsigned int`), a static field or method on the host.
    pub is_global: bool,
    pub is_unsigned: bool,
    pub args: Vec<TypeSignature>,
    pub array_dims: usize,
}

/// A field, activity variable or attribute field.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct FieldSignature {
    pub name: String,
    pub ty: TypeSignature,
    pub qualifiers: Vec<String>,
    pub has_default: bool,
}

/// A method signature.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct MethodSignature {
    pub name: String,
    pub ret: TypeSignature,
    pub params: Vec<ParamSignature>,
    /// `public`, `private`, `global`, … as written.
    pub qualifiers: Vec<String>,
}

/// A parameter of a method, activity diagram or node.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct ParamSignature {
    pub name: String,
    pub ty: TypeSignature,
    pub qualifiers: Vec<String>,
}

/// What an activity diagram declares: parameters, owner, variables, swimlanes and nodes.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct ActivitySignature {
    pub params: Vec<ParamSignature>,
    pub owner: Option<String>,
    pub variables: Vec<FieldSignature>,
    pub swimlanes: Vec<SwimlaneSignature>,
}

/// A swimlane; nodes outside any swimlane form one with no name.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct SwimlaneSignature {
    pub name: Option<String>,
    pub owner: Option<String>,
    pub nodes: Vec<NodeSignature>,
}

/// A node's kind, name and declared parameters.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NodeSignature {
    pub kind: NodeKind,
    pub name: String,
    pub params: Vec<ParamSignature>,
}

/// The item tree of a file.
#[salsa::tracked(returns(ref))]
pub fn item_tree(db: &dyn Db, file: SourceFile) -> ItemTree {
    let source = parse(db, file).source_file();
    ItemTree { diagrams: source.diagrams().filter_map(|d| diagram_item(&d)).collect() }
}

fn name_of(node: &impl HasName) -> Option<String> {
    node.name().map(|n| n.text()).filter(|n| !n.is_empty())
}

fn diagram_item(diagram: &ast::Diagram) -> Option<DiagramItem> {
    let name = diagram.name().map(|n| n.text()).filter(|n| !n.is_empty())?;
    let mut item = DiagramItem {
        kind: DiagramKind::Class,
        name,
        imports: Vec::new(),
        types: Vec::new(),
        diagrams: Vec::new(),
        activity: None,
        components: Vec::new(),
    };
    let imports: Vec<ast::Import> = ast::support::children::<ast::Import>(diagram.syntax()).collect();
    item.imports = imports.iter().filter_map(import_item).collect();
    item.diagrams = ast::support::children::<ast::Diagram>(diagram.syntax()).filter_map(|d| diagram_item(&d)).collect();
    match diagram {
        ast::Diagram::ClassDiagram(d) => {
            item.types = d.type_decls().filter_map(|t| type_item(&t)).map(std::sync::Arc::new).collect()
        }
        ast::Diagram::ActivityDiagram(d) => {
            item.kind = DiagramKind::Activity;
            item.activity = Some(std::sync::Arc::new(activity_signature(d)));
        }
        ast::Diagram::ComponentDiagram(d) => {
            item.kind = DiagramKind::Component;
            for component in d.components() {
                component_items(&component, &mut item.components);
            }
        }
        ast::Diagram::ComponentInstanceDiagram(_) => item.kind = DiagramKind::ComponentInstance,
    }
    Some(item)
}

fn component_items(component: &ast::Component, out: &mut Vec<ComponentItem>) {
    use ast::HasEnds;
    let Some(class) = component.class().map(|p| p.text()) else { return };
    let ports = component
        .ports()
        .filter_map(|port| {
            Some(PortItem {
                name: name_of(&port)?,
                is_async: port.is_async(),
                is_buffered: port.is_buffered(),
                connectors: port
                    .connectors()
                    .filter_map(|c| {
                        Some(ConnectorItem { role: c.role()?, name: name_of(&c)?, interface: c.interface()?.text() })
                    })
                    .collect(),
            })
        })
        .collect();
    let connections = component
        .connections()
        .filter_map(|c| {
            Some(ConnectionItem {
                name: c.connection_name().map(|n| n.text()),
                source: c.source()?.text(),
                target: c.target()?.text(),
            })
        })
        .collect();
    out.push(ComponentItem { kind: component.kind(), class, ports, connections });
    for nested in component.components() {
        component_items(&nested, out);
    }
}

/// What an import statement brings into scope.
pub(crate) fn import_item(import: &ast::Import) -> Option<ImportItem> {
    Some(match import.target()? {
        ast::ImportTarget::Name(p) => ImportItem::Name(p.text()),
        ast::ImportTarget::Wildcard(p) => ImportItem::Wildcard(p.text()),
        ast::ImportTarget::Header(_) => ImportItem::Header,
    })
}

/// The signature of a type reference (an absent type reads as the empty signature).
pub fn type_signature(ty: Option<ast::TypeRef>) -> TypeSignature {
    let Some(ty) = ty else { return TypeSignature::default() };
    // The qualifiers of the declaration the type is written in (`global ref` before a
    // parameter's type); none for a type argument.
    let qualifier = |keyword: SyntaxKind| {
        ty.syntax()
            .parent()
            .and_then(|parent| ast::support::child::<ast::Modifiers>(&parent))
            .is_some_and(|m| m.has(keyword))
    };
    TypeSignature {
        builtin: ty.builtin().map(|t| t.text().to_string()),
        path: ty.path().map(|p| p.text()),
        is_ref: ty.is_ref() || qualifier(SyntaxKind::REF_KW),
        is_global: qualifier(SyntaxKind::GLOBAL_KW),
        is_unsigned: ty.is_unsigned(),
        args: ty.type_args().map(|t| type_signature(Some(t))).collect(),
        array_dims: ty.array_dims(),
    }
}

fn qualifiers(node: &impl HasModifiers) -> Vec<String> {
    node.modifiers()
        .map(|m| m.keywords().map(|k| k.describe().trim_matches('`').to_string()).collect())
        .unwrap_or_default()
}

fn param_signature(param: &ast::Param) -> Option<ParamSignature> {
    Some(ParamSignature { name: name_of(param)?, ty: type_signature(param.type_ref()), qualifiers: qualifiers(param) })
}

fn type_item(decl: &ast::TypeDecl) -> Option<TypeItem> {
    let name = decl.name().map(|n| n.text()).filter(|n| !n.is_empty())?;
    let mut item = TypeItem {
        kind: TypeKind::Enum,
        name,
        is_abstract: false,
        template_params: Vec::new(),
        extends: Vec::new(),
        implements: Vec::new(),
        fields: Vec::new(),
        methods: Vec::new(),
        enum_values: Vec::new(),
    };
    let sig = |t: ast::TypeRef| type_signature(Some(t));
    match decl {
        ast::TypeDecl::Class(c) => {
            item.kind = TypeKind::Class(c.kind());
            item.is_abstract = c.is_abstract();
            item.template_params = c.template_params().filter_map(|t| name_of(&t)).collect();
            item.extends = c.extends().map(sig).collect();
            item.implements = c.implements().map(sig).collect();
        }
        ast::TypeDecl::Interface(i) => {
            item.kind = TypeKind::Interface(i.role());
            item.template_params = i.template_params().filter_map(|t| name_of(&t)).collect();
            item.extends = i.extends().map(sig).collect();
        }
        ast::TypeDecl::Enum(e) => item.enum_values = e.values().filter_map(|v| name_of(&v)).collect(),
        ast::TypeDecl::AttributeDef(_) => item.kind = TypeKind::Attribute,
    }
    for member in decl.members() {
        match member {
            ast::Member::Field(f) => {
                if let Some(name) = name_of(&f) {
                    item.fields.push(FieldSignature {
                        name,
                        ty: type_signature(f.type_ref()),
                        qualifiers: qualifiers(&f),
                        has_default: f.initializer().is_some(),
                    });
                }
            }
            ast::Member::Association(a) => {
                if let Some(name) = name_of(&a) {
                    item.fields.push(FieldSignature {
                        name,
                        ty: type_signature(a.target()),
                        qualifiers: qualifiers(&a),
                        has_default: false,
                    });
                }
            }
            ast::Member::Method(m) => {
                if let Some(name) = name_of(&m) {
                    item.methods.push(MethodSignature {
                        name,
                        ret: type_signature(m.return_type()),
                        params: m.params().filter_map(|p| param_signature(&p)).collect(),
                        qualifiers: qualifiers(&m),
                    });
                }
            }
        }
    }
    Some(item)
}

fn activity_signature(diagram: &ast::ActivityDiagram) -> ActivitySignature {
    // A node's nested nodes (Sec. 9.2.2.3) are the swimlane's too: node names are one namespace.
    let with_nested = |n: ast::ActivityNode| n.and_nested();
    let node_signature = |n: ast::ActivityNode| {
        Some(NodeSignature {
            kind: n.kind(),
            name: name_of(&n)?,
            params: n.params().filter_map(|p| param_signature(&p)).collect(),
        })
    };
    let mut swimlanes: Vec<SwimlaneSignature> = diagram
        .swimlanes()
        .map(|lane| SwimlaneSignature {
            name: name_of(&lane),
            owner: lane.owner().map(|p| p.text()),
            nodes: lane.nodes().flat_map(with_nested).filter_map(node_signature).collect(),
        })
        .collect();
    let loose: Vec<NodeSignature> = diagram.nodes().flat_map(with_nested).filter_map(node_signature).collect();
    if !loose.is_empty() {
        swimlanes.push(SwimlaneSignature { name: None, owner: None, nodes: loose });
    }
    let mut variables: Vec<FieldSignature> = diagram
        .variables()
        .filter_map(|v| {
            Some(FieldSignature {
                name: name_of(&v)?,
                ty: type_signature(v.type_ref()),
                qualifiers: qualifiers(&v),
                has_default: v.initializer().is_some(),
            })
        })
        .collect();
    variables.extend(diagram.var_decls().filter_map(|v| {
        Some(FieldSignature {
            name: name_of(&v)?,
            ty: type_signature(v.type_ref()),
            qualifiers: qualifiers(&v),
            has_default: v.initializer().is_some(),
        })
    }));
    ActivitySignature {
        params: diagram.params().filter_map(|p| param_signature(&p)).collect(),
        owner: diagram.owner().map(|p| p.text()),
        variables,
        swimlanes,
    }
}
