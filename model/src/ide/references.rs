//! Find references and rename: every place that names the declaration under the cursor.
//!
//! Workspace-level declarations (diagrams, classes, interfaces, enums, attributes) are found
//! through the index of names (`hir::uses`): only the path segments spelled like the
//! declaration are resolved, from where they are written; activity
//! nodes through the transitions of their diagram; parameters and variables through the names
//! of their scope.

use crate::{
    ast::{self, AstNode, HasEnds},
    db::{parse, Db, SourceFile, Workspace},
    hir::{uses::segments_named, Semantics},
    library::is_library,
    syntax::{SyntaxKind, SyntaxNode, TextRange, TextSize},
};

use super::navigation::resolve_at;

/// One place in the workspace.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct FileRange {
    pub file: SourceFile,
    pub range: TextRange,
}

/// Every reference to what the name at `offset` means (with its declaration's name first if
/// `include_declaration`). Empty where the name resolves to nothing.
pub fn find_references(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    offset: TextSize,
    include_declaration: bool,
) -> Vec<FileRange> {
    let Some(resolved) = resolve_at(db, workspace, file, offset) else { return Vec::new() };
    let target = &resolved.target;
    let mut found = Vec::new();
    let declaration = resolved.declaration.clone();
    if let Some(fqn) = resolved.qualified.as_deref().filter(|_| is_global(&declaration)) {
        // Only a segment spelled like the declaration can name it: the index of names says
        // where those are, and only they are resolved.
        let sema = Semantics::new(db, workspace);
        let simple = fqn.rsplit('.').next().unwrap_or(fqn);
        for (other, range) in segments_named(db, workspace, simple) {
            let root = parse(db, other).syntax_node();
            let element = root.covering_element(range);
            let node = element.as_node().cloned().or_else(|| element.parent());
            let Some(segment) = node.and_then(|n| n.ancestors().find_map(ast::NameRef::cast)) else { continue };
            let Some(path) = segment.syntax().parent().and_then(ast::Path::cast) else { continue };
            if sema.resolve_path_segment(&path, &segment).is_some_and(|d| d.fqn == fqn) {
                found.push(FileRange { file: other, range });
            }
        }
    } else if ast::ActivityNode::can_cast(declaration.kind()) {
        let name = text_of(&declaration, target.focus_range);
        if let Some(diagram) = declaration.ancestors().find_map(ast::ActivityDiagram::cast) {
            for transition in diagram.syntax().descendants().filter_map(ast::Transition::cast) {
                if let Some(reference) = transition.target().filter(|t| t.text() == name) {
                    found.push(FileRange { file: target.file, range: reference.syntax().text_range() });
                }
            }
        }
    } else if ast::ComponentInstance::can_cast(declaration.kind()) {
        // Bindings name another instance of the diagram as `instance.portInstance.connector`.
        let name = text_of(&declaration, target.focus_range);
        if let Some(diagram) = declaration.ancestors().find_map(ast::ComponentInstanceDiagram::cast) {
            for binding in diagram.syntax().descendants().filter_map(ast::Binding::cast) {
                for path in [binding.source(), binding.target()].into_iter().flatten() {
                    let segments: Vec<ast::NameRef> = path.segments().collect();
                    if let [instance, _, _] = segments.as_slice() {
                        if instance.text() == name {
                            found.push(FileRange { file: target.file, range: instance.syntax().text_range() });
                        }
                    }
                }
            }
        }
    } else if matches!(declaration.kind(), SyntaxKind::PARAM | SyntaxKind::VAR_DECL | SyntaxKind::VARIABLE) {
        let name = text_of(&declaration, target.focus_range);
        let scope = declaration
            .ancestors()
            .skip(1)
            .find(|a| {
                matches!(
                    a.kind(),
                    SyntaxKind::METHOD | SyntaxKind::ACTIVITY_DIAGRAM | SyntaxKind::BLOCK | SyntaxKind::NODE_BODY
                ) || ast::ActivityNode::can_cast(a.kind())
            })
            .unwrap_or_else(|| declaration.clone());
        // Parameters of a node are used in its body; of a diagram, everywhere in it.
        for name_expr in scope.descendants().filter_map(ast::NameExpr::cast) {
            if let Some(reference) = name_expr.name_ref().filter(|r| r.text() == name) {
                // Only those that resolve back to this declaration (shadowing aside).
                let back = resolve_at(db, workspace, target.file, reference.syntax().text_range().start());
                if back.is_some_and(|b| b.target.focus_range == target.focus_range && b.target.file == target.file) {
                    found.push(FileRange { file: target.file, range: reference.syntax().text_range() });
                }
            }
        }
    }
    found.retain(|r| !(r.file == target.file && r.range == target.focus_range));
    if include_declaration {
        found.insert(0, FileRange { file: target.file, range: target.focus_range });
    }
    found.sort_by_key(|r| (r.file.path(db).clone(), r.range.start(), r.range.end()));
    found.dedup();
    found
}

fn is_global(declaration: &SyntaxNode) -> bool {
    ast::Diagram::can_cast(declaration.kind()) || ast::TypeDecl::can_cast(declaration.kind())
}

fn text_of(declaration: &SyntaxNode, range: TextRange) -> String {
    let start = declaration.text_range().start();
    let text = declaration.text().to_string();
    let (from, to) = (usize::from(range.start() - start), usize::from(range.end() - start));
    text.get(from..to).unwrap_or_default().to_string()
}

/// Why a rename cannot be done here.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RenameError(pub String);

/// The range of the name that a rename at `offset` would change.
pub fn prepare_rename(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    offset: TextSize,
) -> Result<TextRange, RenameError> {
    let resolved =
        resolve_at(db, workspace, file, offset).ok_or_else(|| RenameError("no renameable name here".into()))?;
    if is_library(db, resolved.target.file) {
        return Err(RenameError(format!(
            "`{}` is declared in gudsl's bundled library ({}), which is read-only",
            &file.text(db)[resolved.reference],
            resolved.target.file.path(db)
        )));
    }
    let declaration = &resolved.declaration;
    let renameable = is_global(declaration)
        || ast::ActivityNode::can_cast(declaration.kind())
        || ast::ComponentInstance::can_cast(declaration.kind())
        || matches!(declaration.kind(), SyntaxKind::PARAM | SyntaxKind::VAR_DECL | SyntaxKind::VARIABLE);
    if !renameable {
        return Err(RenameError("renaming fields and methods is not supported yet".into()));
    }
    Ok(resolved.reference)
}

/// Whether `name` is a name a user could declare (no keyword).
pub(crate) fn is_valid_name(name: &str) -> bool {
    name.chars().next().is_some_and(|c| c == '_' || c.is_ascii_alphabetic())
        && name.chars().all(|c| c == '_' || c.is_ascii_alphanumeric())
        && crate::SyntaxKind::from_keyword(name).is_none()
}

/// The edits that rename what the name at `offset` means to `new_name`.
pub fn rename(
    db: &dyn Db,
    workspace: Workspace,
    file: SourceFile,
    offset: TextSize,
    new_name: &str,
) -> Result<Vec<(FileRange, String)>, RenameError> {
    if !is_valid_name(new_name) {
        return Err(RenameError(format!("`{new_name}` is not a valid name")));
    }
    prepare_rename(db, workspace, file, offset)?;
    Ok(find_references(db, workspace, file, offset, true).into_iter().map(|r| (r, new_name.to_string())).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    use super::super::test_fixture::with_cursor as setup;

    fn texts(db: &RootDatabase, refs: &[FileRange]) -> Vec<(String, String)> {
        refs.iter().map(|r| (r.file.path(db).clone(), r.file.text(db)[r.range].to_string())).collect()
    }

    #[test]
    fn a_declaration_of_the_library_is_not_renamed() {
        let (db, _, files, at) = setup(&[(
            "k.gudsl",
            "ClassDiagram K { import OpenCL.GPU.*; class C implements Open$0CL { public void m() { } } }",
        )]);
        let library = crate::library::library_files(&db);
        let ws = Workspace::new(&db, library.into_iter().chain(files.iter().copied()).collect());
        let refused = rename(&db, ws, files[0], at, "Renamed").unwrap_err();
        assert_eq!(
            refused.0,
            "`OpenCL` is declared in gudsl's bundled library (gudsl:/lib/opencl.gudsl), which is read-only"
        );
    }

    #[test]
    fn references_of_a_class_across_files_and_qualifications() {
        let (db, ws, files, at) = setup(&[
            ("defs.gudsl", "ClassDiagram Defs { public class Ima$0ge { } public class Other { public Image i; } }"),
            (
                "user.gudsl",
                "ClassDiagram U { import Defs.*; class V { public Image a; public Defs.Image b; public Other c; } }",
            ),
            ("ad.gudsl", "ActivityDiagram Ad(), owner Defs.Image { swimlane L { start S { => f; } final f; } }"),
        ]);
        let refs = find_references(&db, ws, files[0], at, true);
        let found = texts(&db, &refs);
        assert_eq!(found.len(), 5, "{found:?}");
        assert!(found.iter().all(|(_, t)| t == "Image"));
        let edits = rename(&db, ws, files[0], at, "Picture").unwrap();
        assert_eq!(edits.len(), 5);
        assert!(rename(&db, ws, files[0], at, "class").is_err());
        assert!(rename(&db, ws, files[0], at, "9x").is_err());
    }

    #[test]
    fn references_of_a_node_and_a_parameter() {
        let (db, ws, files, at) = setup(&[(
            "ad.gudsl",
            "ActivityDiagram Ad(int n) { swimlane L { start S { => work(n); } action wo$0rk(int k) { var int x = k + k; [x > 0] => work(x); [] => f; } final f; } }",
        )]);
        let refs = find_references(&db, ws, files[0], at, false);
        assert_eq!(texts(&db, &refs).len(), 2);
        let text = files[0].text(&db).clone();
        let k = TextSize::from(text.find("int k").unwrap() as u32 + 4);
        let refs = find_references(&db, ws, files[0], k, true);
        assert_eq!(texts(&db, &refs).iter().filter(|(_, t)| t == "k").count(), 3);
    }

    #[test]
    fn nothing_to_rename_on_keywords_and_whitespace() {
        let (db, ws, files, at) = setup(&[("a.gudsl", "ClassDiagram D { $0 class C { } }")]);
        assert!(prepare_rename(&db, ws, files[0], at).is_err());
        assert!(find_references(&db, ws, files[0], at, true).is_empty());
    }
}
