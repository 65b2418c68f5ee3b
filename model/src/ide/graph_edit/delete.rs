//! `delete`: an element's text and what would dangle without it (the transitions to a deleted
//! node, the connections of a deleted port, the generalizations to a deleted class).

use super::{
    edges,
    place::{self, Edit},
    Ctx, Element,
};
use crate::{
    graph::EdgeEnd,
    syntax::{SyntaxKind::*, TextRange},
};

pub(super) fn delete(ctx: &Ctx, id: &str) -> Result<Vec<Edit>, String> {
    Ok(merged(ctx, delete_all(ctx, id)?))
}

fn delete_all(ctx: &Ctx, id: &str) -> Result<Vec<Edit>, String> {
    let Some(element) = ctx.element(id) else {
        return Err(format!("`{}` has no element `{id}`", ctx.graph().id));
    };
    match element {
        Element::Node(node) => {
            let declaration = ctx.declaration(node)?;
            let mut edits = vec![place::delete_declaration(&declaration)?];
            edits.extend(dangling(ctx, declaration.text_range(), |end| end.node == node.id)?);
            Ok(edits)
        }
        Element::Group(group) => {
            let lane = ctx.swimlane(group).ok_or_else(|| format!("`{id}` is declared in another diagram"))?;
            let inside: Vec<&str> = ctx
                .graph()
                .nodes
                .iter()
                .filter(|n| n.group.as_ref() == Some(&group.id))
                .map(|n| n.id.as_str())
                .collect();
            let mut edits = vec![place::delete_declaration(&lane)?];
            edits.extend(dangling(ctx, lane.text_range(), |end| inside.contains(&end.node.as_str()))?);
            Ok(edits)
        }
        Element::Member { owner, name } => {
            let declaration = ctx.declaration(owner)?;
            let member = ctx.member(&declaration, &name).ok_or_else(|| format!("`{id}` is not found in the text"))?;
            Ok(vec![match member.kind() {
                FIELD | METHOD => place::delete_declaration(&member)?,
                _ => match place::delete_from_list(&member) {
                    Some(edit) => edit,
                    // The only value: `{ Red }` → `{ }`, `(width = 1)` → `()`.
                    None => {
                        let list = member.parent().expect("a value is in a list");
                        let open = list.first_token().expect("a list has tokens").text_range().end();
                        let close = list.last_token().expect("a list has tokens").text_range().start();
                        let inside = if member.kind() == ENUM_VALUE { " " } else { "" };
                        (TextRange::new(open, close), inside.to_string())
                    }
                },
            }])
        }
        Element::Port { owner, port } => {
            let (port_syntax, connector) = ctx.port(owner, port)?;
            // A port's last connector goes with its port (a port has at least one).
            let (edit, removed) = match place::delete_from_list(&connector) {
                Some(edit) => (edit, connector.text_range()),
                None => (place::delete_declaration(&port_syntax)?, port_syntax.text_range()),
            };
            let port_id = port.id.as_str();
            let mut edits = vec![edit];
            edits.extend(dangling(ctx, removed, |end| end.port.as_deref() == Some(port_id))?);
            Ok(edits)
        }
        Element::Edge(edge) => edges::remove(ctx, edge),
    }
}

/// Deletions that overlap (a port and the connection after it each take the space between
/// them) as one; and one that leaves its body with nothing but whitespace closes it, as
/// deleting a body's last item does.
fn merged(ctx: &Ctx, mut edits: Vec<Edit>) -> Vec<Edit> {
    edits.sort_by_key(|(range, _)| range.start());
    let mut out: Vec<Edit> = Vec::new();
    for (range, text) in edits {
        match out.last_mut() {
            Some((last, last_text)) if range.start() < last.end() => {
                *last = last.cover(range);
                if last_text.is_empty() {
                    *last_text = text;
                }
            }
            _ => out.push((range, text)),
        }
    }
    for edit in out.iter_mut().filter(|(_, new)| new.is_empty()) {
        if let Some(closed) = place::emptied_by(ctx.root(), ctx.text(), edit.0).and_then(|body| place::close(&body)) {
            *edit = closed;
        }
    }
    out
}

/// The edits that remove the edges with an end `gone` (declared outside `removed`, which goes).
fn dangling(ctx: &Ctx, removed: TextRange, gone: impl Fn(&EdgeEnd) -> bool) -> Result<Vec<Edit>, String> {
    let mut edits = Vec::new();
    for edge in &ctx.graph().edges {
        if (gone(&edge.source) || gone(&edge.target)) && !removed.contains_range(edge.range) {
            edits.extend(edges::remove(ctx, edge)?);
        }
    }
    Ok(edits)
}
