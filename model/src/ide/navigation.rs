//! Go to definition and hover: what the name under the cursor refers to (asked of
//! [`Semantics`]), where it is declared, and how it reads.

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{classify::NameRefClass, Definition, Scope, Semantics},
    syntax::{SyntaxKind, SyntaxNode, SyntaxToken, TextRange, TextSize},
};

use super::symbols::collapse_whitespace;

/// A place to jump to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NavigationTarget {
    pub file: SourceFile,
    /// The whole declaration.
    pub full_range: TextRange,
    /// Its name.
    pub focus_range: TextRange,
}

/// What the name under the cursor means.
pub(crate) struct Resolved {
    /// The name at the cursor.
    pub(crate) reference: TextRange,
    pub(crate) target: NavigationTarget,
    /// The declaration's node, for hover text.
    pub(crate) declaration: SyntaxNode,
    /// The fully qualified name, for workspace-level declarations.
    pub(crate) qualified: Option<String>,
}

/// The declarations the name at `offset` refers to (the declaration itself on a defining name).
pub fn goto_definition(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Vec<NavigationTarget> {
    resolve_at(db, workspace, file, offset).map(|r| r.target).into_iter().collect()
}

/// The declaration of the type of what the name at `offset` means: the class of a variable,
/// parameter or field; a type itself.
pub fn goto_type_definition(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    offset: TextSize,
) -> Vec<NavigationTarget> {
    type_of_name_at(db, workspace, file, offset).map(|r| r.target).into_iter().collect()
}

/// The definition of the declared type of the name at `offset`, if it has a user type.
pub(crate) fn type_of_name_at(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    offset: TextSize,
) -> Option<Resolved> {
    let resolved = resolve_at(db, workspace, file, offset)?;
    if ast::TypeDecl::can_cast(resolved.declaration.kind()) {
        return Some(resolved);
    }
    let type_ref = ast::support::child::<ast::TypeRef>(&resolved.declaration)?;
    let path = type_ref.path()?;
    let sema = Semantics::new(db, workspace);
    let def = sema.resolve(&Scope::at(&resolved.declaration), &path.text())?;
    definition_target(&sema, def, resolved.reference)
}

/// Hover text (markdown) for the name at `offset`, and the range it applies to.
pub fn hover(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Option<(TextRange, String)> {
    let resolved = resolve_at(db, workspace, file, offset)?;
    let mut text = format!("```gudsl\n{}\n```", signature(&resolved.declaration));
    if let Some(fqn) = resolved.qualified {
        text.push_str(&format!("\n\n`{fqn}`"));
    }
    let docs = doc_comment(&resolved.declaration);
    if !docs.is_empty() {
        text.push_str("\n\n---\n\n");
        text.push_str(&docs);
    }
    Some((resolved.reference, text))
}

fn ident_at(root: &SyntaxNode, offset: TextSize) -> Option<SyntaxToken> {
    let tokens = root.token_at_offset(offset);
    let (left, right) = (tokens.clone().left_biased(), tokens.right_biased());
    [right, left].into_iter().flatten().find(|t| t.kind() == SyntaxKind::IDENT || t.kind().is_contextual_keyword())
}

pub(crate) fn resolve_at(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Option<Resolved> {
    let root = parse(db, file).syntax_node();
    let parent = ident_at(&root, offset)?.parent()?;
    if parent.kind() == SyntaxKind::NAME {
        return Some(declared_at(file, &parent));
    }
    let name_ref = ast::NameRef::cast(parent)?;
    let reference = name_ref.syntax().text_range();
    let sema = Semantics::new(db, workspace);
    match sema.classify_name_ref(&name_ref)? {
        NameRefClass::Definition(def) => definition_target(&sema, def, reference),
        NameRefClass::Member { owner, member } => {
            let name = member.name()?;
            Some(Resolved {
                reference,
                target: NavigationTarget {
                    file: owner.file,
                    full_range: member.syntax().text_range(),
                    focus_range: name.syntax().text_range(),
                },
                declaration: member.syntax().clone(),
                qualified: Some(format!("{}.{}", owner.fqn, name.text())),
            })
        }
        NameRefClass::Node(node) => Some(local_target(file, reference, node.syntax().clone())),
        NameRefClass::Local(declaration) => Some(local_target(file, reference, declaration)),
    }
}

/// On a declaration's own name: the declaration (with its fully qualified name if it is a
/// diagram or type).
fn declared_at(file: SourceFile, name: &SyntaxNode) -> Resolved {
    let declaration = name.parent().unwrap_or_else(|| name.clone());
    let qualified = if ast::Diagram::can_cast(declaration.kind()) {
        // A diagram's scope includes itself.
        Some(Scope::at(&declaration).innermost().to_string())
    } else if ast::TypeDecl::can_cast(declaration.kind()) {
        Some(Scope::at(&declaration).qualify(&name.text().to_string()))
    } else {
        None
    };
    Resolved {
        reference: name.text_range(),
        target: NavigationTarget { file, full_range: declaration.text_range(), focus_range: name.text_range() },
        declaration,
        qualified,
    }
}

fn definition_target(sema: &Semantics, def: &Definition, reference: TextRange) -> Option<Resolved> {
    let (declaration, name) = sema.declaration(def)?;
    Some(Resolved {
        reference,
        target: NavigationTarget { file: def.file, full_range: declaration.text_range(), focus_range: name },
        declaration,
        qualified: Some(def.fqn.clone()),
    })
}

/// A declaration in the same file (a node, parameter or variable), named by its `NAME` child.
fn local_target(file: SourceFile, reference: TextRange, declaration: SyntaxNode) -> Resolved {
    let name = declaration.children().find(|c| c.kind() == SyntaxKind::NAME).map_or(reference, |n| n.text_range());
    Resolved {
        reference,
        target: NavigationTarget { file, full_range: declaration.text_range(), focus_range: name },
        declaration,
        qualified: None,
    }
}

/// A declaration's header as written, without attributes, comments or body.
fn signature(node: &SyntaxNode) -> String {
    let mut text = String::new();
    for element in node.children_with_tokens() {
        match element.kind() {
            SyntaxKind::ATTRIBUTE_LIST | SyntaxKind::LINE_COMMENT | SyntaxKind::BLOCK_COMMENT => continue,
            SyntaxKind::MEMBER_LIST | SyntaxKind::NODE_BODY | SyntaxKind::BLOCK | SyntaxKind::L_CURLY => break,
            SyntaxKind::SEMICOLON => break,
            _ => text.push_str(&element.to_string()),
        }
    }
    collapse_whitespace(&text)
}

/// The comments written directly above a declaration (attached to its node by the parser).
fn doc_comment(node: &SyntaxNode) -> String {
    let mut lines = Vec::new();
    for element in node.children_with_tokens() {
        match element.kind() {
            SyntaxKind::LINE_COMMENT => {
                let text = element.to_string();
                lines.push(text.trim_start_matches('/').trim().to_string());
            }
            SyntaxKind::BLOCK_COMMENT => {
                let text = element.to_string();
                lines.push(text.trim_start_matches("/*").trim_end_matches("*/").trim().to_string());
            }
            SyntaxKind::WHITESPACE => {}
            _ => break,
        }
    }
    lines.join("\n")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    use super::super::test_fixture::with_cursor as setup;

    fn target_text(db: &RootDatabase, target: &NavigationTarget) -> String {
        target.file.text(db)[target.focus_range].to_string()
    }

    #[test]
    fn definition_of_a_type_in_another_file() {
        let (db, ws, files, at) = setup(&[
            ("user.gudsl", "ClassDiagram U { import Defs.*; class V { public Ima$0ge img; } }"),
            ("defs.gudsl", "ClassDiagram Defs {\n  /// The image.\n  public class Image { }\n}"),
        ]);
        let targets = goto_definition(&db, ws, files[0], at);
        assert_eq!(targets.len(), 1);
        assert_eq!(targets[0].file, files[1]);
        assert_eq!(target_text(&db, &targets[0]), "Image");
        let (_, text) = hover(&db, ws, files[0], at).unwrap();
        assert!(text.contains("public class Image"), "{text}");
        assert!(text.contains("`Defs.Image`") && text.contains("The image."), "{text}");
    }

    #[test]
    fn definition_of_a_transition_target_and_a_local() {
        let (db, ws, files, at) = setup(&[(
            "ad.gudsl",
            "ActivityDiagram Ad(int n) { swimlane L { start S { => wo$0rk(n); } action work(int k) { var int x = k; => f; } final f; } }",
        )]);
        let targets = goto_definition(&db, ws, files[0], at);
        assert_eq!(target_text(&db, &targets[0]), "work");
        let (_, text) = hover(&db, ws, files[0], at).unwrap();
        assert!(text.contains("action work(int k)"), "{text}");

        let (db, ws, files, at) = setup(&[(
            "ad.gudsl",
            "ActivityDiagram Ad(int n) { swimlane L { start S { => work(n); } action work(int k) { var int x = k$0; => f; } final f; } }",
        )]);
        let targets = goto_definition(&db, ws, files[0], at);
        assert_eq!(target_text(&db, &targets[0]), "k");
    }

    #[test]
    fn definition_of_an_owner_field_and_a_class_method() {
        let (db, ws, files, at) = setup(&[
            ("ad.gudsl", "ActivityDiagram Ad() { swimlane L, owner Defs.Image { start S { => a; } action a { wid$0th = 3; call Defs.Image::grow(1); => f; } final f; } }"),
            ("defs.gudsl", "ClassDiagram Defs { class Base { public int width; } class Image extends Base { public void grow(int by); } }"),
        ]);
        let targets = goto_definition(&db, ws, files[0], at);
        assert_eq!(target_text(&db, &targets[0]), "width");
        assert_eq!(targets[0].file, files[1]);
        let text = files[0].text(&db).clone();
        let at = TextSize::from(text.find("grow").unwrap() as u32 + 1);
        let targets = goto_definition(&db, ws, files[0], at);
        assert_eq!(target_text(&db, &targets[0]), "grow");
    }

    #[test]
    fn type_definition_of_a_variable() {
        let (db, ws, files, at) = setup(&[
            ("ad.gudsl", "ActivityDiagram Ad(Defs.Image img) { swimlane L { start S { var int w = im$0g.width; => f; } final f; } }"),
            ("defs.gudsl", "ClassDiagram Defs { class Image { public int width; } }"),
        ]);
        let targets = goto_type_definition(&db, ws, files[0], at);
        assert_eq!(targets.len(), 1);
        assert_eq!(targets[0].file, files[1]);
        assert_eq!(target_text(&db, &targets[0]), "Image");
    }

    #[test]
    fn nothing_on_whitespace_and_broken_code() {
        let (db, ws, files, at) = setup(&[("x.gudsl", "ClassDiagram D { class C { public Unknown$0 x; } }  ")]);
        assert!(goto_definition(&db, ws, files[0], at).is_empty());
        assert!(goto_definition(&db, ws, files[0], TextSize::from(0)).is_empty());
        let (db, ws, files, at) = setup(&[("y.gudsl", "ClassDiagram D { class C { public $0 ")]);
        assert!(goto_definition(&db, ws, files[0], at).is_empty());
        assert!(hover(&db, ws, files[0], at).is_none());
    }
}
