//! Every operation kind on every diagram of every listing (as written, and formatted): made,
//! parsed again, the graph has exactly that change, the text the formatter's style, and the
//! reverse operation gives back the text byte for byte.

use std::collections::BTreeMap;

use salsa::Setter;

use super::tests::{apply, listings, texts};
use super::*;
use crate::{
    db::RootDatabase,
    graph::{Graph, GraphEdge, GraphKind, NodeShape},
};

pub(super) struct Run {
    pub(super) db: RootDatabase,
    pub(super) ws: Workspace,
    pub(super) files: Vec<SourceFile>,
    /// Whether every file is formatted (then every edit must keep it so).
    formatted: bool,
    pub(super) made: BTreeMap<&'static str, usize>,
}

impl Run {
    pub(super) fn new(formatted: bool) -> Run {
        let db = RootDatabase::default();
        let (ws, files) = listings(&db);
        let mut run = Run { db, ws, files, formatted, made: BTreeMap::new() };
        if formatted {
            for &file in &run.files.clone() {
                if let Some(text) = crate::format::format(&crate::syntax::parse(file.text(&run.db))) {
                    file.set_text(&mut run.db).to(text);
                }
            }
        }
        run
    }

    pub(super) fn graph(&self, file: SourceFile, id: &str) -> Graph {
        file_graphs(&self.db, self.ws, file).iter().find(|g| g.id == id).cloned().expect("the diagram is still there")
    }

    /// Makes `op`, checks that only whitespace or an empty body was replaced and that the file
    /// keeps its formatting, and gives the graph after it.
    pub(super) fn make(&mut self, file: SourceFile, graph: &Graph, op: &GraphOp) -> Graph {
        let edits = match graph_edit(&self.db, self.ws, file, &graph.id, std::slice::from_ref(op)) {
            Ok(edits) => edits,
            Err(refused) => panic!("{}: {op:?}: {}", file.path(&self.db), refused.0),
        };
        assert!(!edits.is_empty(), "{op:?} made no edit");
        // A one-line body holding only a comment (`{ /*some code*/ }`, Listing 13) gets a new
        // item beside the comment, so that deleting it gives the line back; the formatter would
        // break the body's lines.
        let beside_a_comment = edits.iter().any(|(r, t)| {
            let text = file.text(&self.db);
            t.starts_with(' ') && text[..usize::from(r.range.start())].ends_with("*/")
                || t.ends_with(' ') && text[usize::from(r.range.end())..].starts_with("/*")
        });
        apply(&mut self.db, &self.files, &edits);
        if self.formatted && !beside_a_comment {
            let text = file.text(&self.db).clone();
            let formatted = crate::format::format(&crate::syntax::parse(&text));
            assert_eq!(formatted.as_deref(), Some(text.as_str()), "{op:?} left {}'s formatting", file.path(&self.db));
        }
        self.graph(file, &graph.id)
    }

    /// Makes `op`, checks the graph with `check`, makes `undo(new graph)` and checks the text
    /// is back as it was.
    pub(super) fn round_trip(
        &mut self,
        file: SourceFile,
        graph: &Graph,
        name: &'static str,
        op: GraphOp,
        check: impl Fn(&Graph),
        undo: impl Fn(&Graph) -> Vec<GraphOp>,
    ) {
        let before = texts(&self.db, &self.files);
        let after = self.make(file, graph, &op);
        check(&after);
        for back in undo(&after) {
            let now = self.graph(file, &graph.id);
            self.make(file, &now, &back);
        }
        let path = file.path(&self.db).clone();
        let mut now = texts(&self.db, &self.files);
        let mut before = before;
        if !self.formatted {
            // A body emptied again closes as the formatter writes it: `class A{}` comes back `class A { }`.
            for text in before.iter_mut().chain(now.iter_mut()) {
                *text = empty_bodies_as_formatted(text);
            }
        }
        if let Some((a, b)) = before.iter().zip(&now).find(|(a, b)| a != b) {
            let at = a.bytes().zip(b.bytes()).position(|(x, y)| x != y).unwrap_or(a.len().min(b.len()));
            let show = |t: &str| t[at.saturating_sub(60)..(at + 60).min(t.len())].to_string();
            panic!("{path}: undoing {op:?} did not give the text back:\n{}\n----- now -----\n{}", show(a), show(b));
        }
        *self.made.entry(name).or_default() += 1;
    }

    /// Makes `op` and checks the graph with `check`, then puts the text back.
    pub(super) fn once(
        &mut self,
        file: SourceFile,
        graph: &Graph,
        name: &'static str,
        op: GraphOp,
        check: impl Fn(&Graph),
    ) {
        let before = file.text(&self.db).clone();
        let after = self.make(file, graph, &op);
        check(&after);
        file.set_text(&mut self.db).to(before);
        *self.made.entry(name).or_default() += 1;
    }
}

/// `{}`, `{\n}` and ` {  }` as ` { }`.
fn empty_bodies_as_formatted(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(open) = rest.find('{') {
        if let Some(after) = rest[open + 1..].trim_start().strip_prefix('}') {
            out.push_str(rest[..open].trim_end());
            out.push_str(" { }");
            rest = after;
        } else {
            out.push_str(&rest[..=open]);
            rest = &rest[open + 1..];
        }
    }
    out.push_str(rest);
    out
}

pub(super) fn ids(graph: &Graph) -> Vec<String> {
    let mut ids: Vec<String> = graph.nodes.iter().map(|n| n.id.clone()).collect();
    ids.extend(graph.nodes.iter().flat_map(|n| n.ports.iter().map(|p| p.id.clone())));
    ids.extend(graph.nodes.iter().flat_map(|n| n.compartments.iter().flat_map(|c| c.ids.clone())));
    ids.retain(|id| !id.is_empty());
    ids.sort();
    ids
}

pub(super) fn edge_ends(graph: &Graph) -> Vec<String> {
    let mut ends: Vec<String> =
        graph.edges.iter().map(|e| format!("{:?} {} {}", e.kind, e.source.id(), e.target.id())).collect();
    ends.sort();
    ends
}

pub(super) fn props(pairs: &[(&str, &str)]) -> Properties {
    pairs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect()
}

fn create(kind: NewKind, name: &str, parent: Option<&str>, properties: Properties) -> GraphOp {
    GraphOp::Create { kind, name: name.into(), parent: parent.map(str::to_string), properties }
}

/// The creations that fit `graph`, each with the id of what it creates.
fn creations(run: &Run, file: SourceFile, graph: &Graph) -> Vec<(&'static str, GraphOp, String)> {
    let mut out = Vec::new();
    let declared = |shape: NodeShape| graph.nodes.iter().find(|n| n.shape == shape && !n.range.is_empty());
    match graph.kind {
        GraphKind::Class => {
            for kind in [NewKind::Class, NewKind::Interface, NewKind::Enum] {
                out.push((
                    kind.name(),
                    create(kind, "Created", None, Properties::new()),
                    format!("{}.Created", graph.id),
                ));
            }
            if let Some(class) = declared(NodeShape::Class) {
                let field =
                    create(NewKind::Field, "created", Some(&class.id), props(&[("type", "float"), ("value", "1.0f")]));
                out.push(("field", field, format!("{}.created", class.id)));
                let method = create(NewKind::Method, "create", Some(&class.id), props(&[("parameters", "int n")]));
                out.push(("method", method, format!("{}.create()", class.id)));
            }
            if let Some(e) = declared(NodeShape::Enum) {
                out.push((
                    "value",
                    create(NewKind::Value, "Created", Some(&e.id), Properties::new()),
                    format!("{}.Created", e.id),
                ));
            }
        }
        GraphKind::Activity => {
            let lanes = std::iter::once(None).chain(graph.groups.iter().take(1).map(|g| Some(g.id.clone())));
            for lane in lanes {
                for (kind, name) in NewKind::all().filter(|(k, _)| k.is_activity_node()) {
                    let id = format!("{}/created", lane.as_deref().unwrap_or(&graph.id));
                    out.push((name, create(kind, "created", lane.as_deref(), Properties::new()), id));
                }
            }
        }
        GraphKind::Component => {
            out.push(("component", create(NewKind::Component, "Created", None, Properties::new()), "Created".into()));
            if let Some(component) = declared(NodeShape::Component) {
                let p = props(&[("connector", "Out"), ("interface", "ICreated"), ("role", "provider")]);
                let port = create(NewKind::Port, "CreatedPort", Some(&component.id), p);
                out.push(("port", port, format!("{}.CreatedPort.Out", component.id)));
                if let Some(first) = component.ports.first() {
                    let p = props(&[("interface", "ICreated"), ("role", "processor")]);
                    let connector = create(NewKind::Connector, "CreatedIn", Some(&first.id), p);
                    let port = first.id.rsplit_once('.').unwrap().0;
                    out.push(("connector", connector, format!("{port}.CreatedIn")));
                }
            }
        }
        GraphKind::ComponentInstance => {
            let p = props(&[("component", "Created")]);
            out.push(("instance", create(NewKind::Instance, "created", None, p), "created".into()));
            // A port instance of every port of the first instance's component it does not use yet.
            let sema = Semantics::new(&run.db, run.ws);
            for instance in graph.nodes.iter().filter(|n| n.shape == NodeShape::Instance).take(1) {
                let root = parse(&run.db, file).syntax_node();
                let syntax = root.covering_element(instance.range).into_node().unwrap();
                let path = syntax.children().find(|c| c.kind() == PATH).unwrap().text().to_string();
                let fqn = sema.resolve(&Scope::at(&syntax), &path).map(|d| d.fqn.clone()).unwrap_or_default();
                for port in sema.components(&fqn).iter().flat_map(|c| &c.item.ports).take(2) {
                    let p = props(&[("port", &port.name)]);
                    let name = format!("Created{}", port.name);
                    let id = format!("{}.{name}.", instance.id);
                    out.push(("portInstance", create(NewKind::PortInstance, &name, Some(&instance.id), p), id));
                }
            }
        }
    }
    out
}

#[test]
fn every_creation_on_every_listing_makes_exactly_it_and_undoes() {
    for formatted in [false, true] {
        let mut run = Run::new(formatted);
        for file in run.files.clone() {
            for graph in file_graphs(&run.db, run.ws, file).clone() {
                for (name, op, id) in creations(&run, file, &graph) {
                    let old = ids(&graph);
                    let old_edges = edge_ends(&graph);
                    let (check_id, check_path) = (id.clone(), file.path(&run.db).clone());
                    let check = move |after: &Graph| {
                        let new: Vec<String> = ids(after).into_iter().filter(|i| !old.contains(i)).collect();
                        assert!(
                            !new.is_empty() && new.iter().all(|i| i.starts_with(&check_id)),
                            "{check_path}: creating {check_id} gave the new ids {new:?}"
                        );
                        assert!(old.iter().all(|i| ids(after).contains(i)), "{check_path}: {check_id}: an id went");
                        assert_eq!(edge_ends(after), old_edges, "{check_path}: {check_id}: the edges changed");
                    };
                    let undo = move |after: &Graph| -> Vec<GraphOp> {
                        ids(after)
                            .into_iter()
                            .filter(|i| i.starts_with(&id) && (i == &id || id.ends_with('.')))
                            .map(|element| GraphOp::Delete { element })
                            .collect()
                    };
                    run.round_trip(file, &graph, name, op, check, undo);
                }
            }
        }
        for (kind, name) in NewKind::all() {
            assert!(run.made.get(name).is_some_and(|&n| n > 0), "no {kind:?} was created (formatted: {formatted})");
        }
    }
}

#[test]
fn deleting_any_element_of_any_listing_removes_it_and_what_dangles() {
    let mut run = Run::new(false);
    for file in run.files.clone() {
        for graph in file_graphs(&run.db, run.ws, file).clone() {
            let path = file.path(&run.db).clone();
            let elements: Vec<String> = ids(&graph)
                .into_iter()
                .filter(|id| graph.nodes.iter().all(|n| n.id != *id || !n.range.is_empty()))
                .chain(graph.edges.iter().map(|e| e.id.clone()))
                .collect();
            for element in elements {
                let (old, old_edges) = (ids(&graph), edge_ends(&graph));
                let edge = graph.edges.iter().find(|e| e.id == element).cloned();
                // What may go with a node: what is in it (nested components, members, ports) and
                // the types of other diagrams only its edges reached.
                let range = graph.nodes.iter().find(|n| n.id == element).map(|n| n.range);
                let may_go: Vec<String> = graph
                    .nodes
                    .iter()
                    .filter(|n| n.range.is_empty() || range.is_some_and(|r| r.contains_range(n.range)))
                    .map(|n| n.id.clone())
                    .chain([element.clone()])
                    .collect();
                // The types of other diagrams (drawn without a range here) that no other edge reaches.
                let may_go_with_edge: Vec<String> = edge
                    .iter()
                    .flat_map(|e| [e.source.id().to_string(), e.target.id().to_string()])
                    .filter(|id| graph.nodes.iter().any(|n| n.id == *id && n.range.is_empty()))
                    .filter(|id| {
                        let reaches = |e: &&GraphEdge| e.source.id() == id.as_str() || e.target.id() == id.as_str();
                        graph.edges.iter().filter(reaches).count() == 1
                    })
                    .collect();
                let under = |id: &str, of: &str| id == of || id.starts_with(&format!("{of}."));
                let (path, element_id) = (path.clone(), element.clone());
                let check = move |after: &Graph| {
                    let gone: Vec<&String> = old.iter().filter(|i| !ids(after).contains(i)).collect();
                    let edges = edge_ends(after);
                    if let Some(edge) = &edge {
                        // Only a type of another diagram that this edge alone reached may go.
                        let ends = [edge.source.id(), edge.target.id()];
                        let only_reached = |id: &&String| may_go_with_edge.contains(*id) && ends.contains(&id.as_str());
                        assert!(gone.iter().all(only_reached), "{path}: deleting the edge {element_id} took {gone:?}");
                        let mut expected = old_edges.clone();
                        let this = format!("{:?} {} {}", edge.kind, edge.source.id(), edge.target.id());
                        expected.remove(expected.iter().position(|e| *e == this).unwrap());
                        assert_eq!(edges, expected, "{path}: deleting {element_id}");
                        return;
                    }
                    assert!(gone.contains(&&element_id), "{path}: {element_id} is still there");
                    for g in gone {
                        assert!(may_go.iter().any(|m| under(g, m)), "{path}: deleting {element_id} took {g}");
                    }
                    for e in &edges {
                        assert!(old_edges.contains(e), "{path}: deleting {element_id} made the edge {e}");
                        let dangles = e.split(' ').skip(1).any(|end| under(end, &element_id));
                        assert!(!dangles, "{path}: deleting {element_id} left the edge {e}");
                    }
                };
                run.once(file, &graph, "delete", GraphOp::Delete { element }, check);
            }
        }
    }
    assert!(run.made["delete"] > 300, "{} elements deleted", run.made["delete"]);
}
