//! Quick fixes for diagnostics: create a missing node, remove an unreachable one, fix a
//! transition's arguments, add the processor signature a provider method needs, implement a
//! port's interface in the component's class, import an ambiguous type, correct a misspelt
//! name, and put a type's bases right (`bases`).

mod bases;

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{
        file_diagnostics,
        items::{InterfaceRole, TypeKind},
        spelling::{closest, edit_distance, typo_distance},
        DefKind, DiagnosticCode, Scope, Semantics,
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
            // A typo of something that exists: write what was meant.
            _ if diagnostic.suggestion.is_some() => {
                let name = diagnostic.suggestion.clone().unwrap_or_default();
                push(format!("Change to `{name}`"), vec![(diagnostic.range, name)]);
            }
            // A transition to a node that does not exist (and is no typo): create it.
            DiagnosticCode::UnresolvedTransitionTarget => {
                if let Some((title, edit)) = create_node(&node, text) {
                    push(title, vec![edit]);
                }
            }
            DiagnosticCode::UnreachableNode => {
                // Not a final node (removing it never helps), nor one a mistyped transition
                // was meant to reach.
                if let Some(node) = node.ancestors().find_map(ast::ActivityNode::cast) {
                    let name = node.name().map(|n| n.text()).unwrap_or_default();
                    let missing = unresolved_targets(&node);
                    let meant = missing.iter().any(|target| closest(target, [name.as_str()]).is_some());
                    if node.kind() != ast::NodeKind::Final && !meant {
                        push(
                            format!("Remove unreachable node `{name}`"),
                            vec![(line_span(text, node.syntax().text_range()), String::new())],
                        );
                    }
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
            DiagnosticCode::InterfaceNotImplemented => {
                if let Some((title, edit)) = implement_interface(db, workspace, &node) {
                    fixes.push(QuickFix {
                        title,
                        code: diagnostic.code,
                        diagnostic_range: diagnostic.range,
                        edits: vec![edit],
                    });
                }
            }
            DiagnosticCode::InvalidInheritance => {
                if let Some((title, edit)) = bases::fix_base(db, workspace, &node) {
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
                    if let Some((at, before, after)) = import_position(&node, text) {
                        for fqn in candidates {
                            push(
                                format!("Import `{fqn}`"),
                                vec![(TextRange::empty(at), format!("{before}import {fqn};{after}"))],
                            );
                        }
                    }
                }
                // Misspelt: the closest declared type.
                let wanted_class = diagnostic.code == DiagnosticCode::UnresolvedOwner;
                let written_len = written.chars().count();
                let most = typo_distance(&written);
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
    // A node of that name in another flow (a container's, Sec. 9.2.2.3) is not created twice.
    let diagram = current.syntax().ancestors().find_map(ast::ActivityDiagram::cast)?;
    if diagram.every_node().iter().any(|n| n.name().is_some_and(|n| n.text() == target)) {
        return None;
    }
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

/// The names of the nodes of the activity diagram around `node`.
fn node_names(node: &SyntaxNode) -> Vec<String> {
    let Some(diagram) = node.ancestors().find_map(ast::ActivityDiagram::cast) else { return Vec::new() };
    diagram.syntax().descendants().filter_map(ast::ActivityNode::cast).filter_map(|n| Some(n.name()?.text())).collect()
}

/// The transition targets of the diagram around `node` that name no node.
fn unresolved_targets(node: &ast::ActivityNode) -> Vec<String> {
    let names = node_names(node.syntax());
    let Some(diagram) = node.syntax().ancestors().find_map(ast::ActivityDiagram::cast) else { return Vec::new() };
    diagram
        .syntax()
        .descendants()
        .filter_map(ast::Transition::cast)
        .filter_map(|t| t.target().map(|target| target.text()))
        .filter(|target| !names.contains(target))
        .collect()
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
    // Work sizes (a calc node's 3) and ranges (a calcRange node's: global and local, 1D) as
    // written, else 1; then each parameter's argument as written, else a value of its type.
    let leading = match target_node.kind() {
        ast::NodeKind::Calc => 3,
        ast::NodeKind::CalcRange => 2,
        _ => 0,
    };
    // Arguments as many as the parameters are the parameters' (the work sizes were left out).
    let existing: Vec<String> = transition.args().map(|a| a.syntax().text().to_string()).collect();
    let params: Vec<ast::Param> = target_node.params().collect();
    let (sizes, values) = match existing.len() == params.len() {
        true => (&[][..], &existing[..]),
        false => existing.split_at(leading.min(existing.len())),
    };
    let mut args: Vec<String> = (0..leading).map(|i| sizes.get(i).cloned().unwrap_or_else(|| "1".into())).collect();
    for (i, param) in params.iter().enumerate() {
        args.push(values.get(i).cloned().unwrap_or_else(|| default_value(param.type_ref())));
    }
    let new_list = format!("({})", args.join(", "));
    let range = match transition.arg_list() {
        Some(list) => list.syntax().text_range(),
        None => TextRange::empty(target.syntax().text_range().end()),
    };
    Some((format!("Pass {} argument(s) to `{}`", args.len(), target.text()), (range, new_list)))
}

/// A value of a type, for an argument the user has still to write: `0`, `0.0f`, `false`,
/// `""`, a vector of zeros, or `null` (references and declared types).
fn default_value(ty: Option<ast::TypeRef>) -> String {
    let ty = crate::hir::items::type_signature(ty);
    let name = ty.builtin.or(ty.path).unwrap_or_default();
    if ty.is_ref || ty.array_dims > 0 {
        return "null".into();
    }
    match crate::hir::ty::builtin(&name) {
        Some(crate::hir::ty::Ty::Int | crate::hir::ty::Ty::UInt) => "0".into(),
        Some(crate::hir::ty::Ty::Float) => "0.0f".into(),
        Some(crate::hir::ty::Ty::Bool) => "false".into(),
        Some(crate::hir::ty::Ty::String) => "\"\"".into(),
        Some(crate::hir::ty::Ty::Vector(..)) => format!("new {name}(0)"),
        _ => "null".into(),
    }
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

/// A port's interface its component's class does not implement: add it to the class's
/// `implements` clause (in the class diagram's file), by the name the class's scope sees.
fn implement_interface(db: &dyn Db, workspace: Workspace, node: &SyntaxNode) -> Option<(String, (FileRange, String))> {
    let sema = Semantics::new(db, workspace);
    let interface = node.ancestors().find_map(ast::Path::cast)?;
    let component = node.ancestors().find_map(ast::Component::cast)?;
    let scope = Scope::at(component.syntax());
    let interface = sema.resolve(&scope, &interface.text())?;
    let class = sema.resolve(&scope, &component.class()?.text())?;
    if crate::library::is_library(db, class.file) {
        return None;
    }
    let (declaration, _) = sema.declaration(class)?;
    let declaration = ast::Class::cast(declaration)?;
    let class_scope = Scope::at(declaration.syntax());
    let simple = interface.fqn.rsplit('.').next().unwrap_or(&interface.fqn);
    let written = match sema.resolve(&class_scope, simple) {
        Some(def) if def.fqn == interface.fqn => simple.to_string(),
        _ => interface.fqn.clone(),
    };
    let edit = match declaration.implements_clause() {
        Some(clause) => (TextRange::empty(clause.syntax().text_range().end()), format!(", {written}")),
        None => {
            let after = declaration
                .extends_clause()
                .map(|c| c.syntax().clone())
                .or_else(|| declaration.template_param_list().map(|t| t.syntax().clone()))
                .map(|n| n.text_range().end())
                .or_else(|| declaration.name().map(|n| n.syntax().text_range().end()))?;
            (TextRange::empty(after), format!(" implements {written}"))
        }
    };
    let class_name = declaration.name()?.text();
    Some((format!("Implement `{written}` in `{class_name}`"), (FileRange { file: class.file, range: edit.0 }, edit.1)))
}

/// Where an import goes in the diagram around `node` and how it is written around it: on a
/// line of its own after the diagram's `{`, indented; right after the `{` when the diagram
/// goes on on that line.
fn import_position(node: &SyntaxNode, text: &str) -> Option<(TextSize, String, String)> {
    let diagram = node.ancestors().find_map(ast::Diagram::cast)?;
    let open = diagram.syntax().children_with_tokens().find(|e| e.kind() == SyntaxKind::L_CURLY)?;
    let after = usize::from(open.text_range().end());
    let line_end = next_line_start(text, after);
    if !text[after..line_end].trim().is_empty() {
        return Some(((after as u32).into(), " ".into(), String::new()));
    }
    let indent = format!("{}    ", indentation_at(text, diagram.syntax().text_range().start()));
    Some(((line_end as u32).into(), indent, "\n".into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{db::RootDatabase, text::with_edits};

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
        let text = with_edits(inputs[0].text(&db), fix.edits.iter().map(|(place, new)| (place.range, new.as_str())));
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
    fn a_typo_of_a_node_is_corrected_not_created_and_its_target_not_removed() {
        let text = "ActivityDiagram Ad()\n{\n    swimlane L\n    {\n        start S { => work; }\n        action work { => finsh; }\n        final finish;\n    }\n}\n";
        let out = apply(&[("a.gudsl", text)], "Change to `finish`");
        assert!(out[0].contains("=> finish;"), "{}", out[0]);
        assert_eq!(out[1], "[]");
        let db = RootDatabase::default();
        let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
        let ws = Workspace::new(&db, vec![file]);
        let titles: Vec<String> = quick_fixes(&db, ws, file, TextRange::up_to((text.len() as u32).into()))
            .into_iter()
            .map(|f| f.title)
            .collect();
        assert_eq!(titles, ["Change to `finish`"]);
    }

    #[test]
    fn fix_transition_arguments() {
        let out = apply(
            &[("a.gudsl", "ActivityDiagram Ad(int w)\n{\n    swimlane L\n    {\n        start S { => filter(w); }\n        calc filter(int radius) { => done; }\n        final done;\n    }\n}\n")],
            "Pass 4 argument(s)",
        );
        assert!(out[0].contains("=> filter(1, 1, 1, w);"), "{}", out[0]);
        assert_eq!(out[1], "[]");
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

    #[test]
    fn implement_a_port_interface_in_the_component_class() {
        let text = "ClassDiagram D\n{\n    public interface provider IP { public void provideX(int x); }\n    public interface processor IQ { public void processX(int x); }\n    public source Cam { }\n    public filter F implements IQ { }\n}\nComponentDiagram C\n{\n    source D.Cam { port Out ( provider X : D.IP ); }\n    filter D.F { port In ( processor X : D.IQ ); port Res ( provider Y : D.IP ); }\n}\n";
        let out = apply(&[("a.gudsl", text)], "Implement `IP` in `Cam`");
        assert!(out[0].contains("public source Cam implements IP { }"), "{}", out[0]);
        assert_eq!(out[1], "[\"E0240\"]", "the other class's warning stays");
        let out = apply(&[("a.gudsl", text)], "Implement `IP` in `F`");
        assert!(out[0].contains("public filter F implements IQ, IP { }"), "{}", out[0]);
    }

    #[test]
    fn bases_move_to_the_clause_of_their_kind_and_a_second_one_goes() {
        let text = "ClassDiagram S\n{\n    public interface I { }\n    public interface J { }\n    public class B { }\n    public class C extends B, I implements J { }\n    public class D implements B { }\n    public class E implements J, S.J { }\n}\n";
        let out = apply(&[("a.gudsl", text)], "Move `I` to `implements`");
        assert!(out[0].contains("public class C extends B implements J, I { }"), "{}", out[0]);
        let out = apply(&[("a.gudsl", text)], "Move `B` to `extends`");
        assert!(out[0].contains("public class D extends B { }"), "{}", out[0]);
        let out = apply(&[("a.gudsl", text)], "Remove the second `S.J`");
        assert!(out[0].contains("public class E implements J { }"), "{}", out[0]);
        assert_eq!(out[1], "[\"E0230\", \"E0230\"]", "the other two stay");
    }

    #[test]
    fn no_base_fix_where_no_single_edit_is_right() {
        let text = "ClassDiagram S\n{\n    public class B { }\n    public enum Colour { Red }\n    public interface I extends B { }\n    public class P extends Colour { }\n}\n";
        let db = RootDatabase::default();
        let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
        let ws = Workspace::new(&db, vec![file]);
        let codes: Vec<&str> = file_diagnostics(&db, ws, file).iter().map(|d| d.code.as_str()).collect();
        assert_eq!(codes, ["E0230", "E0230"]);
        assert!(quick_fixes(&db, ws, file, TextRange::up_to((text.len() as u32).into())).is_empty());
    }

    /// Every fix offered for every diagnostic of every `err_` golden case, applied: the
    /// diagnostic it targets is gone and no problem (error or warning) appears that was not
    /// there before.
    #[test]
    fn every_fix_of_every_golden_case_removes_its_diagnostic_and_adds_no_error() {
        use std::collections::BTreeMap;
        type Found = BTreeMap<(String, &'static str, String), usize>;
        let check = |files: &[(String, String)]| -> (RootDatabase, Workspace, Vec<SourceFile>, Found) {
            let db = RootDatabase::default();
            let inputs: Vec<SourceFile> =
                files.iter().map(|(p, t)| SourceFile::new(&db, p.clone(), t.clone())).collect();
            let library = crate::library::library_files(&db);
            let ws = Workspace::new(&db, library.into_iter().chain(inputs.iter().copied()).collect());
            let mut found = Found::new();
            for &file in &inputs {
                for d in file_diagnostics(&db, ws, file) {
                    *found.entry((file.path(&db).clone(), d.code.as_str(), d.message.clone())).or_default() += 1;
                }
            }
            (db, ws, inputs, found)
        };
        let mut failures = Vec::new();
        let mut applied = 0;
        for case in crate::hir::golden::cases() {
            let name = case.file_stem().unwrap().to_string_lossy().into_owned();
            if !name.starts_with("err_") {
                continue;
            }
            let files = crate::hir::golden::split_fixture(&std::fs::read_to_string(&case).unwrap());
            let (db, ws, inputs, before) = check(&files);
            for (index, &file) in inputs.iter().enumerate() {
                for diagnostic in file_diagnostics(&db, ws, file) {
                    let target = (file.path(&db).clone(), diagnostic.code.as_str(), diagnostic.message.clone());
                    for fix in quick_fixes(&db, ws, file, diagnostic.range)
                        .into_iter()
                        .filter(|f| f.code == diagnostic.code && f.diagnostic_range == diagnostic.range)
                    {
                        applied += 1;
                        let mut fixed = files.clone();
                        let at = |file: SourceFile| inputs.iter().position(|f| *f == file).unwrap_or(index);
                        for (k, (_, text)) in fixed.iter_mut().enumerate() {
                            let edits = fix.edits.iter().filter(|(place, _)| at(place.file) == k);
                            *text = with_edits(text, edits.map(|(place, new)| (place.range, new.as_str())));
                        }
                        let (_, _, _, after) = check(&fixed);
                        let still = after.get(&target).copied().unwrap_or(0);
                        if still >= before.get(&target).copied().unwrap_or(0) && before.contains_key(&target) {
                            failures.push(format!("{name}: `{}` leaves {target:?}", fix.title));
                        }
                        for (key, count) in &after {
                            if *count > before.get(key).copied().unwrap_or(0) {
                                failures.push(format!("{name}: `{}` adds {key:?}", fix.title));
                            }
                        }
                    }
                }
            }
        }
        assert!(applied >= 10, "only {applied} fixes applied");
        assert!(failures.is_empty(), "{}", failures.join("\n"));
    }
}
