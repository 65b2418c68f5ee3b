//! Where the cursor is, as completion sees it: the node around the token before it, that
//! token (before the identifier being typed, if any) and what has been typed of the name.

use crate::{
    db::{parse, Db, SourceFile, Workspace},
    hir::Semantics,
    syntax::{SyntaxKind, SyntaxKind::*, SyntaxNode, SyntaxToken, TextSize},
};

/// The place completion is asked at.
pub(super) struct Ctx<'db> {
    pub db: &'db dyn Db,
    pub workspace: Workspace,
    pub file: SourceFile,
    pub sema: Semantics<'db>,
    /// The node around the token before the cursor (the file's root before the first token).
    pub at: SyntaxNode,
    /// The token before the identifier being typed, or before the cursor.
    pub before: Option<SyntaxToken>,
    pub before_kind: Option<SyntaxKind>,
    /// What has been typed of the identifier at the cursor (empty: none).
    pub typed: String,
}

impl<'db> Ctx<'db> {
    pub fn new(db: &'db dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Ctx<'db> {
        let root = parse(db, file).syntax_node();
        let previous = previous_token(&root, offset);
        let at = previous.as_ref().and_then(|t| t.parent()).unwrap_or_else(|| root.clone());
        let typing_ident = previous.as_ref().filter(|t| t.kind() == IDENT && t.text_range().end() == offset);
        let before = match typing_ident {
            Some(ident) => ident.prev_token().and_then(|t| skip_trivia_back(&t)),
            None => previous.clone(),
        };
        let before_kind = before.as_ref().map(|t| t.kind());
        let typed = typing_ident.map_or("", |t| t.text()).to_string();
        Ctx { db, workspace, file, sema: Semantics::new(db, workspace), at, before, before_kind, typed }
    }

    /// `A.B` when the token before is the `.` of `A.B.`.
    pub fn path_before_dot(&self) -> Option<String> {
        self.before.as_ref().filter(|t| t.kind() == DOT).and_then(path_before_dot)
    }
}

fn previous_token(root: &SyntaxNode, offset: TextSize) -> Option<SyntaxToken> {
    let token = root.token_at_offset(offset).left_biased()?;
    skip_trivia_back(&token)
}

pub(super) fn skip_trivia_back(token: &SyntaxToken) -> Option<SyntaxToken> {
    let mut t = Some(token.clone());
    while let Some(current) = t {
        if !current.kind().is_trivia() {
            return Some(current);
        }
        t = current.prev_token();
    }
    None
}

/// `A.B` for the `.` after `B` in `A.B.`.
fn path_before_dot(dot: &SyntaxToken) -> Option<String> {
    let mut segments = Vec::new();
    let mut t = dot.prev_token().and_then(|t| skip_trivia_back(&t));
    while let Some(ident) = t.filter(|t| t.kind() == IDENT) {
        segments.push(ident.text().to_string());
        let before = ident.prev_token().and_then(|t| skip_trivia_back(&t));
        match before {
            Some(d) if d.kind() == DOT => t = d.prev_token().and_then(|t| skip_trivia_back(&t)),
            _ => break,
        }
    }
    segments.reverse();
    (!segments.is_empty()).then(|| segments.join("."))
}
