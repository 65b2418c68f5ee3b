//! Go to definition and hover: what the name under the cursor refers to, where it is declared,
//! and how it reads.

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{
        check::{scope_at, Checker},
        Definition,
    },
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
    let type_ref = resolved.declaration.children().find_map(ast::TypeRef::cast)?;
    let path = type_ref.path()?;
    let checker = Checker::resolver(db, workspace, resolved.target.file);
    let def = checker.resolve(&scope_at(&resolved.declaration), &path.text())?;
    definition_target(db, def, resolved.reference)
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
    let token = ident_at(&root, offset)?;
    let parent = token.parent()?;
    let checker = Checker::resolver(db, workspace, file);
    match parent.kind() {
        // On a declaration's own name: the declaration.
        SyntaxKind::NAME => {
            let declaration = parent.parent()?;
            let is_global = ast::Diagram::can_cast(declaration.kind()) || ast::TypeDecl::can_cast(declaration.kind());
            let qualified = is_global.then(|| {
                let scope = scope_at(&declaration);
                // A diagram's scope includes itself; a type's is its diagram.
                if ast::Diagram::can_cast(declaration.kind()) {
                    scope.namespaces.last().cloned().unwrap_or_default()
                } else {
                    crate::hir::definitions::join(
                        scope.namespaces.last().map_or("", |s| s.as_str()),
                        &parent.text().to_string(),
                    )
                }
            });
            Some(Resolved {
                reference: parent.text_range(),
                target: NavigationTarget {
                    file,
                    full_range: declaration.text_range(),
                    focus_range: parent.text_range(),
                },
                declaration,
                qualified,
            })
        }
        SyntaxKind::NAME_REF => {
            let grand = parent.parent()?;
            match grand.kind() {
                SyntaxKind::PATH => resolve_path_segment(db, &checker, &parent, &grand),
                SyntaxKind::TRANSITION => resolve_transition_target(file, &parent, &grand),
                SyntaxKind::CALL_METHOD_EXPR => {
                    let class = ast::CallMethodExpr::cast(grand)?.class()?;
                    let def = checker.resolve(&scope_at(&parent), &class.text())?;
                    member_of(db, &checker, def, token.text(), parent.text_range())
                }
                SyntaxKind::NAME_EXPR => resolve_local(db, &checker, file, &parent, token.text()),
                _ => None,
            }
        }
        _ => None,
    }
}

/// A segment of a qualified name: resolve the path up to that segment.
fn resolve_path_segment(db: &dyn Db, checker: &Checker, segment: &SyntaxNode, path: &SyntaxNode) -> Option<Resolved> {
    let path = ast::Path::cast(path.clone())?;
    let mut prefix = Vec::new();
    for s in path.segments() {
        prefix.push(s.text());
        if s.syntax() == segment {
            break;
        }
    }
    let text = prefix.join(".");
    let scope = scope_at(path.syntax());
    // `port.connector` and similar paths name no workspace definition: nothing to show.
    let def = checker.resolve(&scope, &text)?;
    definition_target(db, def, segment.text_range())
}

fn definition_target(db: &dyn Db, def: &Definition, reference: TextRange) -> Option<Resolved> {
    let (declaration, name) = find_declaration(db, def)?;
    Some(Resolved {
        reference,
        target: NavigationTarget { file: def.file, full_range: declaration.text_range(), focus_range: name },
        declaration,
        qualified: Some(def.fqn.clone()),
    })
}

/// The declaration node of a definition, found by walking its file's tree along the name.
pub(crate) fn find_declaration(db: &dyn Db, def: &Definition) -> Option<(SyntaxNode, TextRange)> {
    let root = parse(db, def.file).syntax_node();
    let segments: Vec<&str> = def.fqn.split('.').collect();
    let mut candidates: Vec<SyntaxNode> = vec![root];
    let mut found: Option<(SyntaxNode, TextRange)> = None;
    for segment in segments {
        let mut next = Vec::new();
        for parent in &candidates {
            for child in parent.children() {
                let name = match ast::Diagram::cast(child.clone()) {
                    Some(d) => d.name(),
                    None => ast::TypeDecl::cast(child.clone()).and_then(|t| t.name()),
                };
                if let Some(name) = name.filter(|n| n.text() == segment) {
                    found = Some((child.clone(), name.syntax().text_range()));
                    next.push(child);
                }
            }
        }
        if next.is_empty() {
            return None;
        }
        candidates = next;
    }
    found
}

/// A member (field or method) of a type or its bases.
fn member_of(db: &dyn Db, checker: &Checker, def: &Definition, name: &str, reference: TextRange) -> Option<Resolved> {
    let mut seen = std::collections::HashSet::new();
    let (declaring, ()) = checker.find_member(&def.fqn, &mut seen, &|ty| {
        (ty.fields.iter().any(|f| f.name == name) || ty.methods.iter().any(|m| m.name == name)).then_some(())
    })?;
    let (type_node, _) = find_declaration(db, declaring)?;
    let decl = ast::TypeDecl::cast(type_node)?;
    let member = decl.members().find(|m| {
        let member_name = match m {
            ast::Member::Field(f) => f.name(),
            ast::Member::Method(m) => m.name(),
            ast::Member::Association(a) => a.name(),
        };
        member_name.is_some_and(|n| n.text() == name)
    })?;
    let name_range = member.syntax().children().find(|c| c.kind() == SyntaxKind::NAME)?.text_range();
    Some(Resolved {
        reference,
        target: NavigationTarget {
            file: declaring.file,
            full_range: member.syntax().text_range(),
            focus_range: name_range,
        },
        declaration: member.syntax().clone(),
        qualified: Some(format!("{}.{name}", declaring.fqn)),
    })
}

/// `=> target`: the node of that name in the same activity diagram.
fn resolve_transition_target(file: SourceFile, name_ref: &SyntaxNode, _transition: &SyntaxNode) -> Option<Resolved> {
    let wanted = name_ref.text().to_string();
    let diagram = name_ref.ancestors().find_map(ast::ActivityDiagram::cast)?;
    let node = diagram
        .syntax()
        .descendants()
        .filter_map(ast::ActivityNode::cast)
        .find(|n| n.name().is_some_and(|name| name.text() == wanted))?;
    let name = node.name()?;
    Some(Resolved {
        reference: name_ref.text_range(),
        target: NavigationTarget {
            file,
            full_range: node.syntax().text_range(),
            focus_range: name.syntax().text_range(),
        },
        declaration: node.syntax().clone(),
        qualified: None,
    })
}

/// A name in an expression: a local declaration, a parameter or variable of the enclosing
/// body or diagram, or a field of the owner class.
fn resolve_local(
    db: &dyn Db,
    checker: &Checker,
    file: SourceFile,
    name_ref: &SyntaxNode,
    name: &str,
) -> Option<Resolved> {
    let reference = name_ref.text_range();
    for ancestor in name_ref.ancestors() {
        let candidates: Vec<SyntaxNode> = match ancestor.kind() {
            SyntaxKind::BLOCK | SyntaxKind::NODE_BODY | SyntaxKind::SWITCH_CASE => {
                ancestor.children().filter(|c| c.kind() == SyntaxKind::VAR_DECL).collect()
            }
            SyntaxKind::METHOD
            | SyntaxKind::ACTION_NODE
            | SyntaxKind::CALC_NODE
            | SyntaxKind::CALC_RANGE_NODE
            | SyntaxKind::DECISION_NODE
            | SyntaxKind::LOOP_NODE
            | SyntaxKind::LOOP_WINDOW_NODE => ancestor
                .descendants()
                .filter(|c| c.kind() == SyntaxKind::PARAM || (c.kind() == SyntaxKind::VAR_DECL && in_loop_header(c)))
                .collect(),
            SyntaxKind::ACTIVITY_DIAGRAM => ancestor
                .children()
                .filter(|c| matches!(c.kind(), SyntaxKind::VARIABLE | SyntaxKind::VAR_DECL))
                .chain(ancestor.children().filter(|c| c.kind() == SyntaxKind::PARAM_LIST).flat_map(|l| l.children()))
                .collect(),
            _ => continue,
        };
        for candidate in candidates {
            let Some(decl_name) = candidate.children().find(|c| c.kind() == SyntaxKind::NAME) else { continue };
            if decl_name.text() == name {
                return Some(Resolved {
                    reference,
                    target: NavigationTarget {
                        file,
                        full_range: candidate.text_range(),
                        focus_range: decl_name.text_range(),
                    },
                    declaration: candidate,
                    qualified: None,
                });
            }
        }
    }
    // A field or method of the owner class (swimlane owner, diagram owner, enclosing class).
    let scope = scope_at(name_ref);
    let owner = checker.owner_at(name_ref)?;
    if let Some(found) = member_of(db, checker, owner, name, reference) {
        return Some(found);
    }
    // A type used as a scope (`HCImageChannelOrder.RGBA`).
    let def = checker.resolve(&scope, name)?;
    definition_target(db, def, reference)
}

fn in_loop_header(node: &SyntaxNode) -> bool {
    node.ancestors().any(|a| a.kind() == SyntaxKind::LOOP_HEADER)
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
