//! Where graph edits put and take text, in the formatter's style: a new item goes on a line of
//! its own at its siblings' indentation (beside them where they share one line), an empty body
//! `{ }` opens as the formatter writes it, a deleted item takes its own comments and the
//! whitespace before it along, and a body left empty closes to `{ }` again. So deleting what
//! was created gives back the text as it was.

use crate::{
    ast::support::token,
    syntax::{SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange},
};

/// One replacement in the edited file.
pub(super) type Edit = (TextRange, String);

/// The formatter's indentation step.
pub(super) const INDENT: &str = "    ";

/// The braces of a declaration's body: its own, or those of its member list or node body.
#[derive(Debug, Clone)]
pub(super) struct Body {
    pub(super) open: SyntaxToken,
    pub(super) close: SyntaxToken,
    /// The declaration the body belongs to (its line gives the indentation).
    owner: SyntaxNode,
}

impl Body {
    pub(super) fn of(owner: &SyntaxNode) -> Option<Body> {
        let holder = if token(owner, L_CURLY).is_some() {
            owner.clone()
        } else {
            owner.children().find(|c| matches!(c.kind(), MEMBER_LIST | NODE_BODY))?
        };
        Some(Body { open: token(&holder, L_CURLY)?, close: token(&holder, R_CURLY)?, owner: owner.clone() })
    }

    /// The body `item` is in.
    pub(super) fn around(item: &SyntaxNode) -> Option<Body> {
        let holder = item.parent()?;
        let owner = if matches!(holder.kind(), MEMBER_LIST | NODE_BODY) { holder.parent()? } else { holder };
        Body::of(&owner)
    }

    /// What a body left empty becomes: ` { }`, but an instance ends as the file's other
    /// instances without a body do, with `;` or without (`X instantiates C();`).
    pub(super) fn emptied(&self) -> &'static str {
        if self.owner.kind() != COMPONENT_INSTANCE {
            return " { }";
        }
        let siblings = self.owner.parent().into_iter().flat_map(|p| p.children());
        let bodiless: Vec<SyntaxNode> =
            siblings.filter(|s| s.kind() == COMPONENT_INSTANCE && token(s, L_CURLY).is_none()).collect();
        if bodiless.is_empty() || bodiless.iter().any(|s| token(s, SEMICOLON).is_some()) {
            ";"
        } else {
            ""
        }
    }

    /// The body's items: the nodes between its braces.
    pub(super) fn items(&self) -> Vec<SyntaxNode> {
        let inside = TextRange::new(self.open.text_range().end(), self.close.text_range().start());
        let holder = self.open.parent().expect("a brace has a parent");
        holder.children().filter(|c| inside.contains_range(c.text_range())).collect()
    }

    fn on_one_line(&self) -> bool {
        let mut token = self.open.next_token();
        while let Some(t) = token.filter(|t| *t != self.close) {
            if t.text().contains('\n') {
                return false;
            }
            token = t.next_token();
        }
        true
    }

    /// Whether anything but whitespace is between the braces.
    fn is_empty(&self) -> bool {
        self.open.next_token().and_then(|t| significant_from(t, true)).as_ref() == Some(&self.close)
    }
}

/// Where a new item goes in a body.
pub(super) enum At<'a> {
    /// After every item (and comment) of the body.
    End,
    /// Right after this item.
    After(&'a SyntaxNode),
    /// Before every item of the body (and the comments above the first).
    Start,
}

/// The edit that puts `item` (one line of text) into `body` at `at`.
pub(super) fn insert(body: &Body, at: At, item: &str) -> Edit {
    if body.is_empty() {
        return open(body, item);
    }
    let one_line = body.on_one_line();
    let last_inside = body.close.prev_token().and_then(|t| significant_from(t, false));
    match at {
        At::Start => {
            let first = body.open.next_token().and_then(|t| significant_from(t, true)).expect("not empty");
            let first = lead_of(&first);
            let place = TextRange::empty(first.text_range().start());
            let text = if one_line { format!("{item} ") } else { format!("{item}\n{}", indent_of(&first)) };
            (place, text)
        }
        At::After(node) => after(node.last_token().expect("an item has tokens"), body, one_line, item),
        At::End => after(last_inside.expect("not empty"), body, one_line, item),
    }
}

/// A new item after the one `last` ends (or after the comment `last` is), at its indentation.
fn after(last: SyntaxToken, body: &Body, one_line: bool, item: &str) -> Edit {
    let place = TextRange::empty(tail_of(&last).text_range().end());
    if one_line {
        return (place, format!(" {item}"));
    }
    // The indentation of the line the item starts on (it may end on a continuation line).
    let holder = body.open.parent();
    let start = last.parent_ancestors().find(|n| n.parent() == holder).and_then(|n| first_token(&n)).unwrap_or(last);
    (place, format!("\n{}{item}", indent_of(&start)))
}

/// An empty body opened as the formatter writes it: the brace on a line of its own.
fn open(body: &Body, item: &str) -> Edit {
    let indent = indent_of(&first_token(&body.owner).expect("a declaration has tokens"));
    let before = body.open.prev_token().and_then(|t| significant_from(t, false)).expect("a body follows a name");
    let place = TextRange::new(before.text_range().end(), body.close.text_range().end());
    (place, format!("\n{indent}{{\n{indent}{INDENT}{item}\n{indent}}}"))
}

/// The edit that deletes `item` from its body, with its comments and the whitespace before it;
/// a body left empty becomes [`Body::emptied`].
pub(super) fn delete(item: &SyntaxNode) -> Option<Edit> {
    let Some(body) = Body::around(item) else { return delete_flat_member(item) };
    let lead = lead_of(&first_token(item)?);
    let tail = tail_of(&item.last_token().expect("an item has tokens"));
    let prev = lead.prev_token().and_then(|t| significant_from(t, false));
    let next = tail.next_token().and_then(|t| significant_from(t, true));
    let (after_open, before_close) = (prev.as_ref() == Some(&body.open), next.as_ref() == Some(&body.close));
    if after_open && before_close {
        close(&body)
    } else if after_open {
        let next = next?;
        Some((TextRange::new(lead.text_range().start(), next.text_range().start()), String::new()))
    } else {
        let from = prev.map_or(lead.text_range().start(), |p| p.text_range().end());
        Some((TextRange::new(from, tail.text_range().end()), String::new()))
    }
}

/// The edit that deletes a port instance or binding written after its instance without braces
/// (Listing 28's flat form), with its comments and the whitespace before it.
fn delete_flat_member(item: &SyntaxNode) -> Option<Edit> {
    crate::ast::ComponentInstance::of_flat_member(item)?;
    let lead = lead_of(&first_token(item)?);
    let tail = tail_of(&item.last_token()?);
    let prev = lead.prev_token().and_then(|t| significant_from(t, false))?;
    Some((TextRange::new(prev.text_range().end(), tail.text_range().end()), String::new()))
}

/// The edit that closes a body whose items all go: from the end of what precedes `{` through
/// `}`, replaced by [`Body::emptied`].
pub(super) fn close(body: &Body) -> Option<Edit> {
    let before = body.open.prev_token().and_then(|t| significant_from(t, false))?;
    Some((TextRange::new(before.text_range().end(), body.close.text_range().end()), body.emptied().to_string()))
}

/// The innermost body around `range` that holds nothing but `range` and whitespace.
pub(super) fn emptied_by(root: &SyntaxNode, text: &str, range: TextRange) -> Option<Body> {
    let start = match root.covering_element(range) {
        rowan::NodeOrToken::Node(n) => n,
        rowan::NodeOrToken::Token(t) => t.parent()?,
    };
    let body = start.ancestors().find_map(|n| {
        Body::of(&n)
            .filter(|b| b.open.text_range().end() <= range.start() && range.end() <= b.close.text_range().start())
    })?;
    let blank = |from, to| text[std::ops::Range::<usize>::from(TextRange::new(from, to))].trim().is_empty();
    (blank(body.open.text_range().end(), range.start()) && blank(range.end(), body.close.text_range().start()))
        .then_some(body)
}

/// The edit that deletes `element` from the comma- (or semicolon-) separated list it is in,
/// with one separator; `None` when it is the list's only element.
pub(super) fn delete_from_list(element: &SyntaxNode) -> Option<Edit> {
    let is_separator = |t: &SyntaxToken| matches!(t.kind(), COMMA | SEMICOLON);
    let first = first_token(element)?;
    let last = element.last_token()?;
    let next = last.next_token().and_then(|t| significant_from(t, true));
    let prev = first.prev_token().and_then(|t| significant_from(t, false));
    if let Some(separator) = next.filter(&is_separator) {
        let after = separator.next_token().and_then(|t| significant_from(t, true))?;
        if matches!(after.kind(), COMMA | SEMICOLON | R_PAREN | R_CURLY) {
            // `a; )` or `a, }`: the trailing separator stays with the list (if `a` is not alone).
            let separator = prev.filter(&is_separator)?;
            let before = separator.prev_token().and_then(|t| significant_from(t, false))?;
            return Some((TextRange::new(before.text_range().end(), last.text_range().end()), String::new()));
        }
        return Some((TextRange::new(first.text_range().start(), after.text_range().start()), String::new()));
    }
    let separator = prev.filter(&is_separator)?;
    let before = separator.prev_token().and_then(|t| significant_from(t, false))?;
    Some((TextRange::new(before.text_range().end(), last.text_range().end()), String::new()))
}

/// The edit that deletes `node` and the whitespace before it on its line (a clause: ` extends A`).
pub(super) fn delete_clause(node: &SyntaxNode) -> Option<Edit> {
    let before = node.first_token()?.prev_token().and_then(|t| significant_from(t, false))?;
    Some((TextRange::new(before.text_range().end(), node.text_range().end()), String::new()))
}

/// The edit that puts ` text` right after `node`.
pub(super) fn append(node: &SyntaxNode, text: &str) -> Edit {
    (TextRange::empty(node.text_range().end()), text.to_string())
}

/// The first token of `node` that is no comment (a node starts with the comments above it).
pub(super) fn first_token(node: &SyntaxNode) -> Option<SyntaxToken> {
    let mut current = node.first_token();
    while let Some(t) = current.clone().filter(|t| t.kind().is_trivia()) {
        if t.text_range().end() >= node.text_range().end() {
            break;
        }
        current = t.next_token();
    }
    current
}

/// The first token at or after (`forward`) or before `token` that is not whitespace.
pub(super) fn significant_from(token: SyntaxToken, forward: bool) -> Option<SyntaxToken> {
    let mut token = Some(token);
    while let Some(t) = token {
        if t.kind() != WHITESPACE {
            return Some(t);
        }
        token = if forward { t.next_token() } else { t.prev_token() };
    }
    None
}

/// The first token of what belongs to the item `token` starts: its comments on the lines
/// right above it (no blank line between).
fn lead_of(token: &SyntaxToken) -> SyntaxToken {
    let mut first = token.clone();
    loop {
        let Some(space) = first.prev_token() else { break };
        if space.kind() != WHITESPACE || space.text().matches('\n').count() != 1 {
            break;
        }
        let Some(comment) =
            space.prev_token().filter(|c| matches!(c.kind(), LINE_COMMENT | BLOCK_COMMENT) && starts_line(c))
        else {
            break;
        };
        first = comment;
    }
    first
}

/// The last token of what belongs to the item `token` ends: a `//` comment after it on its line.
fn tail_of(token: &SyntaxToken) -> SyntaxToken {
    let mut next = token.next_token();
    if next.as_ref().is_some_and(|t| t.kind() == WHITESPACE && !t.text().contains('\n')) {
        next = next.and_then(|t| t.next_token());
    }
    match next {
        Some(comment) if comment.kind() == LINE_COMMENT => comment,
        _ => token.clone(),
    }
}

fn starts_line(token: &SyntaxToken) -> bool {
    match token.prev_token() {
        None => true,
        Some(t) => t.kind() == WHITESPACE && t.text().contains('\n'),
    }
}

/// The whitespace that starts the line `token` is on.
pub(super) fn indent_of(token: &SyntaxToken) -> String {
    let mut t = token.prev_token();
    while let Some(prev) = t {
        if let Some(k) = prev.text().rfind('\n') {
            let after = &prev.text()[k + 1..];
            return if prev.kind() == WHITESPACE { after.to_string() } else { String::new() };
        }
        if prev.kind() != WHITESPACE {
            // Something before it on its line: the line's own indentation.
            return indent_of(&prev);
        }
        t = prev.prev_token();
    }
    String::new()
}

/// The edit that deletes a declaration from its body.
pub(super) fn delete_declaration(node: &SyntaxNode) -> Result<Edit, String> {
    delete(node).ok_or_else(|| {
        let owner = node.parent().and_then(|p| Body::of(&p).map(|_| p)).map(|p| p.kind());
        format!("the body around it is incomplete ({owner:?}): complete its braces first")
    })
}
