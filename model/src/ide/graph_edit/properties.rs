//! `setProperty`: the values an element's text holds (a transition's guard and arguments, an
//! association's role and multiplicities, a field's type and value, a node's parameters, …),
//! each read and written where it stands.

use super::{edges::multiplicity, has_properties, place::Edit, valid_name, Ctx, Element, GraphEditError};
use crate::{
    ast::support::token,
    db::{Db, SourceFile, Workspace},
    graph::EdgeKind,
    syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, TextRange, TextSize},
};

/// Where one property's value is written.
struct Slot {
    /// The value's text (inside `[…]` or `(…)`, after `=`); `None` where it has none.
    value: Option<TextRange>,
    /// Where a value is written where there is none, and how (`{}` is the value).
    insert: (TextSize, &'static str),
    /// What removing the value removes; `None` where it cannot go.
    remove: Option<TextRange>,
}

/// The current value of `property` of `element` (`None` where it has none).
pub fn property(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    diagram: &str,
    element: &str,
    property: &str,
) -> Result<Option<String>, GraphEditError> {
    let ctx = Ctx::new(db, workspace, file, diagram)?;
    let slot = slot(&ctx, element, property).map_err(GraphEditError)?;
    Ok(slot.value.map(|range| file.text(db)[range].to_string()))
}

pub(super) fn set(ctx: &Ctx, element: &str, property: &str, value: Option<&str>) -> Result<Vec<Edit>, String> {
    let slot = slot(ctx, element, property)?;
    match (property, value, slot.value) {
        ("sourceMultiplicity", Some(v), None) => return source_multiplicity(ctx, element, Some(&multiplicity(v)?)),
        ("sourceMultiplicity", None, Some(_)) => return source_multiplicity(ctx, element, None),
        _ => {}
    }
    let value = match (property, value) {
        ("sourceMultiplicity" | "targetMultiplicity", Some(v)) => Some(multiplicity(v)?),
        ("name", Some(v)) => {
            valid_name(v)?;
            Some(v.to_string())
        }
        (_, v) => v.map(str::to_string),
    };
    Ok(match (value, slot.value) {
        (Some(value), Some(range)) => vec![(range, value)],
        (Some(value), None) => vec![(TextRange::empty(slot.insert.0), slot.insert.1.replace("{}", &value))],
        (None, None) => Vec::new(),
        (None, Some(_)) => {
            vec![(slot.remove.ok_or_else(|| format!("`{property}` cannot be removed, only changed"))?, String::new())]
        }
    })
}

/// An association's role name, type and the multiplicities written before the role and after
/// the type.
struct AssociationEnds {
    name: SyntaxNode,
    ty: SyntaxNode,
    before_role: Option<SyntaxNode>,
    after_type: Option<SyntaxNode>,
}

impl AssociationEnds {
    fn of(syntax: &SyntaxNode) -> Option<AssociationEnds> {
        let (name, ty) = (child(syntax, NAME)?, child(syntax, TYPE_REF)?);
        let mut multiplicities = syntax.children().filter(|c| c.kind() == MULTIPLICITY);
        let before_role = multiplicities.clone().find(|m| m.text_range().end() <= name.text_range().start());
        let after_type = multiplicities.find(|m| m.text_range().start() >= ty.text_range().end());
        Some(AssociationEnds { name, ty, before_role, after_type })
    }
}

/// Writes (`Some`) or removes (`None`) an association's source multiplicity, moving the
/// target's with it: `self [t] role : Type;` (the target's end alone) becomes
/// `self [s] role : Type [t];` and back.
fn source_multiplicity(ctx: &Ctx, id: &str, value: Option<&str>) -> Result<Vec<Edit>, String> {
    let syntax = element_syntax(ctx, id)?;
    let ends = AssociationEnds::of(&syntax).ok_or_else(|| format!("`{id}` is incomplete"))?;
    let before = ends.before_role.as_ref().and_then(inside).ok_or_else(|| {
        format!("`{id}` has no target multiplicity: set `targetMultiplicity` first (a lone multiplicity before the role is the target's)")
    })?;
    let text = |range: TextRange| ctx.text()[range].to_string();
    Ok(match (value, &ends.after_type) {
        (Some(value), None) => {
            vec![
                (before, value.to_string()),
                (TextRange::empty(ends.ty.text_range().end()), format!(" [{}]", text(before))),
            ]
        }
        (None, Some(after)) => {
            let target = inside(after).ok_or_else(|| format!("`{id}` is incomplete"))?;
            vec![(before, text(target)), (with_space_before(after), String::new())]
        }
        _ => Vec::new(),
    })
}

fn element_syntax(ctx: &Ctx, id: &str) -> Result<SyntaxNode, String> {
    Ok(match ctx.element(id) {
        Some(Element::Node(node)) => ctx.declaration(node)?,
        Some(Element::Edge(edge)) => {
            ctx.syntax(edge.range).ok_or_else(|| format!("`{id}` is stated in another diagram"))?
        }
        Some(Element::Member { owner, name }) => {
            ctx.member(&ctx.declaration(owner)?, &name).ok_or_else(|| format!("`{id}` is not found in the text"))?
        }
        Some(_) => return Err(format!("`{id}` has no properties")),
        None => return Err(format!("`{}` has no element `{id}`", ctx.graph().id)),
    })
}

fn slot(ctx: &Ctx, id: &str, property: &str) -> Result<Slot, String> {
    let syntax = element_syntax(ctx, id)?;
    let is_association = matches!(ctx.element(id), Some(Element::Edge(e)) if matches!(e.kind, EdgeKind::Association | EdgeKind::Aggregation | EdgeKind::Composition));
    let name = child(&syntax, NAME);
    let end_of = |n: &Option<SyntaxNode>| n.as_ref().map(|n| n.text_range().end());
    let known: &[&str] = match syntax.kind() {
        TRANSITION => &["guard", "arguments"],
        ASSOCIATION if is_association => &["name", "sourceMultiplicity", "targetMultiplicity"],
        CONNECTION | BINDING => &["name"],
        FIELD => &["type", "value"],
        METHOD => &["type", "parameters"],
        ACTION_NODE | DECISION_NODE | CALC_NODE | CALC_RANGE_NODE | START_NODE | FORK_NODE | JOIN_NODE => {
            &["parameters"]
        }
        LOOP_NODE | LOOP_WINDOW_NODE => &["header"],
        COMPONENT_INSTANCE => &["component"],
        ENUM_VALUE | NAMED_ARG => &["value"],
        _ => &[],
    };
    has_properties(&format!("`{id}`"), [property], known)?;
    let missing = || format!("`{id}` is incomplete: its {property} cannot be found");
    Ok(match property {
        "guard" => {
            let guard = child(&syntax, GUARD);
            Slot {
                value: guard.as_ref().and_then(inside),
                insert: (super::place::first_token(&syntax).ok_or_else(missing)?.text_range().start(), "[{}] "),
                remove: guard.as_ref().map(with_space_after),
            }
        }
        "arguments" | "parameters" => {
            let list = child(&syntax, ARG_LIST).or_else(|| child(&syntax, PARAM_LIST));
            let after = if syntax.kind() == TRANSITION { child(&syntax, NAME_REF) } else { name.clone() };
            // A method's parameters empty to `()`; a node's go with their parentheses.
            let remove = match (&list, syntax.kind()) {
                (Some(list), METHOD) => inside(list),
                (Some(list), _) => Some(with_space_before(list)),
                (None, _) => None,
            };
            Slot {
                value: list.as_ref().and_then(inside),
                insert: (end_of(&after).ok_or_else(missing)?, "({})"),
                remove,
            }
        }
        "header" => {
            let header = child(&syntax, LOOP_HEADER).ok_or_else(missing)?;
            Slot { value: inside(&header), insert: (header.text_range().start(), "({})"), remove: None }
        }
        "name" => {
            // A connection's or binding's name is optional: `[Name source … ]`.
            let optional = syntax.kind() != ASSOCIATION;
            // Written before `source` (after `[` and the space there may be).
            let keyword = token(&syntax, L_BRACK)
                .and_then(|t| t.next_token())
                .and_then(|t| super::place::significant_from(t, true));
            let at = match (&name, keyword) {
                (Some(name), _) => name.text_range().start(),
                (None, Some(keyword)) if optional => keyword.text_range().start(),
                _ => return Err(missing()),
            };
            Slot {
                value: name.as_ref().map(|n| n.text_range()),
                insert: (at, "{} "),
                remove: name.as_ref().filter(|_| optional).map(with_space_after),
            }
        }
        "sourceMultiplicity" | "targetMultiplicity" => {
            // `self [t] role : Type;` states the target's end; `self [s] role : Type [t];` the
            // source's end before the role and the target's after the type.
            let ends = AssociationEnds::of(&syntax).ok_or_else(missing)?;
            let before_role = (ends.name.text_range().start(), "[{}] ");
            match (property, &ends.before_role, &ends.after_type) {
                ("targetMultiplicity", before, Some(after)) => Slot {
                    value: inside(after),
                    insert: (ends.ty.text_range().end(), " [{}]"),
                    // Without it the source's multiplicity would read as the target's.
                    remove: before.is_none().then(|| with_space_before(after)),
                },
                ("targetMultiplicity", before, None) | ("sourceMultiplicity", before, Some(_)) => Slot {
                    value: before.as_ref().and_then(inside),
                    insert: before_role,
                    remove: before.as_ref().map(with_space_after),
                },
                // No source end is written (`set` writes one by moving the target's after the type).
                _ => Slot { value: None, insert: before_role, remove: None },
            }
        }
        "type" => {
            let ty = child(&syntax, TYPE_REF).ok_or_else(missing)?;
            Slot { value: Some(ty.text_range()), insert: (ty.text_range().start(), "{}"), remove: None }
        }
        "value" => {
            // After `=`: a field's initial value, an enum value's, an instance's field value.
            let eq = token(&syntax, EQ);
            let value = eq.as_ref().and_then(|eq| {
                let after = syntax.children().find(|c| c.text_range().start() >= eq.text_range().end())?;
                Some(after.text_range())
            });
            let anchor = if syntax.kind() == NAMED_ARG { child(&syntax, NAME_REF) } else { name };
            let anchor = end_of(&anchor).ok_or_else(missing)?;
            let remove = value.filter(|_| syntax.kind() != NAMED_ARG).map(|v| TextRange::new(anchor, v.end()));
            Slot { value, insert: (anchor, " = {}"), remove }
        }
        "component" => {
            let path = child(&syntax, PATH).ok_or_else(missing)?;
            Slot { value: Some(path.text_range()), insert: (path.text_range().start(), "{}"), remove: None }
        }
        _ => unreachable!("checked against the known properties"),
    })
}

fn child(node: &SyntaxNode, kind: SyntaxKind) -> Option<SyntaxNode> {
    node.children().find(|c| c.kind() == kind)
}

/// The text between a bracketed node's first and last token: the guard's condition.
fn inside(node: &SyntaxNode) -> Option<TextRange> {
    let (open, close) = (node.first_token()?, node.last_token()?);
    (open != close && matches!(close.kind(), R_BRACK | R_PAREN))
        .then(|| TextRange::new(open.text_range().end(), close.text_range().start()))
}

/// `node` and the whitespace after it (`[guard] ` before `=>`).
fn with_space_after(node: &SyntaxNode) -> TextRange {
    let next = node.last_token().and_then(|t| t.next_token()).filter(|t| t.kind() == WHITESPACE);
    TextRange::new(node.text_range().start(), next.map_or(node.text_range().end(), |t| t.text_range().end()))
}

/// `node` and the whitespace before it (` [0 .. *]` after a type).
fn with_space_before(node: &SyntaxNode) -> TextRange {
    let prev = node.first_token().and_then(|t| t.prev_token()).filter(|t| t.kind() == WHITESPACE);
    TextRange::new(prev.map_or(node.text_range().start(), |t| t.text_range().start()), node.text_range().end())
}
