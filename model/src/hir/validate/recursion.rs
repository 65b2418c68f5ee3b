//! Recursion in device code: OpenCL C has none (OpenCL 1.2, 6.9: "Recursion is not
//! supported"), nor has WGSL. A method of an `OpenCL` class that reaches itself — through the
//! class's methods it calls (by name and number of arguments) and the diagrams it calls with
//! `call behavior` — is reported at the call that starts the cycle, called or not.

use std::collections::HashSet;

use super::{Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasName},
    hir::definitions::{DefKind, Definition},
    syntax::{SyntaxNode, TextRange},
};

/// A function of device code: a method of the class (by name and arity) or a diagram.
#[derive(Clone, PartialEq, Eq, Hash)]
enum Function {
    Method(String, usize),
    Diagram(String),
}

impl Function {
    fn describe(&self) -> String {
        match self {
            Function::Method(name, _) => name.clone(),
            Function::Diagram(fqn) => format!("call behavior {fqn}"),
        }
    }
}

/// The methods of the OpenCL class `fqn` (declared by `decl`) that call themselves.
pub(super) fn check(ctx: &mut Ctx, scope: &Scope, fqn: &str, decl: &ast::TypeDecl) {
    let bodies: Vec<(Function, ast::Block)> = decl
        .members()
        .filter_map(|member| match member {
            ast::Member::Method(m) => Some((Function::Method(m.name()?.text(), m.params().count()), m.body()?)),
            _ => None,
        })
        .collect();
    let graph = Graph { ctx, scope, class: fqn, bodies: &bodies };
    let mut reported: HashSet<Function> = HashSet::new();
    let mut found = Vec::new();
    for (start, body) in &bodies {
        if reported.contains(start) {
            continue;
        }
        for (callee, range) in graph.calls(body.syntax(), scope) {
            if let Some(path) = graph.path_back(&callee, start) {
                reported.extend(path.iter().cloned());
                found.push((start.clone(), path, range));
                break;
            }
        }
    }
    for (start, path, range) in found {
        let cycle: Vec<String> = std::iter::once(&start).chain(&path).map(Function::describe).collect();
        ctx.sink.error(
            DiagnosticCode::DeviceRecursion,
            range,
            format!(
                "`{}` calls itself ({}): device code has no recursion (OpenCL C 6.9, WGSL); write it as a loop",
                start.describe(),
                cycle.join(" → ")
            ),
        );
    }
}

/// The calls between the class's methods and the diagrams they call.
struct Graph<'a, 'db> {
    ctx: &'a Ctx<'db>,
    scope: &'a Scope,
    class: &'a str,
    bodies: &'a [(Function, ast::Block)],
}

impl Graph<'_, '_> {
    /// The path from `from` to `target` (ending with `target`), if the calls lead there.
    fn path_back(&self, from: &Function, target: &Function) -> Option<Vec<Function>> {
        let mut seen: HashSet<Function> = HashSet::new();
        let mut stack: Vec<(Function, Vec<Function>)> = vec![(from.clone(), vec![from.clone()])];
        while let Some((at, path)) = stack.pop() {
            if &at == target {
                return Some(path);
            }
            if !seen.insert(at.clone()) {
                continue;
            }
            for (next, _) in self.callees(&at) {
                let mut longer = path.clone();
                longer.push(next.clone());
                stack.push((next, longer));
            }
        }
        None
    }

    /// What `function` calls: the methods of the class with a body and the diagrams.
    fn callees(&self, function: &Function) -> Vec<(Function, TextRange)> {
        match function {
            Function::Method(..) => match self.bodies.iter().find(|(f, _)| f == function) {
                Some((_, body)) => self.calls(body.syntax(), self.scope),
                None => Vec::new(),
            },
            Function::Diagram(fqn) => {
                let Some(def) = self.ctx.sema.definition(fqn) else { return Vec::new() };
                let Some((node, _)) = self.ctx.sema.declaration(def) else { return Vec::new() };
                let owned = self.owned_by_class(def);
                let scope = Scope::of(def);
                self.calls(&node, &scope)
                    .into_iter()
                    .filter(|(f, _)| owned || matches!(f, Function::Diagram(_)))
                    .collect()
            }
        }
    }

    /// Whether a diagram's unqualified calls are the class's: it or a swimlane is owned by it.
    fn owned_by_class(&self, def: &Definition) -> bool {
        self.ctx.sema.activity_owners(def).iter().any(|owner| owner.fqn == self.class)
    }

    /// The calls written in `node` (read in `scope`) of the class's methods and of diagrams.
    fn calls(&self, node: &SyntaxNode, scope: &Scope) -> Vec<(Function, TextRange)> {
        let names_class = |text: String| {
            let text: String = text.split_whitespace().collect();
            self.ctx.sema.resolve(scope, &text).is_some_and(|d| d.fqn == self.class)
        };
        let mut out = Vec::new();
        for descendant in node.descendants() {
            if let Some(call) = ast::CallExpr::cast(descendant.clone()) {
                let arity = call.args().count();
                let name = match call.callee() {
                    Some(ast::Expr::NameExpr(n)) => n.name_ref().map(|n| n.text()),
                    Some(ast::Expr::MemberExpr(m)) if matches!(m.receiver(), Some(ast::Expr::ThisExpr(_))) => {
                        m.member().map(|n| n.text())
                    }
                    Some(ast::Expr::ScopeExpr(s))
                        if s.scope().is_some_and(|c| names_class(c.syntax().text().to_string())) =>
                    {
                        s.member().map(|n| n.text())
                    }
                    _ => None,
                };
                if let Some(name) = name {
                    out.push((Function::Method(name, arity), call.syntax().text_range()));
                }
            } else if let Some(call) = ast::CallMethodExpr::cast(descendant.clone()) {
                let (Some(class), Some(method)) = (call.class(), call.method()) else { continue };
                if names_class(class.text()) {
                    out.push((Function::Method(method.text(), call.args().count()), call.syntax().text_range()));
                }
            } else if let Some(call) = ast::CallBehaviorExpr::cast(descendant) {
                let Some(path) = call.behavior() else { continue };
                if let Some(def) = self.ctx.sema.resolve(scope, &path.text()) {
                    if matches!(def.kind, DefKind::Activity(_)) {
                        out.push((Function::Diagram(def.fqn.clone()), call.syntax().text_range()));
                    }
                }
            }
        }
        out
    }
}
