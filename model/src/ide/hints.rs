//! Inlay hints (the parameter each transition argument fills) and signature help (the
//! signature of the node, activity diagram or method whose arguments the cursor is in).

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{DefKind, Scope, Semantics},
    syntax::{SyntaxKind, TextRange, TextSize},
};

/// A label shown before an argument.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InlayHint {
    pub offset: TextSize,
    pub label: String,
}

/// The names of what a transition's arguments fill: the work size of calc nodes, the ranges of
/// calcRange nodes, then the node's parameters.
fn transition_slots(transition: &ast::Transition) -> Option<(String, Vec<String>)> {
    let target = transition.target()?;
    let diagram = transition.syntax().ancestors().find_map(ast::ActivityDiagram::cast)?;
    let node = diagram
        .syntax()
        .descendants()
        .filter_map(ast::ActivityNode::cast)
        .find(|n| n.name().is_some_and(|name| name.text() == target.text()))?;
    let given = transition.args().count();
    let params: Vec<String> = node.params().filter_map(|p| p.name()).map(|n| n.text()).collect();
    let mut slots: Vec<String> = match node.kind() {
        ast::NodeKind::Calc => ["x", "y", "z"].map(String::from).to_vec(),
        ast::NodeKind::CalcRange => {
            let dims = given.saturating_sub(params.len()).clamp(2, 6) / 2;
            let axes = ["x", "y", "z"];
            let mut slots: Vec<String> = axes[..dims].iter().map(|a| format!("global {a}")).collect();
            slots.extend(axes[..dims].iter().map(|a| format!("local {a}")));
            slots
        }
        _ => Vec::new(),
    };
    slots.extend(params.iter().cloned());
    let signature = node
        .syntax()
        .children_with_tokens()
        .take_while(|e| e.kind() != SyntaxKind::NODE_BODY)
        .map(|e| e.to_string())
        .collect::<String>();
    Some((super::symbols::collapse_whitespace(&signature), slots))
}

/// Hints for the transition arguments in `range`.
pub fn inlay_hints(db: &dyn Db, file: SourceFile, range: TextRange) -> Vec<InlayHint> {
    let root = parse(db, file).syntax_node();
    let mut hints = Vec::new();
    for transition in root.descendants().filter_map(ast::Transition::cast) {
        if transition.syntax().text_range().intersect(range).is_none() {
            continue;
        }
        let Some((_, slots)) = transition_slots(&transition) else { continue };
        for (arg, slot) in transition.args().zip(slots) {
            // No hint where the argument already says it (`=> load(name)` for `name`).
            if arg.syntax().text() == slot.as_str() {
                continue;
            }
            hints.push(InlayHint { offset: arg.syntax().text_range().start(), label: format!("{slot}:") });
        }
    }
    hints
}

/// The signature the cursor's argument list belongs to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SignatureHelp {
    pub label: String,
    pub parameters: Vec<String>,
    pub active_parameter: usize,
}

/// Signature help inside the arguments of a transition, `call behavior`, `call C::m` or a call
/// of an owner method.
pub fn signature_help(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Option<SignatureHelp> {
    let root = parse(db, file).syntax_node();
    let token = root.token_at_offset(offset).left_biased()?;
    let list = token.parent_ancestors().find(|n| n.kind() == SyntaxKind::ARG_LIST)?;
    if offset <= list.text_range().start() {
        return None;
    }
    let active_parameter =
        list.children_with_tokens().filter(|e| e.kind() == SyntaxKind::COMMA && e.text_range().end() <= offset).count();
    let owner = list.parent()?;
    let sema = Semantics::new(db, workspace);
    let (label, parameters) = match owner.kind() {
        SyntaxKind::TRANSITION => transition_slots(&ast::Transition::cast(owner)?)?,
        SyntaxKind::CALL_BEHAVIOR_EXPR => {
            let call = ast::CallBehaviorExpr::cast(owner.clone())?;
            let def = sema.resolve(&Scope::at(&owner), &call.behavior()?.text())?;
            let DefKind::Activity(signature) = &def.kind else { return None };
            let params: Vec<String> = signature.params.iter().map(|p| p.name.clone()).collect();
            (format!("ActivityDiagram {}({})", def.fqn, params.join(", ")), params)
        }
        SyntaxKind::CALL_METHOD_EXPR => {
            let call = ast::CallMethodExpr::cast(owner.clone())?;
            let def = sema.resolve(&Scope::at(&owner), &call.class()?.text())?;
            method_signature(&sema, def, &call.method()?.text())?
        }
        SyntaxKind::CALL_EXPR => {
            let call = ast::CallExpr::cast(owner.clone())?;
            let ast::Expr::NameExpr(name) = call.callee()? else { return None };
            let owner_def = sema.owner_at(&owner)?;
            method_signature(&sema, owner_def, &name.name_ref()?.text())?
        }
        _ => return None,
    };
    Some(SignatureHelp { label, parameters, active_parameter })
}

fn method_signature(sema: &Semantics, def: &crate::hir::Definition, name: &str) -> Option<(String, Vec<String>)> {
    let (declaring, method) = sema.methods(def, name).into_iter().next()?;
    let params: Vec<String> = method.params.iter().map(|p| p.name.clone()).collect();
    Some((format!("{}.{}({})", declaring.fqn, method.name, params.join(", ")), params))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::db::RootDatabase;

    #[test]
    fn hints_for_calc_and_action_arguments() {
        let db = RootDatabase::default();
        let text = "ActivityDiagram Ad(int w) { swimlane L { start S { => filter(w, 8, 1, 5); } calc filter(int radius) { => load(\"a\"); } action load(string name) { => f; } final f; } }";
        let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
        let hints: Vec<String> =
            inlay_hints(&db, file, TextRange::up_to((text.len() as u32).into())).into_iter().map(|h| h.label).collect();
        assert_eq!(hints, ["x:", "y:", "z:", "radius:", "name:"]);
    }

    #[test]
    fn signature_help_in_transitions_and_calls() {
        let db = RootDatabase::default();
        let text = "ActivityDiagram Ad(int w), owner D.C { swimlane L { start S { => range(1, 1, 8, 1, w); } calcRange range(int n) { grow(1, 2); => f; } final f; } }";
        let defs = SourceFile::new(
            &db,
            "d.gudsl".into(),
            "ClassDiagram D { class C { public void grow(int by, int times); } }".into(),
        );
        let file = SourceFile::new(&db, "a.gudsl".into(), text.into());
        let ws = Workspace::new(&db, vec![file, defs]);
        let at = TextSize::from(text.find("8,").unwrap() as u32);
        let help = signature_help(&db, ws, file, at).unwrap();
        assert_eq!(help.parameters, ["global x", "global y", "local x", "local y", "n"]);
        assert_eq!(help.active_parameter, 2);
        let at = TextSize::from(text.find("2);").unwrap() as u32);
        let help = signature_help(&db, ws, file, at).unwrap();
        assert_eq!((help.label.as_str(), help.active_parameter), ("D.C.grow(by, times)", 1));
        assert!(signature_help(&db, ws, file, TextSize::from(0)).is_none());
    }
}
