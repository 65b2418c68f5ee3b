//! Graph edits as text edits (the graph view's `gudsl/applyGraphEdit`): operations on a
//! diagram's graph, naming its elements by the ids of `graph/`, answered with the edits of the
//! text that make them, so the text stays the one truth and the graph follows it. A rename goes
//! through [`rename`]; new text is placed and deleted text taken as `place` says.
//!
//! An operation a user could type is made even when the model it gives is wrong (the
//! diagnostics say what is wrong); one the language cannot state (a transition to a node of
//! another diagram, a second superclass) is refused with the reason, and so is a batch whose
//! text would not parse as well as before.

mod create;
mod delete;
mod edges;
mod place;
mod properties;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_edges;
#[cfg(test)]
mod tests_ops;

use std::collections::BTreeMap;

use crate::{
    ast::{self, AstNode},
    db::{parse, Db, SourceFile, Workspace},
    graph::{file_graphs, EdgeKind, Graph, GraphEdge, GraphGroup, GraphNode, GraphPort},
    hir::{Scope, Semantics},
    syntax::{NodeKind, SyntaxKind::*, SyntaxNode, TextRange},
};

use super::{references::is_valid_name, rename, FileRange};
pub use properties::property;

/// Named values an operation takes (`type`, `guard`, `sourceMultiplicity`, …).
pub type Properties = BTreeMap<String, String>;

/// One operation on a diagram's graph.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum GraphOp {
    /// Declares a new element: a node (in the diagram, a swimlane or a component), a member of a
    /// class, a port or connector of a component, a port instance of an instance.
    Create { kind: NewKind, name: String, parent: Option<String>, properties: Properties },
    /// Deletes an element and what would dangle without it (the edges of a deleted node).
    Delete { element: String },
    /// Renames a node and every reference to it, across files.
    Rename { element: String, name: String },
    /// States a new edge from `source` to `target` (nodes, or ports for connections and bindings).
    Connect { kind: EdgeKind, source: String, target: String, properties: Properties },
    /// Moves an edge's ends.
    Reconnect { edge: String, source: Option<String>, target: Option<String> },
    /// Sets (`Some`) or removes (`None`) a property: a guard, a multiplicity, a field's value, …
    SetProperty { element: String, property: String, value: Option<String> },
}

/// What [`GraphOp::Create`] declares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NewKind {
    Class,
    Interface,
    Enum,
    Value,
    Field,
    Method,
    /// An activity node of a kind of the grammar's (`action`, `loopWindow`, …).
    Node(NodeKind),
    Component,
    Port,
    Connector,
    Instance,
    PortInstance,
}

impl NewKind {
    /// The kinds that are no activity node, with their names in the protocol.
    const OTHERS: [(NewKind, &'static str); 11] = [
        (NewKind::Class, "class"),
        (NewKind::Interface, "interface"),
        (NewKind::Enum, "enum"),
        (NewKind::Value, "value"),
        (NewKind::Field, "field"),
        (NewKind::Method, "method"),
        (NewKind::Component, "component"),
        (NewKind::Port, "port"),
        (NewKind::Connector, "connector"),
        (NewKind::Instance, "instance"),
        (NewKind::PortInstance, "portInstance"),
    ];

    /// Every kind with its name in the protocol (an activity node's is its keyword).
    pub fn all() -> impl Iterator<Item = (NewKind, &'static str)> {
        let nodes = NodeKind::ALL.into_iter().map(|kind| (NewKind::Node(kind), kind.keyword()));
        NewKind::OTHERS[..6].iter().copied().chain(nodes).chain(NewKind::OTHERS[6..].iter().copied())
    }

    /// Whether it is a node of an activity diagram.
    pub fn is_activity_node(self) -> bool {
        matches!(self, NewKind::Node(_))
    }

    pub fn name(self) -> &'static str {
        match self {
            NewKind::Node(kind) => kind.keyword(),
            other => NewKind::OTHERS.iter().find(|(k, _)| *k == other).map_or("", |(_, n)| *n),
        }
    }

    pub fn from_name(name: &str) -> Option<NewKind> {
        NewKind::all().find(|(_, n)| *n == name).map(|(k, _)| k)
    }
}

/// Why a batch of operations cannot be made: nothing is changed.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GraphEditError(pub String);

/// The text edits that make `ops` on the diagram `diagram` of `file`, all computed on the
/// text as it is (a batch whose operations would edit the same text is refused).
pub fn graph_edit(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    diagram: &str,
    ops: &[GraphOp],
) -> Result<Vec<(FileRange, String)>, GraphEditError> {
    let ctx = Ctx::new(db, workspace, file, diagram)?;
    let mut edits: Vec<(usize, FileRange, String)> = Vec::new();
    for (k, op) in ops.iter().enumerate() {
        let made = ctx.make(op).map_err(|reason| GraphEditError(format!("operation {k}: {reason}")))?;
        for (range, text) in made {
            if let Some((j, _, _)) =
                edits.iter().find(|(_, r, _)| r.file == range.file && overlap(r.range, range.range))
            {
                if *j != k {
                    return Err(GraphEditError(format!(
                        "operations {j} and {k} edit the same text: send them in separate batches"
                    )));
                }
                continue; // reached twice (a reference; an edge of two deleted nodes)
            }
            edits.push((k, range, text));
        }
    }
    let edits: Vec<(FileRange, String)> = edits.into_iter().map(|(_, range, text)| (range, text)).collect();
    ctx.still_parses(&edits)?;
    Ok(edits)
}

/// What an operation works on.
pub(super) struct Ctx<'a> {
    db: &'a dyn Db,
    workspace: Workspace,
    file: SourceFile,
    graph: &'a Graph,
    root: SyntaxNode,
    sema: Semantics<'a>,
}

/// An element of the graph, found by its id.
pub(super) enum Element<'g> {
    Node(&'g GraphNode),
    /// A field, a method, an enum value or an instance's field value, by its name.
    Member {
        owner: &'g GraphNode,
        name: String,
    },
    Port {
        owner: &'g GraphNode,
        port: &'g GraphPort,
    },
    Edge(&'g GraphEdge),
    Group(&'g GraphGroup),
}

impl<'a> Ctx<'a> {
    fn new(db: &'a dyn Db, workspace: Workspace, file: SourceFile, diagram: &str) -> Result<Ctx<'a>, GraphEditError> {
        let graphs = file_graphs(db, workspace, file);
        let Some(graph) = graphs.iter().find(|g| g.id == diagram) else {
            let known: Vec<&str> = graphs.iter().map(|g| g.id.as_str()).collect();
            let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
            return Err(GraphEditError(format!(
                "{} declares no diagram `{diagram}` (it declares: {known})",
                file.path(db)
            )));
        };
        let root = parse(db, file).syntax_node();
        Ok(Ctx { db, workspace, file, graph, root, sema: Semantics::new(db, workspace) })
    }

    fn make(&self, op: &GraphOp) -> Result<Vec<(FileRange, String)>, String> {
        let here = |edits: Vec<place::Edit>| -> Vec<(FileRange, String)> {
            edits.into_iter().map(|(range, text)| (FileRange { file: self.file, range }, text)).collect()
        };
        Ok(match op {
            GraphOp::Rename { element, name } => {
                let Some(Element::Node(node)) = self.element(element) else {
                    return Err(format!("`{}` has no node `{element}`", self.graph.id));
                };
                let Some(at) = declared_name(&self.root, node.range) else {
                    return Err(format!("`{element}` is not declared in this file: rename it where it is"));
                };
                rename(self.db, self.workspace, self.file, at.start(), name).map_err(|e| e.0)?
            }
            GraphOp::Create { kind, name, parent, properties } => {
                here(create::create(self, *kind, name, parent.as_deref(), properties)?)
            }
            GraphOp::Delete { element } => here(delete::delete(self, element)?),
            GraphOp::Connect { kind, source, target, properties } => {
                here(edges::connect(self, *kind, source, target, properties)?)
            }
            GraphOp::Reconnect { edge, source, target } => {
                here(edges::reconnect(self, edge, source.as_deref(), target.as_deref())?)
            }
            GraphOp::SetProperty { element, property, value } => {
                here(properties::set(self, element, property, value.as_deref())?)
            }
        })
    }

    /// The element `id` names in the graph.
    pub(super) fn element(&self, id: &str) -> Option<Element<'a>> {
        let graph = self.graph;
        if let Some(node) = graph.nodes.iter().find(|n| n.id == id) {
            return Some(Element::Node(node));
        }
        if let Some(edge) = graph.edges.iter().find(|e| e.id == id) {
            return Some(Element::Edge(edge));
        }
        if let Some(group) = graph.groups.iter().find(|g| g.id == id) {
            return Some(Element::Group(group));
        }
        for owner in &graph.nodes {
            if let Some(port) = owner.ports.iter().find(|p| p.id == id) {
                return Some(Element::Port { owner, port });
            }
            if owner.compartments.iter().any(|c| c.ids.iter().any(|m| m == id)) {
                let name = id[owner.id.len() + 1..].trim_end_matches("()").to_string();
                return Some(Element::Member { owner, name });
            }
        }
        None
    }

    /// The node of the graph `id` names, refused if it is none.
    pub(super) fn node(&self, id: &str) -> Result<&'a GraphNode, String> {
        match self.element(id) {
            Some(Element::Node(node)) => Ok(node),
            Some(_) => Err(format!("`{id}` is no node")),
            None => Err(format!("`{}` has no node `{id}`", self.graph.id)),
        }
    }

    /// The syntax of what the graph draws at `range` (the outermost node with exactly it).
    pub(super) fn syntax(&self, range: TextRange) -> Option<SyntaxNode> {
        syntax_at(&self.root, range)
    }

    /// The declaration of a node of the graph.
    pub(super) fn declaration(&self, node: &GraphNode) -> Result<SyntaxNode, String> {
        self.syntax(node.range).ok_or_else(|| format!("`{}` is declared in another diagram: edit it there", node.id))
    }

    pub(super) fn diagram(&self) -> SyntaxNode {
        self.syntax(self.graph.range).expect("a graph is drawn from its diagram")
    }

    /// A member of `owner` by name: a field, a method, an enum value, an instance's field value.
    pub(super) fn member(&self, owner: &SyntaxNode, name: &str) -> Option<SyntaxNode> {
        let holders = owner.children().filter(|c| matches!(c.kind(), MEMBER_LIST | NAMED_ARG_LIST));
        holders
            .chain(std::iter::once(owner.clone()))
            .flat_map(|h| h.children())
            .filter(|c| matches!(c.kind(), FIELD | METHOD | ENUM_VALUE | NAMED_ARG))
            .find(|c| name_of(c).as_deref() == Some(name))
    }

    /// The syntax of a port: the connector of a component's port or of an instance's port
    /// instance, and the port (instance) it is in.
    pub(super) fn port(&self, owner: &GraphNode, port: &GraphPort) -> Result<(SyntaxNode, SyntaxNode), String> {
        let declaration = self.declaration(owner)?;
        let rest = &port.id[owner.id.len() + 1..];
        let (port_name, connector) = rest.split_once('.').ok_or_else(|| format!("`{}` is no port", port.id))?;
        let port = declaration
            .children()
            .filter(|c| matches!(c.kind(), PORT | PORT_INSTANCE))
            .find(|c| name_of(c).as_deref() == Some(port_name))
            .ok_or_else(|| format!("`{}` has no port `{port_name}`", owner.id))?;
        let connector = port
            .children()
            .filter(|c| matches!(c.kind(), CONNECTOR | CID_CONNECTOR))
            .find(|c| name_of(c).as_deref() == Some(connector))
            .ok_or_else(|| format!("`{port_name}` has no connector `{connector}`"))?;
        Ok((port, connector))
    }

    /// A swimlane's declaration.
    pub(super) fn swimlane(&self, group: &GraphGroup) -> Option<SyntaxNode> {
        self.diagram()
            .children()
            .filter(|c| c.kind() == SWIMLANE)
            .find(|c| name_of(c).as_deref() == Some(group.label.as_str()))
    }

    /// How a text at `from` writes the type `fqn`: the shortest name that means it there.
    pub(super) fn written_type(&self, from: &SyntaxNode, fqn: &str) -> String {
        let scope = Scope::at(from);
        let segments: Vec<&str> = fqn.split('.').collect();
        (1..=segments.len())
            .map(|n| segments[segments.len() - n..].join("."))
            .find(|name| self.sema.resolve(&scope, name).is_some_and(|d| d.fqn == fqn))
            .unwrap_or_else(|| fqn.to_string())
    }

    pub(super) fn root(&self) -> &SyntaxNode {
        &self.root
    }

    /// The file's text.
    pub(super) fn text(&self) -> &'a str {
        self.file.text(self.db)
    }

    pub(super) fn sema(&self) -> &Semantics<'a> {
        &self.sema
    }

    pub(super) fn graph(&self) -> &'a Graph {
        self.graph
    }

    /// Refuses edits after which this file would parse worse than before.
    fn still_parses(&self, edits: &[(FileRange, String)]) -> Result<(), GraphEditError> {
        let mine: Vec<(TextRange, &str)> =
            edits.iter().filter(|(r, _)| r.file == self.file).map(|(r, t)| (r.range, t.as_str())).collect();
        if mine.is_empty() {
            return Ok(());
        }
        let before = parse(self.db, self.file).errors().len();
        let text = crate::text::with_edits(self.file.text(self.db), mine);
        let after = crate::syntax::parse(&text);
        if after.errors().len() > before {
            let first = &after.errors()[0];
            return Err(GraphEditError(format!(
                "the edit would not parse: {} (a value is written into the text as it is given)",
                first.message
            )));
        }
        Ok(())
    }
}

/// The name a declaration declares (`Name`), or a field value names (`NameRef`).
pub(super) fn name_of(node: &SyntaxNode) -> Option<String> {
    node.children().find(|c| matches!(c.kind(), NAME | NAME_REF)).map(|n| n.text().to_string())
}

/// Refuses a property `what` does not have, naming those it has.
pub(super) fn has_properties<'p>(
    what: &str,
    given: impl IntoIterator<Item = &'p str>,
    known: &[&str],
) -> Result<(), String> {
    match given.into_iter().find(|p| !known.contains(p)) {
        Some(unknown) => {
            let known = if known.is_empty() { "none".to_string() } else { known.join(", ") };
            Err(format!("{what} has no property `{unknown}` (it has: {known})"))
        }
        None => Ok(()),
    }
}

/// A name a user could type, refused otherwise.
pub(super) fn valid_name(name: &str) -> Result<(), String> {
    if is_valid_name(name) {
        Ok(())
    } else {
        Err(format!("`{name}` is not a valid name"))
    }
}

/// The outermost node of `root` with exactly `range` (a graph element's); `None` for an empty
/// range (a node drawn for an edge that leaves the diagram: declared elsewhere).
fn syntax_at(root: &SyntaxNode, range: TextRange) -> Option<SyntaxNode> {
    if range.is_empty() {
        return None;
    }
    let start = match root.covering_element(range) {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    start.ancestors().skip_while(|n| n.text_range() != range).take_while(|n| n.text_range() == range).last()
}

/// The name of the declaration at `range` (a node's range).
fn declared_name(root: &SyntaxNode, range: TextRange) -> Option<TextRange> {
    let declaration = syntax_at(root, range)?;
    ast::support::child::<ast::Name>(&declaration).map(|name| name.syntax().text_range())
}

fn overlap(a: TextRange, b: TextRange) -> bool {
    a.start() < b.end() && b.start() < a.end() || a == b
}
