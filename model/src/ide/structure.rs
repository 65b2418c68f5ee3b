//! Selection ranges, workspace symbols and semantic token classes: features that read the
//! tree's structure (and the definition map) without resolving the cursor's name.

use crate::{
    ast::{self, AstNode},
    db::{parse, Db, SourceFile, Workspace},
    hir::{items::TypeKind, DefKind, Semantics},
    library::is_library,
    syntax::{SyntaxKind::*, SyntaxNode, SyntaxToken, TextRange, TextSize},
};

/// The ranges to grow a selection through at `offset`, innermost first.
pub fn selection_ranges(root: &SyntaxNode, offset: TextSize) -> Vec<TextRange> {
    let Some(token) = root.token_at_offset(offset).right_biased() else { return Vec::new() };
    let mut ranges = vec![token.text_range()];
    for node in token.parent_ancestors() {
        let range = node.text_range();
        if ranges.last() != Some(&range) {
            ranges.push(range);
        }
    }
    ranges
}

/// A workspace-level declaration matching a symbol search.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct WorkspaceSymbol {
    pub name: String,
    pub fqn: String,
    pub kind: WorkspaceSymbolKind,
    pub file: SourceFile,
    pub focus_range: TextRange,
}

/// What a workspace symbol is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkspaceSymbolKind {
    Diagram,
    Activity,
    Class,
    Interface,
    Enum,
    Attribute,
}

/// Diagrams and types whose name contains `query` (case-insensitive; all for an empty query),
/// at most `limit`: the workspace's own first, then the bundled library's.
pub fn workspace_symbols(db: &dyn Db, workspace: Workspace, query: &str, limit: usize) -> Vec<WorkspaceSymbol> {
    let query = query.to_lowercase();
    let sema = Semantics::new(db, workspace);
    let matching = || {
        sema.def_map()
            .definitions
            .iter()
            .map(|(fqn, defs)| (fqn, fqn.rsplit('.').next().unwrap_or(fqn), defs))
            .filter(|(_, name, _)| name.to_lowercase().contains(&query))
            .flat_map(|(fqn, name, defs)| defs.iter().map(move |def| (fqn, name, def)))
    };
    let mut out = Vec::new();
    for library in [false, true] {
        for (fqn, name, def) in matching().filter(|(_, _, def)| is_library(db, def.file) == library) {
            if out.len() >= limit {
                return out;
            }
            let kind = match &def.kind {
                DefKind::Activity(_) => WorkspaceSymbolKind::Activity,
                DefKind::Type(ty) => match ty.kind {
                    TypeKind::Class(_) => WorkspaceSymbolKind::Class,
                    TypeKind::Interface(_) => WorkspaceSymbolKind::Interface,
                    TypeKind::Enum => WorkspaceSymbolKind::Enum,
                    TypeKind::Attribute => WorkspaceSymbolKind::Attribute,
                },
                _ => WorkspaceSymbolKind::Diagram,
            };
            let Some((_, focus_range)) = sema.declaration(def) else { continue };
            out.push(WorkspaceSymbol { name: name.to_string(), fqn: fqn.clone(), kind, file: def.file, focus_range });
        }
    }
    out
}

/// Classes of semantic tokens, in the order of the server's legend.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TokenClass {
    Keyword,
    Comment,
    String,
    Number,
    Operator,
    Namespace,
    Class,
    Interface,
    Enum,
    EnumMember,
    Type,
    Function,
    Method,
    Property,
    Parameter,
    Variable,
    Decorator,
}

/// One classified token.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct HighlightedToken {
    pub range: TextRange,
    pub class: TokenClass,
    /// The token declares the name (bold in most themes).
    pub declaration: bool,
}

/// Classifies every token of a file that has a class, in order.
pub fn semantic_tokens(db: &dyn Db, file: SourceFile) -> Vec<HighlightedToken> {
    let root = parse(db, file).syntax_node();
    // Unwinds with `Cancelled` at the next token once a newer change is waiting.
    root.descendants_with_tokens()
        .filter_map(|e| e.into_token())
        .inspect(|_| db.unwind_if_revision_cancelled())
        .filter_map(|token| {
            classify(&token).map(|(class, declaration)| HighlightedToken {
                range: token.text_range(),
                class,
                declaration,
            })
        })
        .collect()
}

fn classify(token: &SyntaxToken) -> Option<(TokenClass, bool)> {
    let kind = token.kind();
    let simple = match kind {
        LINE_COMMENT | BLOCK_COMMENT => Some(TokenClass::Comment),
        STRING | CHAR => Some(TokenClass::String),
        INT_NUMBER | FLOAT_NUMBER => Some(TokenClass::Number),
        TRUE_KW | FALSE_KW | NULL_KW => Some(TokenClass::Keyword),
        FAT_ARROW | LONG_FAT_ARROW => Some(TokenClass::Operator),
        k if k.is_builtin_type() || k == UNSIGNED_KW => Some(TokenClass::Type),
        k if k.is_keyword() => Some(TokenClass::Keyword),
        _ => None,
    };
    if simple.is_some() {
        return simple.map(|c| (c, false));
    }
    if kind != IDENT {
        return None;
    }
    let parent = token.parent()?;
    let grand = parent.parent();
    let grand_kind = grand.as_ref().map(|g| g.kind()).unwrap_or(SOURCE_FILE);
    match parent.kind() {
        NAME => Some((
            match grand_kind {
                CLASS_DIAGRAM | ACTIVITY_DIAGRAM | COMPONENT_DIAGRAM | COMPONENT_INSTANCE_DIAGRAM | SWIMLANE => {
                    TokenClass::Namespace
                }
                CLASS => TokenClass::Class,
                INTERFACE => TokenClass::Interface,
                ENUM => TokenClass::Enum,
                ENUM_VALUE => TokenClass::EnumMember,
                ATTRIBUTE_DEF => TokenClass::Decorator,
                METHOD => TokenClass::Method,
                FIELD | ASSOCIATION => TokenClass::Property,
                PARAM => TokenClass::Parameter,
                TEMPLATE_PARAM => TokenClass::Type,
                k if ast::ActivityNode::can_cast(k) => TokenClass::Function,
                _ => TokenClass::Variable,
            },
            true,
        )),
        NAME_REF => {
            let in_path = grand_kind == PATH;
            let context =
                if in_path { grand.as_ref().and_then(|g| g.parent()).map(|g| g.kind()) } else { Some(grand_kind) };
            Some((
                match context? {
                    TYPE_REF | EXTENDS_CLAUSE | IMPLEMENTS_CLAUSE | OWNER_CLAUSE | COMPONENT | CALL_METHOD_EXPR => {
                        if in_path && is_last_segment(&parent) {
                            TokenClass::Class
                        } else if in_path {
                            TokenClass::Namespace
                        } else {
                            TokenClass::Method
                        }
                    }
                    ATTRIBUTE_USE => TokenClass::Decorator,
                    IMPORT => TokenClass::Namespace,
                    CALL_BEHAVIOR_EXPR => TokenClass::Function,
                    TRANSITION => TokenClass::Function,
                    NAMED_ARG => TokenClass::Property,
                    MEMBER_EXPR => TokenClass::Property,
                    _ => TokenClass::Variable,
                },
                false,
            ))
        }
        _ => None,
    }
}

fn is_last_segment(name_ref: &SyntaxNode) -> bool {
    name_ref.next_sibling().is_none()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    #[test]
    fn selection_grows_from_token_to_file() {
        let text = "ClassDiagram D { class C { public int width; } }";
        let parse = crate::parse(text);
        let at = TextSize::from(text.find("width").unwrap() as u32 + 1);
        let ranges = selection_ranges(&parse.syntax_node(), at);
        let texts: Vec<&str> = ranges.iter().map(|r| &text[*r]).collect();
        assert_eq!(texts[0], "width");
        assert_eq!(texts[1], "public int width;");
        assert_eq!(texts[2], "{ public int width; }");
        assert_eq!(*texts.last().unwrap(), text);
    }

    #[test]
    fn workspace_symbols_and_semantic_classes() {
        let db = RootDatabase::default();
        let file = SourceFile::new(&db, "a.gudsl".into(), "ClassDiagram Defs { class Image { public int width; } interface IImage { } }\nActivityDiagram AdImage() { swimlane L { start S { => S; } } }".into());
        let ws = Workspace::new(&db, vec![file]);
        let found: Vec<(String, WorkspaceSymbolKind)> =
            workspace_symbols(&db, ws, "image", 10).into_iter().map(|s| (s.fqn, s.kind)).collect();
        assert_eq!(
            found,
            [
                ("AdImage".to_string(), WorkspaceSymbolKind::Activity),
                ("Defs.IImage".to_string(), WorkspaceSymbolKind::Interface),
                ("Defs.Image".to_string(), WorkspaceSymbolKind::Class),
            ]
        );
        let tokens = semantic_tokens(&db, file);
        let text = file.text(&db);
        let class_of = |word: &str| tokens.iter().find(|t| &text[t.range] == word).map(|t| t.class);
        assert_eq!(class_of("ClassDiagram"), Some(TokenClass::Keyword));
        assert_eq!(class_of("Image"), Some(TokenClass::Class));
        assert_eq!(class_of("width"), Some(TokenClass::Property));
        assert_eq!(class_of("int"), Some(TokenClass::Type));
        assert_eq!(class_of("S"), Some(TokenClass::Function));
    }
}
