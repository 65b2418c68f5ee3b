//! Statements of the expression language lowered for the host: declarations, expressions,
//! `if`, the three loops (`loop (c)`, `do … loop (c)`, `for (init : step : test)`),
//! `switch` (each case ends at the next, as in the generated device code), `loopwindow2D/3D`,
//! `return` (leaves the node; its transitions follow), `break`, `continue`.

use std::collections::HashMap;

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::Ty,
};

use super::Lowering;
use crate::run::{
    ir::{Arith, BinOp, CmpOp, Conv, Expr, Place, Stmt},
    value::Constant,
};

impl Lowering<'_, '_> {
    /// Statements in a scope of their own.
    pub(super) fn block(&mut self, statements: &[ast::Stmt]) -> Vec<Stmt> {
        self.scopes.push(HashMap::new());
        let out = statements.iter().filter_map(|s| self.statement(s)).collect();
        self.scopes.pop();
        out
    }

    fn nested(&mut self, stmt: Option<ast::Stmt>) -> Vec<Stmt> {
        match stmt {
            Some(ast::Stmt::Block(block)) => self.block(&block.statements().collect::<Vec<_>>()),
            Some(other) => self.block(&[other]),
            None => Vec::new(),
        }
    }

    fn statement(&mut self, stmt: &ast::Stmt) -> Option<Stmt> {
        Some(match stmt {
            ast::Stmt::Block(block) => Stmt::Block(self.block(&block.statements().collect::<Vec<_>>())),
            ast::Stmt::VarDecl(decl) => self.var_decl(decl)?,
            ast::Stmt::ExprStmt(expr) => Stmt::Expr(self.expr(&expr.expr()?)),
            ast::Stmt::EmptyStmt(_) => return None,
            ast::Stmt::IfStmt(stmt) => {
                let condition = match stmt.condition() {
                    Some(c) => self.condition(&c),
                    None => self.unsupported(stmt.syntax(), "an `if` without a condition"),
                };
                let then = self.nested(stmt.then_branch());
                let other = self.nested(stmt.else_branch());
                Stmt::If(condition, then, other)
            }
            ast::Stmt::LoopStmt(stmt) => {
                let test = stmt.condition().map(|c| self.condition(&c));
                Stmt::Loop { test, body: self.nested(stmt.body()), step: Vec::new(), test_after: false }
            }
            ast::Stmt::DoLoopStmt(stmt) => {
                let test = stmt.condition().map(|c| self.condition(&c));
                Stmt::Loop { test, body: self.nested(stmt.body()), step: Vec::new(), test_after: true }
            }
            ast::Stmt::ForStmt(stmt) => self.for_loop(stmt),
            ast::Stmt::SwitchStmt(stmt) => self.switch(stmt),
            ast::Stmt::ReturnStmt(stmt) => {
                if let Some(value) = stmt.value() {
                    self.error(value.syntax(), "a node of a run returns no value");
                }
                Stmt::Return
            }
            ast::Stmt::BreakStmt(_) => Stmt::Break,
            ast::Stmt::ContinueStmt(_) => Stmt::Continue,
            ast::Stmt::LoopWindowStmt(window) => self.window(window),
        })
    }

    fn var_decl(&mut self, decl: &ast::VarDecl) -> Option<Stmt> {
        let name = decl.name()?.text();
        let ty = self.types.locals.get(&name).cloned().unwrap_or(Ty::Unknown);
        let type_ref = decl.type_ref();
        // The initialiser sees the names declared before, not this one.
        let value = match decl.initializer() {
            Some(value) => self.converted(&value, &ty, type_ref.as_ref()),
            None => self.zero(&ty, decl.syntax()),
        };
        let slot = self.declare(&name, &ty, type_ref.as_ref());
        Some(Stmt::Declare(slot, value))
    }

    /// A part of a loop header or `for`: a declaration or an expression.
    pub(super) fn loop_part(&mut self, part: &ast::LoopPart) -> Stmt {
        match part {
            ast::LoopPart::Decl(decl) => self.var_decl(decl).unwrap_or(Stmt::Block(Vec::new())),
            ast::LoopPart::Expr(expr) => Stmt::Expr(self.expr(expr)),
        }
    }

    pub(super) fn loop_test(&mut self, part: &ast::LoopPart) -> Option<Expr> {
        match part {
            ast::LoopPart::Expr(test) => Some(self.condition(test)),
            ast::LoopPart::Decl(decl) => Some(self.unsupported(decl.syntax(), "a declaration as a loop test")),
        }
    }

    /// `for (init : step : test) body`; a numeric step (`for (i = 0 : 1 : i < n)`) is added
    /// to the variable the first section sets.
    fn for_loop(&mut self, stmt: &ast::ForStmt) -> Stmt {
        let sections = stmt.sections();
        let [init, step, test] = &sections[..] else {
            self.error(stmt.syntax(), "a `for` needs `init : step : test`");
            return Stmt::Block(Vec::new());
        };
        self.scopes.push(HashMap::new());
        let variable = match init {
            ast::LoopPart::Decl(decl) => decl.name().map(|n| n.text()),
            ast::LoopPart::Expr(ast::Expr::BinExpr(bin)) => match bin.lhs() {
                Some(ast::Expr::NameExpr(name)) => name.name_ref().map(|n| n.text()),
                _ => None,
            },
            ast::LoopPart::Expr(_) => None,
        };
        let init = self.loop_part(init);
        let step = match step {
            ast::LoopPart::Expr(
                expr @ (ast::Expr::BinExpr(_) | ast::Expr::PostfixExpr(_) | ast::Expr::PrefixExpr(_)),
            ) if !matches!(expr, ast::Expr::PrefixExpr(p) if p.op().is_some_and(|t| t.text() == "-")) => {
                Stmt::Expr(self.expr(expr))
            }
            ast::LoopPart::Expr(amount) => match variable.and_then(|name| self.lookup(&name).cloned()) {
                Some(local) => {
                    let arith = match local.conv {
                        Conv::UInt => Arith::UInt,
                        Conv::Float => Arith::Float,
                        _ => Arith::Int,
                    };
                    let span = self.span(amount.syntax());
                    let amount = self.converted_to(amount, conv_of_arith(arith));
                    let place = Box::new(Place::Var(local.slot, local.conv));
                    Stmt::Expr(Expr::Update(place, BinOp::Add, arith, Box::new(amount), false, span))
                }
                None => Stmt::Expr(
                    self.unsupported(amount.syntax(), "a numeric step needs a loop variable in the first section"),
                ),
            },
            ast::LoopPart::Decl(decl) => {
                Stmt::Expr(self.unsupported(decl.syntax(), "a declaration as the step of a `for`"))
            }
        };
        let test = self.loop_test(test);
        let body = self.nested(stmt.body());
        self.scopes.pop();
        Stmt::Block(vec![init, Stmt::Loop { test, body, step: vec![step], test_after: false }])
    }

    /// `switch v: { case 1: …; default: … }`: integer cases; each ends where the next begins.
    fn switch(&mut self, stmt: &ast::SwitchStmt) -> Stmt {
        let scrutinee = match stmt.scrutinee() {
            Some(s) => self.converted_to(&s, Conv::Int),
            None => self.unsupported(stmt.syntax(), "a `switch` without a value"),
        };
        let mut cases = Vec::new();
        let mut default = Vec::new();
        for case in stmt.cases() {
            let body = self.block(&case.statements().collect::<Vec<_>>());
            if case.is_default() {
                default = body;
                continue;
            }
            let label = case.label().map(|l| self.converted_to(&l, Conv::Int));
            match label {
                Some(Expr::Const(Constant::Int(value))) => cases.push((value, body)),
                Some(Expr::Negate(_, inner)) if matches!(*inner, Expr::Const(Constant::Int(_))) => {
                    let Expr::Const(Constant::Int(value)) = *inner else { unreachable!("matched above") };
                    cases.push((value.wrapping_neg(), body))
                }
                _ => self.error(case.syntax(), "a case label is an integer or an enum constant"),
            }
        }
        Stmt::Switch(scrutinee, cases, default)
    }

    /// `loopwindow2D(u = -r : r, v = -r : r) { … }`: a loop per dimension, the first
    /// outermost, each variable from its start to its end inclusive.
    fn window(&mut self, window: &ast::LoopWindowStmt) -> Stmt {
        self.scopes.push(HashMap::new());
        let mut levels = Vec::new();
        for range in window.ranges() {
            let Some((name, first, last)) = range.bounds() else {
                self.error(range.syntax(), "a window range is `name = start : end`");
                continue;
            };
            let first = self.converted_to(&first, Conv::Int);
            let last = self.converted_to(&last, Conv::Int);
            let slot = self.declare(&name, &Ty::Int, None);
            let span = self.span(range.syntax());
            let test = Expr::Compare(CmpOp::Le, Arith::Int, Box::new(Expr::Var(slot)), Box::new(last));
            let one = Box::new(Expr::Const(Constant::Int(1)));
            let step = Expr::Update(Box::new(Place::Var(slot, Conv::Int)), BinOp::Add, Arith::Int, one, false, span);
            levels.push((Stmt::Declare(slot, first), test, step));
        }
        let mut body = self.block(&window.body().into_iter().flat_map(|b| b.statements()).collect::<Vec<_>>());
        for (init, test, step) in levels.into_iter().rev() {
            body = vec![init, Stmt::Loop { test: Some(test), body, step: vec![Stmt::Expr(step)], test_after: false }];
        }
        self.scopes.pop();
        Stmt::Block(body)
    }
}

/// The arithmetic values of type `ty` are computed in.
pub(super) fn arith(ty: &Ty) -> Arith {
    match ty.dereferenced() {
        Ty::Float => Arith::Float,
        Ty::UInt => Arith::UInt,
        _ => Arith::Int,
    }
}

pub(super) fn conv_of_arith(arith: Arith) -> Conv {
    match arith {
        Arith::Int => Conv::Int,
        Arith::UInt => Conv::UInt,
        Arith::Float => Conv::Float,
    }
}
