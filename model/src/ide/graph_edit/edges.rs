//! `connect`, `reconnect` and the removal of edges: a transition in its source node's body, a
//! generalization or realization in its class's `extends` or `implements` clause, an
//! association among its class's members, a connection in its source component, a binding in
//! its source instance.

use super::{
    create::insert_into_instance,
    has_properties, name_of,
    place::{self, At, Body, Edit},
    valid_name, Ctx, Element, Properties,
};
use crate::{
    graph::{EdgeKind, GraphEdge, GraphNode, GraphPort, NodeShape},
    hir::DefKind,
    syntax::{SyntaxKind::*, SyntaxNode},
};

pub(super) fn connect(
    ctx: &Ctx,
    kind: EdgeKind,
    source: &str,
    target: &str,
    properties: &Properties,
) -> Result<Vec<Edit>, String> {
    let known = match kind {
        EdgeKind::Transition => &["guard", "arguments"][..],
        EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition => {
            &["name", "sourceMultiplicity", "targetMultiplicity"]
        }
        EdgeKind::Connection | EdgeKind::Binding => &["name"],
        EdgeKind::Generalization | EdgeKind::Realization => &[],
    };
    has_properties(&format!("a {}", kind.name()), properties.keys().map(String::as_str), known)?;
    let prop = |key: &str| properties.get(key).map(String::as_str);
    match kind {
        EdgeKind::Transition => {
            let (from, to) = (activity_node(ctx, source)?, activity_node(ctx, target)?);
            if from.shape == NodeShape::Final {
                return Err(format!("`{source}` is a final node: no transition leaves it"));
            }
            let guard = prop("guard").map(|g| format!("[{g}] ")).unwrap_or_default();
            let arguments = prop("arguments").map(|a| format!("({a})")).unwrap_or_default();
            let text = format!("{guard}=> {}{arguments};", node_name(to));
            Ok(vec![into_body(&ctx.declaration(from)?, &text)?])
        }
        EdgeKind::Generalization | EdgeKind::Realization => supertype(ctx, kind, source, target),
        EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition => {
            let from = ctx.node(source)?;
            if !matches!(from.shape, NodeShape::Class | NodeShape::Interface | NodeShape::Attribute) {
                return Err(format!("`{source}` has no members: an association starts at a class"));
            }
            let class = ctx.declaration(from)?;
            let written = ctx.written_type(&class, &type_named(ctx, target)?);
            let role = match prop("name") {
                Some(name) => {
                    valid_name(name)?;
                    name.to_string()
                }
                None => free_role(&class, &written),
            };
            let keyword = match kind {
                EdgeKind::Aggregation => "aggregation ",
                EdgeKind::Composition => "composition ",
                _ => "",
            };
            // `self [t] role : Type;` states the target's end alone; `self [s] role : Type [t];`
            // both ends.
            let source = prop("sourceMultiplicity").map(multiplicity).transpose()?;
            let target = prop("targetMultiplicity").map(multiplicity).transpose()?;
            let (before_role, after_type) = match (source, target) {
                (Some(s), Some(t)) => (format!("[{s}] "), format!(" [{t}]")),
                (None, Some(t)) => (format!("[{t}] "), String::new()),
                (None, None) => (String::new(), String::new()),
                (Some(_), None) => {
                    return Err("an association's source multiplicity needs its target multiplicity beside it (a lone multiplicity is the target's)".to_string())
                }
            };
            let text = format!("self {keyword}{before_role}{role} : {written}{after_type};");
            Ok(vec![into_body(&class, &text)?])
        }
        EdgeKind::Connection | EdgeKind::Binding => {
            let shape = if kind == EdgeKind::Connection { NodeShape::Component } else { NodeShape::Instance };
            let (from, from_port) = port_of(ctx, source, shape)?;
            let (to, to_port) = port_of(ctx, target, shape)?;
            let name = prop("name").map(|n| valid_name(n).map(|_| format!("{n} "))).transpose()?.unwrap_or_default();
            let declaration = ctx.declaration(from)?;
            let text = format!(
                "[{name}source {} ==> target {}]",
                port_path(kind, from, from_port, from),
                port_path(kind, from, to_port, to)
            );
            if kind == EdgeKind::Binding {
                return Ok(vec![insert_into_instance(&declaration, &text, true)?]);
            }
            Ok(vec![into_body(&declaration, &text)?])
        }
    }
}

/// The edits that remove an edge's text.
pub(super) fn remove(ctx: &Ctx, edge: &GraphEdge) -> Result<Vec<Edit>, String> {
    let syntax = ctx.syntax(edge.range).ok_or_else(|| format!("`{}` is stated in another diagram", edge.id))?;
    if matches!(edge.kind, EdgeKind::Generalization | EdgeKind::Realization) {
        let edit = place::delete_from_list(&syntax).or_else(|| place::delete_clause(&syntax.parent()?));
        return Ok(vec![edit.ok_or("the clause is incomplete")?]);
    }
    Ok(vec![place::delete_declaration(&syntax)?])
}

pub(super) fn reconnect(ctx: &Ctx, id: &str, source: Option<&str>, target: Option<&str>) -> Result<Vec<Edit>, String> {
    let Some(Element::Edge(edge)) = ctx.element(id) else {
        return Err(format!("`{}` has no edge `{id}`", ctx.graph().id));
    };
    let source = source.filter(|s| *s != edge.source.id());
    let target = target.filter(|t| *t != edge.target.id());
    if source.is_none() && target.is_none() {
        return Err("the edge already joins these ends: give a new `source` or `target`".into());
    }
    let syntax = ctx.syntax(edge.range).ok_or_else(|| format!("`{id}` is stated in another diagram"))?;
    match edge.kind {
        EdgeKind::Transition | EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition => {
            // The target is written in the edge's text; the source is the node the text is in.
            let is_transition = edge.kind == EdgeKind::Transition;
            let mut text = syntax.text().to_string();
            let mut retarget = None;
            if let Some(target) = target {
                let (written, part) = if is_transition {
                    (
                        node_name(activity_node(ctx, target)?).to_string(),
                        syntax.children().find(|c| c.kind() == NAME_REF),
                    )
                } else {
                    let class = ctx.declaration(ctx.node(edge.source.id())?)?;
                    (
                        ctx.written_type(&class, &type_named(ctx, target)?),
                        syntax.children().find(|c| c.kind() == TYPE_REF),
                    )
                };
                let part = part.ok_or("the edge's target is not written")?.text_range();
                let local = part - syntax.text_range().start();
                text.replace_range(std::ops::Range::<usize>::from(local), &written);
                retarget = Some((part, written));
            }
            let Some(source) = source else {
                let (range, written) = retarget.expect("a new target");
                return Ok(vec![(range, written)]);
            };
            let from = if is_transition { activity_node(ctx, source)? } else { ctx.node(source)? };
            if is_transition && from.shape == NodeShape::Final {
                return Err(format!("`{source}` is a final node: no transition leaves it"));
            }
            Ok(vec![place::delete_declaration(&syntax)?, into_body(&ctx.declaration(from)?, &text)?])
        }
        EdgeKind::Generalization | EdgeKind::Realization => {
            let Some(source) = source else {
                let class = ctx.declaration(ctx.node(edge.source.id())?)?;
                let written = ctx.written_type(&class, &type_named(ctx, target.expect("a new target"))?);
                return Ok(vec![(syntax.text_range(), written)]);
            };
            let mut edits = remove(ctx, edge)?;
            edits.extend(supertype(ctx, edge.kind, source, target.unwrap_or(edge.target.id()))?);
            Ok(edits)
        }
        EdgeKind::Connection | EdgeKind::Binding => {
            let shape = if edge.kind == EdgeKind::Connection { NodeShape::Component } else { NodeShape::Instance };
            // A binding's short paths are relative to the instance it is written in.
            let here = syntax.parent().filter(|p| p.kind() == COMPONENT_INSTANCE).and_then(|p| name_of(&p));
            let here = here.and_then(|name| ctx.graph().nodes.iter().find(|n| n.id == name));
            let paths: Vec<SyntaxNode> = syntax.children().filter(|c| c.kind() == PATH).collect();
            let mut edits = Vec::new();
            for (k, new) in [(0, source), (1, target)] {
                let Some(new) = new else { continue };
                let (owner, port) = port_of(ctx, new, shape)?;
                let path = paths.get(k).ok_or("the edge's ends are not written")?;
                let written = match here {
                    Some(here) => port_path(edge.kind, here, port, owner),
                    None if edge.kind == EdgeKind::Binding => port.id.clone(),
                    None => port_path(edge.kind, owner, port, owner),
                };
                edits.push((path.text_range(), written));
            }
            Ok(edits)
        }
    }
}

/// A new `extends` or `implements` type, in the clause there is or a new one.
fn supertype(ctx: &Ctx, kind: EdgeKind, source: &str, target: &str) -> Result<Vec<Edit>, String> {
    let from = ctx.node(source)?;
    let (clause, keyword, single) = match (kind, from.shape) {
        (EdgeKind::Generalization, NodeShape::Class) => (EXTENDS_CLAUSE, "extends", true),
        (EdgeKind::Generalization, NodeShape::Interface) => (EXTENDS_CLAUSE, "extends", false),
        (EdgeKind::Realization, NodeShape::Class) => (IMPLEMENTS_CLAUSE, "implements", false),
        (EdgeKind::Realization, NodeShape::Interface) => {
            return Err("an interface extends interfaces: connect a generalization".into())
        }
        _ => return Err(format!("`{source}` has no supertypes: only classes and interfaces do")),
    };
    let class = ctx.declaration(from)?;
    let written = ctx.written_type(&class, &type_named(ctx, target)?);
    if let Some(existing) = class.children().find(|c| c.kind() == clause) {
        if let Some(last) = existing.children().filter(|c| c.kind() == TYPE_REF).last() {
            if single {
                return Err(format!(
                    "`{source}` already extends `{}`: a class extends one class (reconnect that generalization)",
                    last.text()
                ));
            }
            return Ok(vec![place::append(&last, &format!(", {written}"))]);
        }
        return Ok(vec![place::append(&existing, &format!(" {written}"))]);
    }
    let anchors: &[_] =
        if clause == IMPLEMENTS_CLAUSE { &[EXTENDS_CLAUSE, TEMPLATE_PARAMS, NAME] } else { &[TEMPLATE_PARAMS, NAME] };
    let anchor =
        anchors.iter().find_map(|k| class.children().find(|c| c.kind() == *k)).ok_or("the declaration has no name")?;
    Ok(vec![place::append(&anchor, &format!(" {keyword} {written}"))])
}

/// A new item at the end of a declaration's body.
fn into_body(declaration: &SyntaxNode, text: &str) -> Result<Edit, String> {
    let body = Body::of(declaration)
        .ok_or_else(|| format!("`{}` has no body to write it in", name_of(declaration).unwrap_or_default()))?;
    Ok(place::insert(&body, At::End, text))
}

fn activity_node<'g>(ctx: &Ctx<'g>, id: &str) -> Result<&'g GraphNode, String> {
    match ctx.element(id) {
        Some(Element::Node(node)) if !node.range.is_empty() => Ok(node),
        _ => Err(format!("a transition joins nodes of one activity diagram: `{}` has no node `{id}`", ctx.graph().id)),
    }
}

/// An activity node's name (its id's last segment).
fn node_name(node: &GraphNode) -> &str {
    node.id.rsplit('/').next().unwrap_or(&node.id)
}

/// The fully qualified name of the type `id` names: a node of the graph or any type.
fn type_named(ctx: &Ctx, id: &str) -> Result<String, String> {
    if let Ok(node) = ctx.node(id) {
        return Ok(node.id.clone());
    }
    match ctx.sema().definition(id) {
        Some(d) if matches!(d.kind, DefKind::Type(_)) => Ok(d.fqn.clone()),
        _ => Err(format!("`{id}` is no type of the workspace")),
    }
}

/// The port `id` names and its node, which must be drawn as `shape`.
fn port_of<'g>(ctx: &Ctx<'g>, id: &str, shape: NodeShape) -> Result<(&'g GraphNode, &'g GraphPort), String> {
    match ctx.element(id) {
        Some(Element::Port { owner, port }) if owner.shape == shape => Ok((owner, port)),
        _ => Err(format!(
            "a {} joins ports of `{}`: `{id}` is none of its ports",
            if shape == NodeShape::Component { "connection" } else { "binding" },
            ctx.graph().id
        )),
    }
}

/// How an edge written in `here` names `port` of `owner`: `port.connector` in a component
/// diagram (they are the diagram's), and in an instance's own binding; else `instance.port.connector`.
fn port_path(kind: EdgeKind, here: &GraphNode, port: &GraphPort, owner: &GraphNode) -> String {
    if kind == EdgeKind::Connection || here.id == owner.id {
        port.id[owner.id.len() + 1..].to_string()
    } else {
        port.id.clone()
    }
}

/// `pixel` for `Pixel`, numbered if the class has a member of that name.
fn free_role(class: &SyntaxNode, written: &str) -> String {
    let simple = written.rsplit('.').next().unwrap_or(written);
    let mut chars = simple.chars();
    let base = chars.next().map(|c| c.to_ascii_lowercase().to_string() + chars.as_str()).unwrap_or_default();
    let taken: Vec<String> = class.descendants().filter(|n| n.kind() == NAME).map(|n| n.text().to_string()).collect();
    (1..)
        .map(|k| if k == 1 { base.clone() } else { format!("{base}{k}") })
        .find(|r| !taken.contains(r))
        .expect("a free name")
}

/// `0..*` as the formatter writes a multiplicity's bounds: `0 .. *`.
pub(super) fn multiplicity(value: &str) -> Result<String, String> {
    let value = value.trim().trim_start_matches('[').trim_end_matches(']');
    let bound = |b: &str| {
        let b = b.trim();
        (b == "*" || (!b.is_empty() && b.chars().all(|c| c.is_ascii_digit())))
            .then(|| b.to_string())
            .ok_or_else(|| format!("`{value}` is no multiplicity (a bound, or two: `1`, `0..*`)"))
    };
    match value.split_once("..") {
        Some((low, high)) => Ok(format!("{} .. {}", bound(low)?, bound(high)?)),
        None => bound(value),
    }
}
