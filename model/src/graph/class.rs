//! The graph of a class diagram: classes, interfaces, enums and attributes with their members,
//! generalizations, realizations and associations, and the types of other diagrams they reach.

use super::{
    attribute_line, edge_id, text, type_text, visibility_mark, Compartment, EdgeEnd, EdgeKind, Graph, GraphEdge,
    GraphKind, GraphNode, NodeShape,
};
use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{items::TypeKind, DefKind, Scope, Semantics},
    syntax::SyntaxKind::{CONST_KW, GLOBAL_KW, REF_KW},
    syntax::TextRange,
};

pub(super) fn graph(sema: &Semantics, id: String, diagram: &ast::ClassDiagram) -> Graph {
    let scope = Scope::at(diagram.syntax());
    let mut graph = Graph::new(id.clone(), GraphKind::Class, diagram.syntax());
    let mut known: Vec<String> = Vec::new();
    for decl in diagram.type_decls() {
        let Some(name) = decl.name().map(|n| n.text()) else { continue };
        let fqn = format!("{id}.{name}");
        known.push(fqn.clone());
        graph.nodes.push(type_node(&decl, &fqn, &name));
        let resolve =
            |path: &str| sema.resolve(&scope, path).map(|d| d.fqn.clone()).unwrap_or_else(|| path.to_string());
        type_edges(&mut graph, &decl, &fqn, resolve);
    }
    external_nodes(sema, &mut graph, &known);
    graph
}

/// A type's shape, the stereotype of its kind, whether it is abstract, and its template
/// parameters.
fn kind_of(decl: &ast::TypeDecl) -> (NodeShape, Option<String>, bool, Vec<String>) {
    match decl {
        ast::TypeDecl::Class(c) => {
            let stereotype = match c.kind() {
                ast::ClassKind::Class => None,
                ast::ClassKind::Source => Some("source".to_string()),
                ast::ClassKind::Filter => Some("filter".to_string()),
                ast::ClassKind::Sink => Some("sink".to_string()),
            };
            let params: Vec<String> = c.template_params().filter_map(|t| t.name()).map(|n| n.text()).collect();
            (NodeShape::Class, stereotype, c.is_abstract(), params)
        }
        ast::TypeDecl::Interface(i) => {
            let stereotype = match i.role() {
                ast::InterfaceRole::Plain => "interface",
                ast::InterfaceRole::Provider => "provider interface",
                ast::InterfaceRole::Processor => "processor interface",
            };
            (NodeShape::Interface, Some(stereotype.to_string()), false, Vec::new())
        }
        ast::TypeDecl::Enum(_) => (NodeShape::Enum, Some("enumeration".to_string()), false, Vec::new()),
        ast::TypeDecl::AttributeDef(_) => (NodeShape::Attribute, Some("attribute".to_string()), false, Vec::new()),
    }
}

/// A type's node: its label (with template parameters), stereotypes (its kind's and the
/// generator attributes applied to it, as UML shows applied stereotypes, as written), and its
/// members or an enum's values.
fn type_node(decl: &ast::TypeDecl, fqn: &str, name: &str) -> GraphNode {
    let (shape, stereotype, is_abstract, template) = kind_of(decl);
    let label = if template.is_empty() { name.to_string() } else { format!("{name}<{}>", template.join(", ")) };
    let applied: Vec<String> = decl.attribute_lists().iter().flat_map(|l| l.uses()).map(|u| text(&u)).collect();
    let stereotype = match (stereotype, applied.is_empty()) {
        (stereotype, true) => stereotype,
        (None, false) => Some(applied.join(", ")),
        (Some(kind), false) => Some(format!("{kind}, {}", applied.join(", "))),
    };
    let compartments = match decl {
        ast::TypeDecl::Enum(e) => {
            let values: Vec<String> = e.values().filter_map(|v| v.name()).map(|n| n.text()).collect();
            let ids = values.iter().map(|v| format!("{fqn}.{v}")).collect();
            let statics = vec![false; values.len()];
            vec![Compartment { title: None, lines: values, ids, statics }]
        }
        _ => members(decl, fqn),
    };
    GraphNode {
        id: fqn.to_string(),
        shape,
        label,
        stereotype,
        is_abstract,
        compartments,
        ports: Vec::new(),
        group: None,
        parent: None,
        range: decl.syntax().text_range(),
    }
}

/// A type's fields and methods as UML writes them: `+ name : type = initial {readOnly}`,
/// references as `ref type`, static (`global`) members underlined.
fn members(decl: &ast::TypeDecl, fqn: &str) -> Vec<Compartment> {
    let mut fields = Compartment::plain(None, Vec::new());
    let mut methods = Compartment::plain(None, Vec::new());
    for member in decl.members() {
        match &member {
            ast::Member::Field(f) => {
                let name = f.name().map(|n| n.text()).unwrap_or_default();
                let (is_ref, is_const) = (f.has_modifier(REF_KW), f.has_modifier(CONST_KW));
                let line = attribute_line(visibility_mark(f), &name, f.type_ref(), is_ref, f.initializer(), is_const);
                fields.lines.push(line);
                fields.ids.push(format!("{fqn}.{name}"));
                fields.statics.push(f.has_modifier(GLOBAL_KW));
            }
            ast::Member::Method(m) => {
                let ret = type_text(m.return_type(), m.has_modifier(REF_KW));
                let params: Vec<String> = m
                    .params()
                    .map(|p| {
                        let name = p.name().map(|n| n.text()).unwrap_or_default();
                        format!("{name} : {}", type_text(p.type_ref(), p.has_modifier(REF_KW)))
                    })
                    .collect();
                let name = m.name().map(|n| n.text()).unwrap_or_default();
                methods.lines.push(format!("{}{name}({}) : {ret}", visibility_mark(m), params.join(", ")));
                methods.ids.push(format!("{fqn}.{name}()"));
                methods.statics.push(m.has_modifier(GLOBAL_KW));
            }
            ast::Member::Association(_) => {}
        }
    }
    vec![fields, methods]
}

/// A type's edges: generalizations, realizations and associations (with the roles and
/// multiplicities of their ends), to the types `resolve` names.
fn type_edges(graph: &mut Graph, decl: &ast::TypeDecl, fqn: &str, resolve: impl Fn(&str) -> String) {
    let mut edge = |kind: EdgeKind,
                    target: String,
                    label: Option<String>,
                    ends: (Option<String>, Option<String>),
                    range: TextRange| {
        let (source, target) = (EdgeEnd::node(fqn.to_string()), EdgeEnd::node(target));
        graph.edges.push(GraphEdge {
            id: edge_id(graph, &source, &target),
            kind,
            source,
            target,
            label,
            source_label: ends.0,
            target_label: ends.1,
            range,
        });
    };
    let (extends, implements): (Vec<ast::TypeRef>, Vec<ast::TypeRef>) = match decl {
        ast::TypeDecl::Class(c) => (c.extends().collect(), c.implements().collect()),
        ast::TypeDecl::Interface(i) => (i.extends().collect(), Vec::new()),
        _ => (Vec::new(), Vec::new()),
    };
    for (kind, bases) in [(EdgeKind::Generalization, extends), (EdgeKind::Realization, implements)] {
        for base in bases {
            let Some(path) = base.path() else { continue };
            edge(kind, resolve(&path.text()), None, (None, None), base.syntax().text_range());
        }
    }
    for member in decl.members() {
        let ast::Member::Association(a) = member else { continue };
        let Some(target) = a.target().and_then(|t| t.path()) else { continue };
        let kind = match a.kind() {
            ast::AssociationKind::Plain => EdgeKind::Association,
            ast::AssociationKind::Aggregation => EdgeKind::Aggregation,
            ast::AssociationKind::Composition => EdgeKind::Composition,
        };
        let bounds = |m: Option<ast::Multiplicity>| {
            m.map(|m| match m.bounds() {
                (Some(a), Some(b)) => format!("{a}..{b}"),
                (Some(a), None) => a,
                _ => String::new(),
            })
        };
        let role = a.name().map(|n| n.text());
        // `self [m] role : T` gives T's end m; `self [m] role : T [n]` gives this class's end m
        // and T's n (the dissertation's "self [1] contains : Pixel [0 .. *]": one image per
        // pixel, any number of pixels per image).
        let (own, far) = (bounds(a.own_multiplicity()), bounds(a.target_multiplicity()));
        let ends = if far.is_some() { (own, far) } else { (None, own) };
        edge(kind, resolve(&target.text()), role, ends, a.syntax().text_range());
    }
}

/// The types of other diagrams that edges reach, as external nodes.
fn external_nodes(sema: &Semantics, graph: &mut Graph, known: &[String]) {
    let external: Vec<String> =
        graph.edges.iter().map(|e| e.target.node.clone()).filter(|t| !known.contains(t)).collect();
    for target in external {
        if graph.nodes.iter().any(|n| n.id == target) {
            continue;
        }
        let is_interface = sema
            .definition(&target)
            .is_some_and(|d| matches!(&d.kind, DefKind::Type(ty) if matches!(ty.kind, TypeKind::Interface(_))));
        graph.nodes.push(GraphNode {
            id: target.clone(),
            shape: NodeShape::External,
            label: target.rsplit('.').next().unwrap_or(&target).to_string(),
            stereotype: is_interface.then(|| "interface".to_string()),
            is_abstract: false,
            compartments: Vec::new(),
            ports: Vec::new(),
            group: None,
            parent: None,
            range: TextRange::default(),
        });
    }
}
