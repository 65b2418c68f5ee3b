//! Statements and declarations in bodies: variable initialisers, loop headers, assignments to
//! what must not change (`const`), `return` against the method's type and the paths that end
//! without one, and the qualifiers (`const`, `read`, `write`) a declaration gives a local.

use super::InferenceCtx;
use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{
        diagnostics::{excerpt, DiagnosticCode},
        ty::Ty,
    },
    syntax::{SyntaxKind, SyntaxNode},
};

impl InferenceCtx<'_, '_> {
    /// `var int x = value;`: the value fits the variable.
    pub(super) fn var_decl(&mut self, decl: &ast::VarDecl) {
        self.shared_local(decl);
        if let (Some(init), Some(name)) = (decl.initializer(), decl.name()) {
            let target = self.locals.get(&name.text()).cloned().unwrap_or(Ty::Unknown);
            let value = self.infer(&init);
            self.expect_assignable(&value, &target, init.syntax(), &format!("`{}`", name.text()));
        }
    }

    /// `var shared int x`: work-group memory exists only in device code, a body whose owner
    /// implements `OpenCL` (Sec. 10.3.2.3); host code has no work-group to share it with.
    fn shared_local(&mut self, decl: &ast::VarDecl) {
        if !decl.has_modifier(SyntaxKind::SHARED_KW) || self.owner.is_some_and(|o| self.sema.is_gpu_class(o)) {
            return;
        }
        let range = decl.name().map_or_else(|| decl.syntax().text_range(), |n| n.syntax().text_range());
        let place = match self.owner {
            Some(owner) => format!("`{}` does not implement `OpenCL`", owner.fqn),
            None => "this body has no owner class".to_string(),
        };
        self.sink.error(
            DiagnosticCode::SharedOutsideGpuClass,
            range,
            format!("`shared` (work-group) memory exists only in device code, and {place}: drop `shared`"),
        );
    }

    /// `switch (x) { case a: … }`: each label fits what is switched on, and none is written
    /// twice (as in C: the labels of one switch are distinct constants).
    pub(super) fn switch(&mut self, switch: &ast::SwitchStmt) {
        let on = switch.scrutinee().map_or(Ty::Unknown, |e| self.infer(&e));
        let mut seen: std::collections::HashSet<String> = std::collections::HashSet::new();
        for label in switch.cases().filter_map(|case| case.label()) {
            let ty = self.infer(&label);
            let sema = self.sema;
            if !ty.assignable_to(&on, &mut |a, b| sema.is_subtype(a, b)) {
                self.sink.error(
                    DiagnosticCode::TypeMismatch,
                    label.syntax().text_range(),
                    format!("this `case` is `{ty}`, but the `switch` is on `{on}`"),
                );
            }
            let text = excerpt(label.syntax());
            if !seen.insert(text.clone()) {
                self.sink.error(
                    DiagnosticCode::DuplicateName,
                    label.syntax().text_range(),
                    format!("`case {text}` appears twice in this `switch`: the second is never taken"),
                );
            }
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
            other => {
                self.expect_lvalue(other, "assigned");
                return;
            }
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

    /// What is assigned or taken `ref` of is memory, as in C (an lvalue): a variable, a
    /// parameter, an element, a field, `++x`, or a call that returns a reference.
    pub(super) fn expect_lvalue(&mut self, target: &ast::Expr, done: &str) {
        let lvalue = match target {
            ast::Expr::NameExpr(_) | ast::Expr::IndexExpr(_) | ast::Expr::MemberExpr(_) | ast::Expr::ScopeExpr(_) => {
                true
            }
            ast::Expr::ParenExpr(p) => match p.expr() {
                Some(inner) => return self.expect_lvalue(&inner, done),
                None => true,
            },
            ast::Expr::CallExpr(_) => matches!(self.type_of_silently(target), Ty::Ref { .. } | Ty::Unknown),
            // `++x` and `--x` are the variable itself (C++; `--(--y)` is one).
            ast::Expr::PrefixExpr(p) => {
                p.op().is_some_and(|t| matches!(t.kind(), SyntaxKind::PLUS2 | SyntaxKind::MINUS2))
            }
            _ => false,
        };
        if !lvalue {
            self.sink.error(
                DiagnosticCode::NotAssignable,
                target.syntax().text_range(),
                format!(
                    "`{}` is a value, not a variable, element or field: it cannot be {done}",
                    excerpt(target.syntax())
                ),
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
        let value = ast::support::child::<ast::Expr>(stmt);
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
                let what = bin.lhs().map_or("the target".to_string(), |l| format!("`{}`", excerpt(l.syntax())));
                self.expect_assignable(&value, &target, rhs.syntax(), &what);
            }
        }
        target
    }
}

/// The qualifiers of the declaration a type is written in that decide how its name may be used.
#[derive(Debug, Default)]
pub(super) struct DeclQualifiers {
    /// `const int x = 1;`, a `const` parameter: never assigned again.
    pub(super) is_const: bool,
    /// `shared int scratch`: work-group memory, indexed as an array of the type (Listing 32).
    pub(super) is_shared: bool,
    /// `read` or `write` (not both).
    pub(super) access: Option<SyntaxKind>,
}

impl DeclQualifiers {
    /// Read from the declaration's modifiers (`global ref`, `shared`, `read`), looked up once.
    pub(super) fn of(ty: &ast::TypeRef) -> DeclQualifiers {
        let Some(declaration) = ty.syntax().parent() else { return DeclQualifiers::default() };
        let modifiers = ast::support::child::<ast::Modifiers>(&declaration);
        let has = |keyword| modifiers.as_ref().is_some_and(|m| m.has(keyword));
        let const_keyword = ast::VarDecl::cast(declaration.clone()).is_some_and(|d| d.const_token().is_some());
        let access = match (has(SyntaxKind::READ_KW), has(SyntaxKind::WRITE_KW)) {
            (true, false) => Some(SyntaxKind::READ_KW),
            (false, true) => Some(SyntaxKind::WRITE_KW),
            _ => None,
        };
        DeclQualifiers {
            is_const: const_keyword || has(SyntaxKind::CONST_KW),
            is_shared: has(SyntaxKind::SHARED_KW),
            access,
        }
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
        SyntaxKind::EXPR_STMT => match ast::support::child::<ast::Expr>(&last)? {
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
    if !ast::owns_at_least(body, 1, |k| matches!(k, BREAK_STMT | CONTINUE_STMT)) {
        return out;
    }
    for jump in ast::own_descendants(body).filter(|n| matches!(n.kind(), BREAK_STMT | CONTINUE_STMT)) {
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
