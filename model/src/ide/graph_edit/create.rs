//! `create`: the declaration of a new node, member, port or connector, as the formatter writes
//! it, after its siblings in the diagram, swimlane, node container, class or component it goes
//! into.

use super::{
    has_properties, name_of,
    place::{self, At, Body, Edit, INDENT},
    valid_name, Ctx, Element, NewKind, Properties,
};
use crate::{
    ast::{self, AstNode},
    graph::{GraphKind, NodeShape},
    hir::{items::TypeKind, DefKind, Scope},
    syntax::{NodeKind, SyntaxKind::*, SyntaxNode, TextRange},
};

pub(super) fn create(
    ctx: &Ctx,
    kind: NewKind,
    name: &str,
    parent: Option<&str>,
    properties: &Properties,
) -> Result<Vec<Edit>, String> {
    let known = match kind {
        NewKind::Field => &["type", "value", "visibility"][..],
        NewKind::Method => &["type", "parameters", "visibility"],
        NewKind::Node(NodeKind::Action | NodeKind::Decision | NodeKind::Calc | NodeKind::CalcRange) => &["parameters"],
        NewKind::Node(NodeKind::Loop | NodeKind::LoopWindow) => &["header"],
        NewKind::Component => &["stereotype"],
        NewKind::Port | NewKind::Connector => &["role", "connector", "interface"],
        NewKind::Instance => &["component"],
        NewKind::PortInstance => &["port"],
        _ => &[],
    };
    has_properties(&format!("a {}", kind.name()), properties.keys().map(String::as_str), known)?;
    let prop = |key: &str| properties.get(key).map(String::as_str);
    if kind == NewKind::Component {
        name.split('.').try_for_each(valid_name)?;
    } else {
        valid_name(name)?;
    }
    let graph = ctx.graph();
    let diagram_kind = match kind {
        NewKind::Class | NewKind::Interface | NewKind::Enum | NewKind::Value | NewKind::Field | NewKind::Method => {
            GraphKind::Class
        }
        NewKind::Component | NewKind::Port | NewKind::Connector => GraphKind::Component,
        NewKind::Instance | NewKind::PortInstance => GraphKind::ComponentInstance,
        _ => GraphKind::Activity,
    };
    if graph.kind != diagram_kind {
        let (wanted, is) = (kind_name(diagram_kind), kind_name(graph.kind));
        return Err(format!("a {} goes into {wanted} diagram, `{}` is {is} diagram", kind.name(), graph.id));
    }
    // The declaration the new one goes into, when it is a node of the graph.
    let parent_node = |shapes: &[NodeShape]| -> Result<SyntaxNode, String> {
        let Some(parent) = parent else { return Err(format!("a {} needs a parent", kind.name())) };
        let node = ctx.node(parent)?;
        if !shapes.contains(&node.shape) {
            return Err(format!("a {} cannot go into `{parent}`", kind.name()));
        }
        ctx.declaration(node)
    };
    let top = || -> Result<SyntaxNode, String> {
        match parent {
            None => Ok(ctx.diagram()),
            Some(p) if p == graph.id => Ok(ctx.diagram()),
            Some(p) => Err(format!("a {} goes into the diagram itself, not into `{p}`", kind.name())),
        }
    };
    let (owner, at, text) = match kind {
        NewKind::Class => (top()?, At::End, format!("public class {name} {{ }}")),
        NewKind::Interface => (top()?, At::End, format!("public interface {name} {{ }}")),
        NewKind::Enum => (top()?, At::End, format!("public enum {name} {{ }}")),
        NewKind::Value => return new_value(&parent_node(&[NodeShape::Enum])?, name),
        NewKind::Field => {
            let class = parent_node(&[NodeShape::Class, NodeShape::Interface, NodeShape::Attribute])?;
            let visibility = prop("visibility").unwrap_or("public");
            let value = prop("value").map(|v| format!(" = {v}")).unwrap_or_default();
            let text = format!("{visibility} {} {name}{value};", prop("type").unwrap_or("int"));
            let last_field = members(&class).into_iter().filter(|m| m.kind() == FIELD).last();
            return Ok(vec![insert(&class, last_field.as_ref().map_or(At::Start, At::After), &text)?]);
        }
        NewKind::Method => {
            let class = parent_node(&[NodeShape::Class, NodeShape::Interface, NodeShape::Attribute])?;
            let visibility = prop("visibility").unwrap_or("public");
            let (ty, params) = (prop("type").unwrap_or("void"), prop("parameters").unwrap_or(""));
            (class, At::End, format!("{visibility} {ty} {name}({params});"))
        }
        NewKind::Component => {
            let owner = match parent {
                Some(p) if p != graph.id => parent_node(&[NodeShape::Component])?,
                _ => ctx.diagram(),
            };
            let stereotype = match prop("stereotype") {
                Some(s @ ("class" | "source" | "filter" | "sink")) => s.to_string(),
                Some(other) => {
                    return Err(format!("`{other}` is no component stereotype (class, source, filter, sink)"))
                }
                None => class_stereotype(ctx, &owner, name),
            };
            (owner, At::End, format!("{stereotype} {name} {{ }}"))
        }
        NewKind::Port => {
            let component = parent_node(&[NodeShape::Component])?;
            let connector = prop("connector").ok_or("a port needs its first `connector`'s name")?;
            let text = format!("port {name}({})", connector_text(connector, properties)?);
            let last_port = component.children().filter(|c| c.kind() == PORT).last();
            return Ok(vec![insert(&component, last_port.as_ref().map_or(At::Start, At::After), &text)?]);
        }
        NewKind::Connector => return new_connector(ctx, parent, name, properties),
        NewKind::Instance => {
            let component = prop("component").ok_or("an instance needs its `component`")?;
            (top()?, At::End, format!("{name} instantiates {component}();"))
        }
        NewKind::PortInstance => {
            let instance = parent_node(&[NodeShape::Instance])?;
            let port = prop("port").ok_or("a port instance needs the `port` of its component it instantiates")?;
            let text = format!("{name} : {port}({});", instance_connectors(ctx, &instance, port)?);
            return Ok(vec![insert_into_instance(&instance, &text, false)?]);
        }
        NewKind::Node(node) => (activity_owner(ctx, parent)?, At::End, activity_node(node, name, properties)),
    };
    Ok(vec![insert(&owner, at, &text)?])
}

fn kind_name(kind: GraphKind) -> &'static str {
    match kind {
        GraphKind::Class => "a class",
        GraphKind::Activity => "an activity",
        GraphKind::Component => "a component",
        GraphKind::ComponentInstance => "a component-instance",
    }
}

fn insert(owner: &SyntaxNode, at: At, text: &str) -> Result<Edit, String> {
    let body = Body::of(owner).ok_or_else(|| incomplete(owner))?;
    Ok(place::insert(&body, at, text))
}

fn incomplete(owner: &SyntaxNode) -> String {
    let name = name_of(owner).unwrap_or_else(|| owner.text().to_string().split_whitespace().take(2).collect());
    format!("the body of `{name}` is incomplete: complete its braces first")
}

/// The members of a class, interface or attribute definition.
fn members(class: &SyntaxNode) -> Vec<SyntaxNode> {
    class.children().filter(|c| c.kind() == MEMBER_LIST).flat_map(|l| l.children()).collect()
}

/// The diagram, swimlane or node container (Sec. 9.2.2.3: an action, decision, loop or
/// loopWindow node holds a flow of its own) a new activity node goes into.
fn activity_owner(ctx: &Ctx, parent: Option<&str>) -> Result<SyntaxNode, String> {
    match parent {
        None => Ok(ctx.diagram()),
        Some(p) if p == ctx.graph().id => Ok(ctx.diagram()),
        Some(p) => match ctx.element(p) {
            Some(Element::Group(group)) => {
                ctx.swimlane(group).ok_or_else(|| format!("the swimlane `{p}` is declared in another diagram"))
            }
            Some(Element::Node(node)) => {
                let declaration = ctx.declaration(node)?;
                match ast::ActivityNode::cast(declaration.clone()) {
                    Some(container) if container.may_hold_nodes() => Ok(declaration),
                    Some(other) => Err(format!(
                        "a {} node holds no nodes: only action, decision, loop and loopWindow nodes do (Sec. 9.2.2.3)",
                        other.kind().keyword()
                    )),
                    None => Err(format!("`{p}` is no activity node")),
                }
            }
            _ => Err(format!(
                "an activity node goes into the diagram, a swimlane or an action, decision, loop or loopWindow node; `{p}` is none"
            )),
        },
    }
}

/// A new activity node as the formatter writes it, with a body to write transitions in.
fn activity_node(kind: NodeKind, name: &str, properties: &Properties) -> String {
    let parameters = properties.get("parameters").map(|p| format!("({p})"));
    let header = |default: &str| format!("({})", properties.get("header").map_or(default, String::as_str));
    let keyword = kind.keyword();
    match kind {
        NodeKind::Final => format!("{keyword} {name};"),
        NodeKind::Loop => format!("{keyword} {name}{} {{ }}", header("var int i = 0; i < 1; i = i + 1")),
        NodeKind::LoopWindow => format!("{keyword} {name}{} {{ }}", header("var int u = -1; u <= 1; u = u + 1")),
        NodeKind::Calc | NodeKind::CalcRange => {
            format!("{keyword} {name}{} {{ }}", parameters.unwrap_or_else(|| "()".into()))
        }
        _ => format!("{keyword} {name}{} {{ }}", parameters.unwrap_or_default()),
    }
}

/// `source`, `filter` or `sink` as the component's class is declared, `class` otherwise.
fn class_stereotype(ctx: &Ctx, owner: &SyntaxNode, class: &str) -> String {
    let definition = ctx.sema().resolve(&Scope::at(owner), class);
    match definition.map(|d| &d.kind) {
        Some(DefKind::Type(ty)) => match &ty.kind {
            TypeKind::Class(kind) => format!("{kind:?}").to_lowercase(),
            _ => "class".into(),
        },
        _ => "class".into(),
    }
}

/// `provider Out : IImage`, from a port's or connector's properties.
fn connector_text(name: &str, properties: &Properties) -> Result<String, String> {
    valid_name(name)?;
    let role = properties.get("role").map_or("provider", String::as_str);
    if !matches!(role, "provider" | "processor") {
        return Err(format!("`{role}` is no connector role (provider, processor)"));
    }
    let interface = properties.get("interface").ok_or("a connector needs its `interface`")?;
    Ok(format!("{role} {name} : {interface}"))
}

/// A new connector, after the last of its port's.
fn new_connector(ctx: &Ctx, parent: Option<&str>, name: &str, properties: &Properties) -> Result<Vec<Edit>, String> {
    let parent = parent.ok_or("a connector needs its port as parent")?;
    // The parent is one of the port's connectors (`Component.port.connector`) or the port.
    let (owner, port_name) = ctx
        .graph()
        .nodes
        .iter()
        .filter(|n| n.shape == NodeShape::Component)
        .find_map(|n| {
            let rest = parent.strip_prefix(&n.id)?.strip_prefix('.')?;
            Some((n, rest.split('.').next()?.to_string()))
        })
        .ok_or_else(|| format!("`{parent}` is no port of a component of `{}`", ctx.graph().id))?;
    let port = ctx
        .declaration(owner)?
        .children()
        .filter(|c| c.kind() == PORT)
        .find(|p| name_of(p).as_deref() == Some(port_name.as_str()))
        .ok_or_else(|| format!("`{}` has no port `{port_name}`", owner.id))?;
    let last = port.children().filter(|c| c.kind() == CONNECTOR).last().ok_or_else(|| incomplete(&port))?;
    Ok(vec![place::append(&last, &format!(", {}", connector_text(name, properties)?))])
}

/// A new enum value, after the last.
fn new_value(enumeration: &SyntaxNode, name: &str) -> Result<Vec<Edit>, String> {
    if let Some(last) = enumeration.children().filter(|c| c.kind() == ENUM_VALUE).last() {
        return Ok(vec![place::append(&last, &format!(", {name}"))]);
    }
    let body = Body::of(enumeration).ok_or_else(|| incomplete(enumeration))?;
    let inside = TextRange::new(body.open.text_range().end(), body.close.text_range().start());
    Ok(vec![(inside, format!(" {name} "))])
}

/// `provider Out = IImage(); processor In = IImage();`: the connectors of the port `port` of the
/// instance's component, as Listing 24 writes them.
fn instance_connectors(ctx: &Ctx, instance: &SyntaxNode, port: &str) -> Result<String, String> {
    valid_name(port)?;
    let component = instance.children().find(|c| c.kind() == PATH).map(|p| p.text().to_string()).unwrap_or_default();
    let class = ctx
        .sema()
        .resolve(&Scope::at(instance), &component)
        .map(|d| d.fqn.clone())
        .ok_or_else(|| format!("the instance's component `{component}` is not found: its ports are unknown"))?;
    let declared = ctx.sema().components(&class);
    let Some(found) = declared.iter().flat_map(|c| &c.item.ports).find(|p| p.name == port) else {
        let ports: Vec<&str> = declared.iter().flat_map(|c| &c.item.ports).map(|p| p.name.as_str()).collect();
        let ports = if ports.is_empty() { "none".to_string() } else { ports.join(", ") };
        return Err(format!("`{component}` has no port `{port}` (its ports: {ports})"));
    };
    Ok(found
        .connectors
        .iter()
        .map(|c| {
            let role = format!("{:?}", c.role).to_lowercase();
            let interface = c.interface.rsplit('.').next().unwrap_or(&c.interface);
            format!("{role} {} = {interface}();", c.name)
        })
        .collect::<Vec<_>>()
        .join(" "))
}

/// A port instance (after the others) or a binding (`at_end`) into an instance, whose body may
/// be missing (`X instantiates C();`) or whose members follow it without braces (Listing 28).
pub(super) fn insert_into_instance(instance: &SyntaxNode, text: &str, at_end: bool) -> Result<Edit, String> {
    if let Some(body) = Body::of(instance) {
        if at_end {
            return Ok(place::insert(&body, At::End, text));
        }
        let last_port = body.items().into_iter().filter(|c| c.kind() == PORT_INSTANCE).last();
        return Ok(place::insert(&body, last_port.as_ref().map_or(At::Start, At::After), text));
    }
    let members: Vec<SyntaxNode> =
        instance.children().filter(|c| matches!(c.kind(), PORT_INSTANCE | BINDING)).collect();
    if let Some(first) = members.first() {
        // Listing 28's flat form: the new member joins the others, on a line of its own.
        let indent = place::indent_of(&place::first_token(first).expect("a member has tokens"));
        let after = if at_end { members.last() } else { members.iter().rev().find(|c| c.kind() == PORT_INSTANCE) };
        return Ok(match after {
            Some(member) => {
                let end = member.last_token().expect("a member has tokens").text_range().end();
                (TextRange::empty(end), format!("\n{indent}{text}"))
            }
            None => (
                TextRange::empty(place::first_token(first).expect("a member has tokens").text_range().start()),
                format!("{text}\n{indent}"),
            ),
        });
    }
    let indent = place::indent_of(&place::first_token(instance).expect("an instance has tokens"));
    let last = instance.last_token().expect("an instance has tokens");
    let range = if last.kind() == SEMICOLON { last.text_range() } else { TextRange::empty(last.text_range().end()) };
    Ok((range, format!("\n{indent}{{\n{indent}{INDENT}{text}\n{indent}}}")))
}
