//! Quick fixes for diagnostics: create a missing node, remove an unreachable one, fix a
//! transition's arguments, add the processor signature a provider method needs, import an
//! ambiguous type, and correct a misspelt type or owner name.

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{
        file_diagnostics,
        items::{InterfaceRole, TypeKind},
        DefKind, DiagnosticCode, Semantics,
    },
    syntax::{SyntaxKind, SyntaxNode, TextRange, TextSize},
    text::{line_ending, with_line_ending},
};

use super::references::FileRange;

/// One fix: a title and the edits that apply it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct QuickFix {
    pub title: String,
    /// The diagnostic it fixes.
    pub code: DiagnosticCode,
    pub diagnostic_range: TextRange,
    pub edits: Vec<(FileRange, String)>,
}

/// The fixes for the diagnostics of `file` that overlap `range`.
pub fn quick_fixes(db: &dyn Db, workspace: Workspace, file: SourceFile, range: TextRange) -> Vec<QuickFix> {
    let root = parse(db, file).syntax_node();
    let text = file.text(db);
    let eol = line_ending(text);
    let mut fixes = Vec::new();
    for diagnostic in file_diagnostics(db, workspace, file) {
        if diagnostic.range.intersect(range).is_none() && !range.contains_range(diagnostic.range) {
            continue;
        }
        let node = covering_node(&root, diagnostic.range);
        let mut push = |title: String, edits: Vec<(TextRange, String)>| {
            fixes.push(QuickFix {
                title,
                code: diagnostic.code,
                diagnostic_range: diagnostic.range,
                edits: edits
                    .into_iter()
                    .map(|(range, text)| (FileRange { file, range }, with_line_ending(&text, eol)))
                    .collect(),
            });
        };
        match diagnostic.code {
            DiagnosticCode::UnresolvedTransitionTarget => {
                if let Some((title, edit)) = create_node(&node, text) {
                    push(title, vec![edit]);
                }
            }
            DiagnosticCode::UnreachableNode => {
                if let Some(node) = node.ancestors().find_map(ast::ActivityNode::cast) {
                    let name = node.name().map(|n| n.text()).unwrap_or_default();
                    push(
                        format!("Remove unreachable node `{name}`"),
                        vec![(line_span(text, node.syntax().text_range()), String::new())],
                    );
                }
            }
            DiagnosticCode::TransitionArity => {
                if let Some((title, edit)) = fix_arguments(&node) {
                    push(title, vec![edit]);
                }
            }
            DiagnosticCode::MissingProcessorSignature => {
                if let Some((title, edit)) = add_processor_signature(&root, &node, text) {
                    push(title, vec![edit]);
                }
            }
            DiagnosticCode::UnresolvedType | DiagnosticCode::UnresolvedOwner => {
                let written = text[diagnostic.range].to_string();
                let map = Semantics::new(db, workspace).def_map();
                let simple = written.rsplit('.').next().unwrap_or(&written).to_string();
                // Ambiguous: import one of the candidates.
                if let Some(candidates) =
                    map.types_by_simple_name.get(&simple).filter(|c| c.len() > 1 && !written.contains('.'))
                {
                    if let Some((at, indent)) = import_position(&node, text) {
                        for fqn in candidates {
                            push(
                                format!("Import `{fqn}`"),
                                vec![(TextRange::empty(at), format!("{indent}import {fqn};\n"))],
                            );
                        }
                    }
                }
                // Misspelt: the closest declared type.
                let wanted_class = diagnostic.code == DiagnosticCode::UnresolvedOwner;
                let written_len = written.chars().count();
                let most = 2.max(written.len() / 4);
                let qualified = written.contains('.');
                let best = map
                    .definitions
                    .iter()
                    .filter(|(_, defs)| match &defs[0].kind {
                        DefKind::Type(ty) => !wanted_class || matches!(ty.kind, TypeKind::Class(_)),
                        _ => false,
                    })
                    .inspect(|_| db.unwind_if_revision_cancelled())
                    .map(|(fqn, _)| if qualified { fqn.as_str() } else { fqn.rsplit('.').next().unwrap_or(fqn) })
                    // The distance is at least the difference in length: a long name is
                    // compared with nothing rather than with every type.
                    .filter(|candidate| candidate.chars().count().abs_diff(written_len) <= most)
                    .map(|candidate| (edit_distance(&written, candidate), candidate.to_string()))
                    .filter(|(d, c)| *d > 0 && *d <= most && c != &written)
                    .min();
                if let Some((_, replacement)) = best {
                    push(format!("Change to `{replacement}`"), vec![(diagnostic.range, replacement)]);
                }
            }
            _ => {}
        }
    }
    fixes
}

/// The smallest node that covers `range`.
fn covering_node(root: &SyntaxNode, range: TextRange) -> SyntaxNode {
    match root.covering_element(range) {
        rowan::NodeOrToken::Node(node) => node,
        rowan::NodeOrToken::Token(token) => token.parent().unwrap_or_else(|| root.clone()),
    }
}

/// The whole lines a range sits on (with its line break), so deleting leaves no blank line.
fn line_span(text: &str, range: TextRange) -> TextRange {
    let start = line_start(text, range.start().into());
    let end = next_line_start(text, range.end().into());
    TextRange::new((start as u32).into(), (end as u32).into())
}

/// Where the line holding `offset` starts.
fn line_start(text: &str, offset: usize) -> usize {
    text[..offset].rfind(['\n', '\r']).map_or(0, |i| i + 1)
}

/// Where the line after the one holding `offset` starts (the text's end on the last line).
fn next_line_start(text: &str, offset: usize) -> usize {
    match text[offset..].find(['\n', '\r']) {
        Some(i) => offset + i + if text[offset + i..].starts_with("\r\n") { 2 } else { 1 },
        None => text.len(),
    }
}

/// The indentation of the line `offset` is on.
fn indentation_at(text: &str, offset: TextSize) -> String {
    text[line_start(text, offset.into())..].chars().take_while(|c| *c == ' ' || *c == '\t').collect()
}

/// `=> missing;`: a new action node `missing` before the end of the transition's swimlane.
fn create_node(node: &SyntaxNode, text: &str) -> Option<(String, (TextRange, String))> {
    let transition = node.ancestors().find_map(ast::Transition::cast)?;
    let target = transition.target()?.text();
    let current = transition.syntax().ancestors().find_map(ast::ActivityNode::cast)?;
    let container = current.syntax().parent()?;
    let close = container.children_with_tokens().filter(|e| e.kind() == SyntaxKind::R_CURLY).last()?;
    let indent = indentation_at(text, current.syntax().text_range().start());
    let params: Vec<String> = transition
        .args()
        .enumerate()
        .map(|(i, arg)| match arg {
            ast::Expr::NameExpr(n) => {
                format!("int {}", n.name_ref().map(|r| r.text()).unwrap_or_else(|| format!("arg{i}")))
            }
            _ => format!("int arg{}", i + 1),
        })
        .collect();
    let final_node = container
        .children()
        .filter_map(ast::ActivityNode::cast)
        .find(|n| n.kind() == ast::NodeKind::Final)
        .and_then(|n| n.name())
        .map(|n| n.text());
    let body = match final_node {
        Some(f) => format!("{indent}{{\n{indent}    => {f};\n{indent}}}\n"),
        None => format!("{indent}{{\n{indent}}}\n"),
    };
    let insert_at = line_span(text, close.text_range()).start();
    let new_node = format!("\n{indent}action {target}({})\n{body}", params.join(", "));
    Some((format!("Create action node `{target}`"), (TextRange::empty(insert_at), new_node)))
}

/// Rewrites a transition's argument list to what its target node takes.
fn fix_arguments(node: &SyntaxNode) -> Option<(String, (TextRange, String))> {
    let transition = node.ancestors().find_map(ast::Transition::cast)?;
    let target = transition.target()?;
    let diagram = transition.syntax().ancestors().find_map(ast::ActivityDiagram::cast)?;
    let target_node = diagram
        .syntax()
        .descendants()
        .filter_map(ast::ActivityNode::cast)
        .find(|n| n.name().is_some_and(|name| name.text() == target.text()))?;
    let mut args: Vec<String> = match target_node.kind() {
        ast::NodeKind::Calc => vec!["width".into(), "height".into(), "1".into()],
        ast::NodeKind::CalcRange => {
            vec!["globalX".into(), "1".into(), "1".into(), "localX".into(), "1".into(), "1".into()]
        }
        _ => Vec::new(),
    };
    let existing: Vec<String> = transition.args().map(|a| a.syntax().text().to_string()).collect();
    let params: Vec<String> = target_node.params().filter_map(|p| p.name()).map(|n| n.text()).collect();
    // Keep the arguments written for the parameters, fill the rest with the parameter names.
    let skip = args.len();
    for (i, param) in params.iter().enumerate() {
        args.push(existing.get(skip + i).cloned().unwrap_or_else(|| param.clone()));
    }
    let new_list = format!("({})", args.join(", "));
    let range = match transition.arg_list() {
        Some(list) => list.syntax().text_range(),
        None => TextRange::empty(target.syntax().text_range().end()),
    };
    Some((format!("Pass {} argument(s) to `{}`", args.len(), target.text()), (range, new_list)))
}

/// `provideX(…)` without `processX(…)`: add the signature to the file's processor interface.
fn add_processor_signature(root: &SyntaxNode, node: &SyntaxNode, text: &str) -> Option<(String, (TextRange, String))> {
    let method = node.ancestors().find_map(ast::Method::cast)?;
    let name = method.name()?.text();
    let suffix = name.strip_prefix("provide")?;
    let params = method.param_list().map(|p| p.syntax().text().to_string()).unwrap_or_else(|| "()".into());
    let signature = format!("public void process{suffix}{params};");
    let processor =
        root.descendants().filter_map(ast::Interface::cast).find(|i| i.role() == InterfaceRole::Processor)?;
    let list = processor.syntax().children().find(|c| c.kind() == SyntaxKind::MEMBER_LIST)?;
    let close = list.children_with_tokens().filter(|e| e.kind() == SyntaxKind::R_CURLY).last()?;
    let indent = indentation_at(text, processor.syntax().text_range().start());
    let interface = processor.name()?.text();
    let at = line_span(text, close.text_range()).start();
    let edit = if text[usize::from(at)..usize::from(close.text_range().start())].trim().is_empty() {
        (TextRange::empty(at), format!("{indent}    {signature}\n"))
    } else {
        (TextRange::empty(close.text_range().start()), format!(" {signature} "))
    };
    Some((format!("Add `process{suffix}` to processor interface `{interface}`"), edit))
}

/// Where an import goes in the diagram around `node`: after its `{`, with the indentation.
fn import_position(node: &SyntaxNode, text: &str) -> Option<(TextSize, String)> {
    let diagram = node.ancestors().find_map(ast::Diagram::cast)?;
    let open = diagram.syntax().children_with_tokens().find(|e| e.kind() == SyntaxKind::L_CURLY)?;
    let after = usize::from(open.text_range().end());
    let line_end = next_line_start(text, after);
    let indent = format!("{}    ", indentation_at(text, diagram.syntax().text_range().start()));
    Some(((line_end as u32).into(), indent))
}

/// Levenshtein distance, for "did you mean" fixes.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut previous = row[0];
        row[0] = i + 1;
        for j in 0..b.len() {
            let current = row[j + 1];
            row[j + 1] = (current + 1).min(row[j] + 1).min(previous + usize::from(ca != b[j]));
            previous = current;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    fn apply(files: &[(&str, &str)], title_part: &str) -> Vec<String> {
        let db = RootDatabase::default();
        let inputs: Vec<SourceFile> =
            files.iter().map(|(p, t)| SourceFile::new(&db, p.to_string(), t.to_string())).collect();
        let ws = Workspace::new(&db, inputs.clone());
        let whole = TextRange::up_to((inputs[0].text(&db).len() as u32).into());
        let fixes = quick_fixes(&db, ws, inputs[0], whole);
        let fix = fixes.iter().find(|f| f.title.contains(title_part)).unwrap_or_else(|| {
            panic!("no fix `{title_part}` in {:?}", fixes.iter().map(|f| &f.title).collect::<Vec<_>>())
        });
        let mut text = inputs[0].text(&db).clone();
        let mut edits = fix.edits.clone();
        edits.sort_by_key(|(r, _)| std::cmp::Reverse(r.range.start()));
        for (place, new) in edits {
            text.replace_range(std::ops::Range::<usize>::from(place.range), &new);
        }
        // The fixed text checks clean.
        let fixed = SourceFile::new(&db, "fixed.gudsl".into(), text.clone());
        let mut all = inputs[1..].to_vec();
        all.push(fixed);
        let ws2 = Workspace::new(&db, all);
        vec![
            text,
            format!("{:?}", file_diagnostics(&db, ws2, fixed).iter().map(|d| d.code.as_str()).collect::<Vec<_>>()),
        ]
    }

    #[test]
    fn create_missing_node() {
        let out = apply(
            &[("a.gudsl", "ActivityDiagram Ad()\n{\n    swimlane L\n    {\n        start S\n        {\n            => work(3);\n        }\n        final done;\n    }\n}\n")],
            "Create action node `work`",
        );
        assert!(
            out[0].contains("        action work(int arg1)\n        {\n            => done;\n        }\n    }\n}"),
            "{}",
            out[0]
        );
        assert_eq!(out[1], "[]");
    }

    #[test]
    fn remove_unreachable_node() {
        let out = apply(
            &[("a.gudsl", "ActivityDiagram Ad()\n{\n    swimlane L\n    {\n        start S { => done; }\n        action orphan { => done; }\n        final done;\n    }\n}\n")],
            "Remove unreachable node",
        );
        assert!(!out[0].contains("orphan"));
        assert_eq!(out[1], "[]");
    }

    #[test]
    fn fix_transition_arguments() {
        let out = apply(
            &[("a.gudsl", "ActivityDiagram Ad(int w)\n{\n    swimlane L\n    {\n        start S { => filter(w); }\n        calc filter(int radius) { => done; }\n        final done;\n    }\n}\n")],
            "Pass 4 argument(s)",
        );
        assert!(out[0].contains("=> filter(width, height, 1, radius);"), "{}", out[0]);
    }

    #[test]
    fn add_processor_signature_to_the_processor_interface() {
        let out = apply(
            &[("a.gudsl", "ClassDiagram D\n{\n    public class Image { }\n    public interface provider Out\n    {\n        public void provideImage(ref Image image);\n    }\n    public interface processor In\n    {\n    }\n}\n")],
            "Add `processImage`",
        );
        assert!(
            out[0].contains(
                "    public interface processor In\n    {\n        public void processImage(ref Image image);\n    }"
            ),
            "{}",
            out[0]
        );
        assert_eq!(out[1], "[]");
    }

    #[test]
    fn import_an_ambiguous_type_and_correct_a_typo() {
        let files = [
            ("u.gudsl", "ClassDiagram U\n{\n    public class V { public Image a; public Pixle p; }\n}\n"),
            ("a.gudsl", "ClassDiagram A { public class Image { } public class Pixel { } }"),
            ("b.gudsl", "ClassDiagram B { public class Image { } }"),
        ];
        let out = apply(&files, "Import `A.Image`");
        assert!(out[0].starts_with("ClassDiagram U\n{\n    import A.Image;\n"), "{}", out[0]);
        let out = apply(&files, "Change to `Pixel`");
        assert!(out[0].contains("public Pixel p;"), "{}", out[0]);
    }
}
