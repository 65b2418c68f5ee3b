//! Statements and declarations in bodies: variable initialisers, loop headers, assignments to
//! what must not change (`const`), `return` against the method's type and the paths that end
//! without one, and the qualifiers (`const`, `read`, `write`) a declaration gives a local.

use super::InferenceCtx;
use crate::{
    ast::{self, AstNode, HasName},
    hir::{diagnostics::DiagnosticCode, ty::Ty},
    syntax::{SyntaxKind, SyntaxNode},
};

impl InferenceCtx<'_, '_> {
    /// `var int x = value;`: the value fits the variable.
    pub(super) fn var_decl(&mut self, decl: &ast::VarDecl) {
        if let (Some(init), Some(name)) = (decl.initializer(), decl.name()) {
            let target = self.locals.get(&name.text()).cloned().unwrap_or(Ty::Unknown);
            let value = self.infer(&init);
            self.expect_assignable(&value, &target, init.syntax(), &format!("`{}`", name.text()));
        }
    }

    /// A loop or loopWindow node's header, `(setup; test; increment)` or `(test)`: the test
    /// (each of a loopWindow's tests) is boolean, the rest is typed.
    pub fn check_loop_header(&mut self, header: &ast::LoopHeader) {
        let sections: Vec<ast::LoopSection> = header.sections().collect();
        let test = usize::from(sections.len() > 1);
        for (i, section) in sections.iter().enumerate() {
            for part in section.parts() {
                match part {
                    ast::LoopPart::Expr(e) if i == test => self.expect_bool(&e, "a loop test"),
                    ast::LoopPart::Expr(e) => drop(self.infer(&e)),
                    ast::LoopPart::Decl(d) => self.var_decl(&d),
                }
            }
        }
    }

    /// An assignment's (or `++`'s) target must not be `const`: a local, a parameter or a field.
    pub(super) fn expect_mutable(&mut self, target: &ast::Expr) {
        let (name, field_of) = match target {
            ast::Expr::NameExpr(n) => match n.name_ref() {
                Some(name) if self.locals.contains_key(&name.text()) => {
                    if self.constants.contains(&name.text()) {
                        self.sink.error(
                            DiagnosticCode::AssignToConst,
                            target.syntax().text_range(),
                            format!("`{}` is `const`: it cannot be assigned after its declaration", name.text()),
                        );
                    }
                    return;
                }
                Some(name) => (name, self.owner.map(|o| o.fqn.clone())),
                None => return,
            },
            ast::Expr::MemberExpr(m) => {
                let receiver = m.receiver().map_or(Ty::Unknown, |r| self.type_of_silently(&r));
                match (m.member(), receiver.dereferenced()) {
                    (Some(name), Ty::Named(fqn)) => (name, Some(fqn.clone())),
                    _ => return,
                }
            }
            _ => return,
        };
        let Some(fqn) = field_of else { return };
        if let Some(declaring) = self.sema.const_field(&fqn, &name.text()) {
            self.sink.error(
                DiagnosticCode::AssignToConst,
                target.syntax().text_range(),
                format!("the field `{declaring}.{}` is `const`: it cannot be assigned", name.text()),
            );
        }
    }

    /// The type of an expression already checked once (its problems are not reported again).
    pub(super) fn type_of_silently(&mut self, expr: &ast::Expr) -> Ty {
        let reported = std::mem::take(self.sink);
        let ty = self.infer(expr);
        *self.sink = reported;
        ty
    }

    /// `return` and `return value;` against the method's return type.
    pub(super) fn return_stmt(&mut self, stmt: &SyntaxNode) {
        let value = stmt.children().find_map(ast::Expr::cast);
        let value_ty = value.as_ref().map(|v| self.infer(v));
        let Some((method, expected)) = self.returns.clone() else { return };
        let sema = self.sema;
        let problem = match (&expected, value_ty) {
            (Ty::Void, Some(_)) => Some(format!("`{method}` returns `void`: this `return` must not give a value")),
            (Ty::Void | Ty::Unknown, None) => None,
            (_, None) => Some(format!("`{method}` returns `{expected}`: give this `return` a value")),
            (_, Some(ty)) if !ty.assignable_to(&expected, &mut |a, b| sema.is_subtype(a, b)) => {
                Some(format!("`{method}` returns `{expected}`, but this is `{ty}`"))
            }
            _ => None,
        };
        if let Some(message) = problem {
            let range = value.map_or_else(|| stmt.text_range(), |v| v.syntax().text_range());
            self.sink.error(DiagnosticCode::ReturnType, range, message);
        }
    }

    /// A method body that ends with `call behavior X(…)` instead of `return`: `X`'s result must
    /// be one the method returns (E0234), and a diagram that returns nothing leaves the method
    /// without a value (E0235).
    pub fn check_implementing_behavior(&mut self, call: &ast::CallBehaviorExpr) {
        let Some((method, expected)) = self.returns.clone() else { return };
        let sema = self.sema;
        let result = self.behavior_result(call);
        let behavior = call.behavior().map(|p| p.text()).unwrap_or_default();
        let (code, message) = match result {
            Ty::Unknown => return,
            Ty::Void => (
                DiagnosticCode::MissingReturn,
                format!("`{method}` returns `{expected}`, but `{behavior}`, which its body ends with, returns no value: give its final node one (`final f return value;`) or end the body with `return`"),
            ),
            ty if !ty.assignable_to(&expected, &mut |a, b| sema.is_subtype(a, b)) => (
                DiagnosticCode::ReturnType,
                format!("`{method}` returns `{expected}`, but `{behavior}`, which implements it, returns `{ty}`"),
            ),
            _ => return,
        };
        self.sink.error(code, call.syntax().text_range(), message);
    }

    /// `target = value` (and `+=`, …): the value must fit the target; a reference target
    /// takes a value of what it refers to.
    pub(super) fn assignment(&mut self, bin: &ast::BinExpr, target: Ty, value: Ty) -> Ty {
        if let Some(lhs) = bin.lhs() {
            self.expect_mutable(&lhs);
        }
        if bin.op().is_some_and(|t| t.kind() == SyntaxKind::EQ) {
            if let Some(rhs) = bin.rhs() {
                let what = bin.lhs().map_or("the target".to_string(), |l| format!("`{}`", l.syntax().text()));
                self.expect_assignable(&value, &target, rhs.syntax(), &what);
            }
        }
        target
    }
}

/// Whether the declaration a type is written in is `const` (`const int x = 1;`, a `const`
/// parameter).
pub(super) fn declared_const(ty: &ast::TypeRef) -> bool {
    let Some(declaration) = ty.syntax().parent() else { return false };
    if let Some(decl) = ast::VarDecl::cast(declaration.clone()) {
        return decl.is_const();
    }
    declaration.children().find_map(ast::Modifiers::cast).is_some_and(|m| m.has(SyntaxKind::CONST_KW))
}

/// `shared` among the qualifiers of the declaration a type is written in: work-group memory,
/// indexed as an array of the type (`shared int scratch` … `scratch[localId]`, Listing 32).
pub(super) fn declared_shared(ty: &ast::TypeRef) -> bool {
    let modifiers = ty.syntax().parent().and_then(|p| p.children().find_map(ast::Modifiers::cast));
    modifiers.is_some_and(|m| m.has(SyntaxKind::SHARED_KW))
}

/// `read` or `write` (not both) among the qualifiers of the declaration a type is written in.
pub(super) fn declared_access(ty: &ast::TypeRef) -> Option<SyntaxKind> {
    let modifiers = ty.syntax().parent()?.children().find_map(ast::Modifiers::cast)?;
    match (modifiers.has(SyntaxKind::READ_KW), modifiers.has(SyntaxKind::WRITE_KW)) {
        (true, false) => Some(SyntaxKind::READ_KW),
        (false, true) => Some(SyntaxKind::WRITE_KW),
        _ => None,
    }
}

/// Whether a body (a block) ends in `return` on every path: a `return`, a block that does, or
/// an `if` whose both branches do.
pub fn returns_on_every_path(block: &SyntaxNode) -> bool {
    block.children().any(|stmt| match stmt.kind() {
        SyntaxKind::RETURN_STMT => true,
        SyntaxKind::BLOCK => returns_on_every_path(&stmt),
        SyntaxKind::IF_STMT => {
            let if_stmt = ast::IfStmt::cast(stmt).expect("kind checked");
            let branch_returns = |branch: Option<ast::Stmt>| {
                branch.is_some_and(|b| match b.syntax().kind() {
                    SyntaxKind::RETURN_STMT => true,
                    _ => returns_on_every_path(b.syntax()),
                })
            };
            branch_returns(if_stmt.then_branch()) && branch_returns(if_stmt.else_branch())
        }
        _ => false,
    })
}

/// The `call behavior X(…)` a method's body ends with: the dissertation's way of saying that
/// the diagram `X` implements the method (Listing 36's `bindBetterValueAndReturnNumber`), whose
/// result — the value of `X`'s final node — is then the method's result.
pub fn implementing_behavior(body: &ast::Block) -> Option<ast::CallBehaviorExpr> {
    let last = body.syntax().children().filter(|n| ast::Stmt::can_cast(n.kind())).last()?;
    match last.kind() {
        SyntaxKind::EXPR_STMT => match last.children().find_map(ast::Expr::cast)? {
            ast::Expr::CallBehaviorExpr(call) => Some(call),
            _ => None,
        },
        _ => None,
    }
}

/// The `break`s in `body` outside any loop or `switch` of it and the `continue`s outside any
/// loop of it, with a message; `in_loop` when the body itself runs in a loop (a loop or
/// loopWindow node's), where both are in place; `body_is` "the node" or "the method".
pub fn misplaced_jumps(body: &SyntaxNode, in_loop: bool, body_is: &str) -> Vec<(crate::syntax::TextRange, String)> {
    use SyntaxKind::*;
    let mut out = Vec::new();
    for jump in body.descendants().filter(|n| matches!(n.kind(), BREAK_STMT | CONTINUE_STMT)) {
        let enclosing: Vec<SyntaxKind> = jump.ancestors().skip(1).take_while(|n| n != body).map(|n| n.kind()).collect();
        let in_a_loop =
            in_loop || enclosing.iter().any(|k| matches!(k, LOOP_STMT | DO_LOOP_STMT | FOR_STMT | LOOP_WINDOW_STMT));
        let message = match jump.kind() {
            BREAK_STMT if !in_a_loop && !enclosing.contains(&SWITCH_STMT) => "`break` leaves a loop or a `switch`",
            CONTINUE_STMT if !in_a_loop => "`continue` starts a loop's next round",
            _ => continue,
        };
        out.push((jump.text_range(), format!("{message}, and there is none here: `return;` leaves {body_is}")));
    }
    out
}
