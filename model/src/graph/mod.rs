//! Graph view: every diagram as nodes (with compartments and ports), edges (with kinds, labels
//! and ends resolved to nodes and ports) and groups (swimlanes), independent of any renderer.
//! One module a diagram kind builds its graphs.
//!
//! Ids come from names, never positions (DESIGN.md, "Identity"): a class is its fully qualified
//! name, an activity node `Diagram/swimlane/node`, a transition `source->target#k` (k counting
//! transitions between the same two nodes), a port `Component.port.connector`. They survive
//! whitespace, comment and reordering edits.

mod activity;
mod class;
mod components;
#[cfg(test)]
pub(crate) mod tests;

use crate::{
    ast::{self, AstNode, HasModifiers},
    db::{parse, Db, SourceFile, Workspace},
    hir::{Scope, Semantics},
    syntax::TextRange,
};

/// The kind of a diagram.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GraphKind {
    Class,
    Activity,
    Component,
    ComponentInstance,
}

/// What a node is drawn as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum NodeShape {
    Class,
    Interface,
    Enum,
    Attribute,
    /// A type of another diagram, drawn for an edge that leaves this one.
    External,
    Start,
    Final,
    Action,
    Decision,
    Fork,
    Join,
    Loop,
    LoopWindow,
    Calc,
    CalcRange,
    Component,
    Instance,
}

/// A titled list of text lines inside a node (fields, methods, expressions, values).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Compartment {
    pub title: Option<String>,
    pub lines: Vec<String>,
    /// `ids[i]` is the id of the element `lines[i]` shows (a field, a method, an enum value, an
    /// instance's field value: `Owner.name`, a method `Owner.name()`), empty for a line that
    /// is no element of its own (a statement, a loop header's section).
    pub ids: Vec<String>,
    /// `statics[i]`: `lines[i]` shows a static (`global`) member, which UML underlines.
    pub statics: Vec<bool>,
}

impl Compartment {
    /// A compartment of lines that are no elements of their own.
    pub fn plain(title: Option<String>, lines: Vec<String>) -> Compartment {
        let ids = vec![String::new(); lines.len()];
        let statics = vec![false; lines.len()];
        Compartment { title, lines, ids, statics }
    }
}

/// A port on a node's boundary.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphPort {
    pub id: String,
    pub label: String,
    /// `provider` (lollipop) or `processor` (socket); `None` for a port instance's own box.
    pub provider: Option<bool>,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphNode {
    pub id: String,
    pub shape: NodeShape,
    pub label: String,
    /// «interface», «source», «attribute», … or a node kind's header.
    pub stereotype: Option<String>,
    pub is_abstract: bool,
    pub compartments: Vec<Compartment>,
    pub ports: Vec<GraphPort>,
    /// The swimlane it belongs to (activity diagrams).
    pub group: Option<String>,
    /// The node it is nested in (a component inside another; an activity node inside the
    /// loop, decision or action that holds it).
    pub parent: Option<String>,
    /// Where it is declared, for round trips to the text.
    pub range: TextRange,
}

/// The kind of an edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EdgeKind {
    Generalization,
    Realization,
    Association,
    Aggregation,
    Composition,
    Transition,
    Connection,
    Binding,
}

impl EdgeKind {
    pub const ALL: [EdgeKind; 8] = [
        EdgeKind::Generalization,
        EdgeKind::Realization,
        EdgeKind::Association,
        EdgeKind::Aggregation,
        EdgeKind::Composition,
        EdgeKind::Transition,
        EdgeKind::Connection,
        EdgeKind::Binding,
    ];

    /// Its name in the protocol: `generalization`, `transition`, …
    pub fn name(self) -> &'static str {
        match self {
            EdgeKind::Generalization => "generalization",
            EdgeKind::Realization => "realization",
            EdgeKind::Association => "association",
            EdgeKind::Aggregation => "aggregation",
            EdgeKind::Composition => "composition",
            EdgeKind::Transition => "transition",
            EdgeKind::Connection => "connection",
            EdgeKind::Binding => "binding",
        }
    }

    pub fn from_name(name: &str) -> Option<EdgeKind> {
        EdgeKind::ALL.into_iter().find(|k| k.name() == name)
    }
}

/// Where an edge starts or ends: a node, and for connections and bindings one of its ports.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct EdgeEnd {
    /// The node's id: a node of the graph, or (for an edge to something that does not exist) a
    /// name no node has.
    pub node: String,
    /// The port's id, for connections and bindings.
    pub port: Option<String>,
}

impl EdgeEnd {
    fn node(id: impl Into<String>) -> EdgeEnd {
        EdgeEnd { node: id.into(), port: None }
    }

    /// The port's id if the end is a port, else the node's.
    pub fn id(&self) -> &str {
        self.port.as_deref().unwrap_or(&self.node)
    }
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphEdge {
    pub id: String,
    pub kind: EdgeKind,
    pub source: EdgeEnd,
    pub target: EdgeEnd,
    /// `[guard]`, `(args)`, a connection's name, an association's role.
    pub label: Option<String>,
    /// Multiplicity at the source and target end.
    pub source_label: Option<String>,
    pub target_label: Option<String>,
    /// The text that states it: a transition, an association, a connection, a binding, the
    /// type an `extends` or `implements` clause names.
    pub range: TextRange,
}

/// A swimlane.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct GraphGroup {
    pub id: String,
    pub label: String,
    pub owner: Option<String>,
}

/// One diagram's graph.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Graph {
    /// The diagram's fully qualified name.
    pub id: String,
    pub kind: GraphKind,
    /// The diagram's declaration, and its name in it.
    pub range: TextRange,
    pub name_range: Option<TextRange>,
    pub nodes: Vec<GraphNode>,
    pub edges: Vec<GraphEdge>,
    pub groups: Vec<GraphGroup>,
    /// An activity diagram's parameters, as written (`int kernelSize`).
    pub parameters: Vec<String>,
    /// The class an activity diagram belongs to (its `owner`), as written.
    pub owner: Option<String>,
    /// An activity diagram's variable section: each variable as written, without its `;`.
    pub variables: Vec<String>,
}

impl Graph {
    /// The empty graph of the diagram `syntax` declares.
    fn new(id: String, kind: GraphKind, syntax: &crate::syntax::SyntaxNode) -> Graph {
        let name_range = ast::support::child::<ast::Name>(syntax).map(|name| name.syntax().text_range());
        Graph {
            id,
            kind,
            range: syntax.text_range(),
            name_range,
            nodes: Vec::new(),
            edges: Vec::new(),
            groups: Vec::new(),
            parameters: Vec::new(),
            owner: None,
            variables: Vec::new(),
        }
    }
}

/// The graphs of every diagram of a file (nested diagrams included, each its own graph).
#[salsa::tracked(returns(ref))]
pub fn file_graphs(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Graph> {
    let root = parse(db, file).syntax_node();
    let sema = Semantics::new(db, workspace);
    root.descendants()
        .filter_map(ast::Diagram::cast)
        .filter_map(|diagram| {
            let id = Scope::at(diagram.syntax()).namespaces.last()?.clone();
            Some(match &diagram {
                ast::Diagram::ClassDiagram(d) => class::graph(&sema, id, d),
                ast::Diagram::ActivityDiagram(d) => activity::graph(id, d),
                ast::Diagram::ComponentDiagram(d) => components::component_graph(&sema, id, d),
                ast::Diagram::ComponentInstanceDiagram(d) => components::instance_graph(id, d),
            })
        })
        .collect()
}

/// A node's text on one line.
pub(super) fn text(node: &impl AstNode) -> String {
    syntax_text(node.syntax())
}

/// A syntax node's text on one line, without its comments.
pub(super) fn syntax_text(node: &crate::syntax::SyntaxNode) -> String {
    use crate::syntax::SyntaxKind::{BLOCK_COMMENT, LINE_COMMENT};
    let mut out = String::new();
    for token in node.descendants_with_tokens().filter_map(|e| e.into_token()) {
        match token.kind() {
            LINE_COMMENT | BLOCK_COMMENT => out.push(' '),
            _ => out.push_str(token.text()),
        }
    }
    out.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// An attribute as UML writes one: `+ name : type = initial`, and `{readOnly}` for a constant;
/// a reference's type is `ref type`.
pub(super) fn attribute_line(
    visibility: &str,
    name: &str,
    ty: Option<ast::TypeRef>,
    is_ref: bool,
    initial: Option<ast::Expr>,
    read_only: bool,
) -> String {
    let mut line = format!("{visibility}{name} : {}", type_text(ty, is_ref));
    if let Some(initial) = initial {
        line.push_str(" = ");
        line.push_str(&text(&initial));
    }
    if read_only {
        line.push_str(" {readOnly}");
    }
    line
}

/// A type as written, `ref type` where a `ref` modifier (not the type itself) makes it a
/// reference.
pub(super) fn type_text(ty: Option<ast::TypeRef>, is_ref: bool) -> String {
    let written = ty.as_ref().map(text).unwrap_or_default();
    let written_ref = ty.is_some_and(|t| t.is_ref());
    if is_ref && !written_ref {
        format!("ref {written}")
    } else {
        written
    }
}

/// UML's mark of a member's visibility.
pub(super) fn visibility_mark(node: &impl HasModifiers) -> &'static str {
    match node.modifiers().and_then(|m| m.visibility()) {
        Some(ast::Visibility::Public) => "+ ",
        Some(ast::Visibility::Protected) => "# ",
        Some(ast::Visibility::Private) => "- ",
        None => "",
    }
}

/// The next id of an edge from `source` to `target`: `source->target#k`, k counting the edges
/// between the two ends so far, of any kind (an aggregation and an association between two
/// classes are `#0` and `#1`).
fn edge_id(graph: &Graph, source: &EdgeEnd, target: &EdgeEnd) -> String {
    let k = graph.edges.iter().filter(|e| e.source.id() == source.id() && e.target.id() == target.id()).count();
    format!("{}->{}#{k}", source.id(), target.id())
}
