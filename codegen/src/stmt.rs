//! Statements in WGSL: declarations, assignments (C's compound forms and conversions), `++`/`--`,
//! calls, `if`, the three loops of the expression language (`loop (c)`, `do … loop (c)`,
//! `for (init : step : test)`), `switch`, `loopwindow2D/3D`, `return`, `break`, `continue`.

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::Ty,
    syntax::SyntaxKind,
};

use crate::{
    emitter::{bare, ident, Emitter},
    types::{common, convert, value_type},
};

impl Emitter<'_> {
    pub fn statement(&mut self, stmt: &ast::Stmt) {
        match stmt {
            ast::Stmt::Block(block) => self.block("{", |e| {
                for stmt in block.statements() {
                    e.statement(&stmt);
                }
            }),
            ast::Stmt::VarDecl(decl) => self.var_decl(decl),
            ast::Stmt::ExprStmt(expr) => {
                if let Some(expr) = expr.expr() {
                    let code = self.expr_statement(&expr);
                    self.line(format!("{code};"));
                }
            }
            ast::Stmt::EmptyStmt(_) => {}
            ast::Stmt::IfStmt(stmt) => {
                let cond = match stmt.condition() {
                    Some(cond) => self.expr_as(&cond, &Ty::Bool),
                    None => self.unsupported(stmt.syntax(), "an `if` without a condition"),
                };
                self.block(format!("if {cond} {{"), |e| e.nested(stmt.then_branch()));
                if let Some(other) = stmt.else_branch() {
                    self.block("else {", |e| e.nested(Some(other)));
                }
            }
            ast::Stmt::LoopStmt(stmt) => {
                let cond = match stmt.condition() {
                    Some(cond) => self.expr_as(&cond, &Ty::Bool),
                    None => self.unsupported(stmt.syntax(), "a `loop` without a condition"),
                };
                self.breakable(format!("while {cond} {{"), |e| e.nested(stmt.body()));
            }
            ast::Stmt::DoLoopStmt(stmt) => {
                let cond = match stmt.condition() {
                    Some(cond) => self.expr_as(&cond, &Ty::Bool),
                    None => self.unsupported(stmt.syntax(), "a `do … loop` without a condition"),
                };
                self.breakable("loop {", |e| {
                    e.nested(stmt.body());
                    e.block("continuing {", |e| e.line(format!("break if !{cond};")));
                });
            }
            ast::Stmt::ForStmt(stmt) => self.for_loop(stmt),
            ast::Stmt::SwitchStmt(stmt) => self.switch(stmt),
            ast::Stmt::ReturnStmt(stmt) => match (stmt.value(), self.current_function.clone()) {
                (None, _) if self.node_exit.is_some() => self.leave_node(self.node_exit.expect("checked")),
                (None, None) => self.line("return;"),
                (None, Some((_, Ty::Void))) => self.line("return;"),
                (None, Some((_, returns))) => {
                    self.unsupported(
                        stmt.syntax(),
                        format!("the method returns a `{returns}`: `return` needs a value"),
                    );
                }
                (Some(value), Some((_, returns))) if returns != Ty::Void => {
                    let value = bare(self.expr_as(&value, &returns));
                    self.line(format!("return {value};"));
                }
                (Some(value), Some(_)) => {
                    self.unsupported(value.syntax(), "the method returns nothing (`void`)");
                }
                (Some(value), None) => {
                    self.unsupported(value.syntax(), "a kernel returns no value");
                }
            },
            ast::Stmt::BreakStmt(_) => self.line("break;"),
            ast::Stmt::ContinueStmt(_) => self.line("continue;"),
            ast::Stmt::LoopWindowStmt(window) => self.window_statement(window),
        }
    }

    /// The statements of a branch or loop body (a block's, or the one statement).
    fn nested(&mut self, stmt: Option<ast::Stmt>) {
        match stmt {
            Some(ast::Stmt::Block(block)) => {
                for stmt in block.statements() {
                    self.statement(&stmt);
                }
            }
            Some(stmt) => self.statement(&stmt),
            None => {}
        }
    }

    /// `var T x = v;` as `var x: T = v;` (`let` for a `const` one).
    pub fn var_decl(&mut self, decl: &ast::VarDecl) {
        let Some(name) = decl.name().map(|n| n.text()) else { return };
        let keyword = if decl.is_const() && decl.initializer().is_some() { "let" } else { "var" };
        if let Some(declaration) = self.declaration(keyword, &name, decl.initializer(), decl.syntax()) {
            self.line(format!("{declaration};"));
        }
    }

    /// `var name: T = value` (no `;`) for a local, variable or loop variable `name` of the
    /// current body, its value converted to its type; `None`, reported, when the type has no
    /// WGSL value type.
    pub fn declaration(
        &mut self,
        keyword: &str,
        name: &str,
        initializer: Option<ast::Expr>,
        at: &gudsl_model::syntax::SyntaxNode,
    ) -> Option<String> {
        let ty = self.types.locals.get(name).cloned().unwrap_or(Ty::Unknown);
        let Some(wgsl_ty) = value_type(&ty) else {
            self.unsupported(at, format!("`{name}` is a `{ty}`, which has no WGSL value type"));
            return None;
        };
        Some(match initializer {
            Some(value) => format!("{keyword} {}: {wgsl_ty} = {}", ident(name), bare(self.expr_as(&value, &ty))),
            None => format!("{keyword} {}: {wgsl_ty}", ident(name)),
        })
    }

    /// The first section of a `for` or loop node: a declaration or an expression statement.
    pub fn loop_init(&mut self, part: &ast::LoopPart) -> String {
        match part {
            ast::LoopPart::Decl(decl) => {
                let name = decl.name().map(|n| n.text()).unwrap_or_default();
                self.declaration("var", &name, decl.initializer(), decl.syntax()).unwrap_or_default()
            }
            ast::LoopPart::Expr(expr) => self.expr_statement(expr),
        }
    }

    /// An expression used as a statement: an assignment, `++`/`--`, or a call.
    pub fn expr_statement(&mut self, expr: &ast::Expr) -> String {
        match expr {
            ast::Expr::BinExpr(bin) if bin.is_assignment() => self.assignment(bin),
            ast::Expr::PostfixExpr(postfix) => match postfix.operand() {
                Some(operand) => {
                    let op = postfix.op().map(|t| t.text().to_string()).unwrap_or_default();
                    self.step(&operand, &op)
                }
                None => self.unsupported(expr.syntax(), "an incomplete `++`/`--`"),
            },
            ast::Expr::PrefixExpr(prefix)
                if prefix.op().is_some_and(|t| matches!(t.kind(), SyntaxKind::PLUS2 | SyntaxKind::MINUS2)) =>
            {
                let op = prefix.op().map(|t| t.text().to_string()).unwrap_or_default();
                match prefix.operand() {
                    Some(operand) => self.step(&operand, &op),
                    None => self.unsupported(expr.syntax(), "an incomplete `++`/`--`"),
                }
            }
            ast::Expr::CallExpr(_) | ast::Expr::CallBehaviorExpr(_) => {
                let code = self.expr(expr);
                match self.ty(expr).dereferenced() {
                    Ty::Void | Ty::Unknown => code,
                    _ => format!("_ = {code}"),
                }
            }
            _ => {
                let code = self.expr(expr);
                format!("_ = {code}")
            }
        }
    }

    /// `x++` or `x--` as a statement (an element an atomic function works on is loaded and
    /// stored, as C's read-modify-write).
    fn step(&mut self, operand: &ast::Expr, op: &str) -> String {
        match self.atomic_element(operand) {
            Some((element, ty)) => {
                let one = if ty == Ty::UInt { "1u" } else { "1i" };
                let sign = if op == "--" { "-" } else { "+" };
                format!("atomicStore(&{element}, atomicLoad(&{element}) {sign} {one})")
            }
            None => format!("{}{op}", self.expr(operand)),
        }
    }

    /// `a = b`, `a += b`: the value converted to the target's type; a compound assignment
    /// computes in the common type of both, as C does.
    fn assignment(&mut self, bin: &ast::BinExpr) -> String {
        let (Some(target), Some(value), Some(op)) = (bin.lhs(), bin.rhs(), bin.op()) else {
            return self.unsupported(bin.syntax(), "an incomplete assignment");
        };
        let target_ty = self.ty(&target);
        if let Some((element, _)) = self.atomic_element(&target) {
            // An element an atomic function works on is stored atomically; `+=` and the others
            // stay C's read-modify-write.
            let value = match op.kind() {
                SyntaxKind::EQ => bare(self.expr_as(&value, &target_ty)),
                _ => bare(self.computed(&format!("atomicLoad(&{element})"), &target_ty, op.text(), &value)),
            };
            return format!("atomicStore(&{element}, {value})");
        }
        let place = self.expr(&target);
        if op.kind() == SyntaxKind::EQ {
            let value = bare(self.expr_as(&value, &target_ty));
            return format!("{place} = {value}");
        }
        let computed = self.computed(&place, &target_ty, op.text(), &value);
        format!("{place} = {computed}")
    }

    /// `place op= value`'s new value: computed in the common type of both, as C does, and
    /// converted back to the place's type.
    fn computed(&mut self, place: &str, target_ty: &Ty, op: &str, value: &ast::Expr) -> String {
        let operator = op.trim_end_matches('=');
        if matches!(operator, "<<" | ">>") {
            let value = self.expr_as(value, &Ty::UInt);
            return format!("({place} {operator} {value})");
        }
        let both = common(target_ty, &self.ty(value));
        let value = self.expr_as(value, &both);
        let computed = format!("({} {operator} {value})", convert(place.to_string(), target_ty, &both));
        convert(computed, &both, target_ty)
    }

    /// `for (init : step : test) body`: a step that is a number adds it to the loop variable.
    fn for_loop(&mut self, stmt: &ast::ForStmt) {
        let sections = stmt.sections();
        let [init, step, test] = &sections[..] else {
            self.unsupported(stmt.syntax(), "a `for` needs `init : step : test`");
            return;
        };
        // The loop variable, for a numeric step.
        let variable = match init {
            ast::LoopPart::Decl(decl) => decl.name().map(|n| ident(&n.text())),
            ast::LoopPart::Expr(ast::Expr::BinExpr(bin)) => bin.lhs().map(|l| self.expr(&l)),
            ast::LoopPart::Expr(_) => None,
        };
        let init_code = self.loop_init(init);
        let step_code = match step {
            ast::LoopPart::Expr(
                expr @ (ast::Expr::BinExpr(_) | ast::Expr::PostfixExpr(_) | ast::Expr::PrefixExpr(_)),
            ) if !matches!(expr, ast::Expr::PrefixExpr(p) if p.op().is_some_and(|t| t.kind() == SyntaxKind::MINUS)) => {
                self.expr_statement(expr)
            }
            ast::LoopPart::Expr(amount) => match &variable {
                Some(variable) => format!("{variable} += {}", self.expr(amount)),
                None => self.unsupported(amount.syntax(), "a numeric step needs a loop variable in the first section"),
            },
            ast::LoopPart::Decl(decl) => self.unsupported(decl.syntax(), "a declaration as the step of a `for`"),
        };
        let test_code = match test {
            ast::LoopPart::Expr(test) => bare(self.expr_as(test, &Ty::Bool)),
            ast::LoopPart::Decl(decl) => self.unsupported(decl.syntax(), "a declaration as the test of a `for`"),
        };
        self.breakable(format!("for ({init_code}; {test_code}; {step_code}) {{"), |e| e.nested(stmt.body()));
    }

    /// `switch x: { case 1: s; default: t; }`: cases of constant integers; WGSL wants a
    /// `default`, an empty one is added.
    fn switch(&mut self, stmt: &ast::SwitchStmt) {
        let Some(scrutinee) = stmt.scrutinee() else {
            self.unsupported(stmt.syntax(), "a `switch` without a value");
            return;
        };
        let ty = match self.ty(&scrutinee).dereferenced() {
            Ty::UInt => Ty::UInt,
            _ => Ty::Int,
        };
        let value = self.expr_as(&scrutinee, &ty);
        let cases: Vec<ast::SwitchCase> = stmt.cases().collect();
        self.breakable(format!("switch {value} {{"), |e| {
            for case in &cases {
                let label = match case.label() {
                    Some(label) if !case.is_default() => e.expr_as(&label, &ty),
                    _ => "default".into(),
                };
                let opener = if label == "default" { "default: {".to_string() } else { format!("case {label}: {{") };
                e.block(opener, |e| {
                    for stmt in case.statements() {
                        e.statement(&stmt);
                    }
                });
            }
            if !cases.iter().any(|c| c.is_default()) {
                e.line("default: {}");
            }
        });
    }

    /// `loopwindow2D(u = -r : r, v = -r : r) { … }`: a loop per window dimension, the first
    /// outermost, each variable from its start to its end inclusive.
    fn window_statement(&mut self, window: &ast::LoopWindowStmt) {
        let ranges: Vec<ast::LoopWindowDim> = window.ranges().collect();
        let mut headers = Vec::new();
        for range in &ranges {
            let Some((name, first, last)) = range.bounds() else {
                self.unsupported(range.syntax(), "a window range is `name = start : end`");
                return;
            };
            let name = ident(&name);
            let (first, last) = (self.expr_as(&first, &Ty::Int), self.expr_as(&last, &Ty::Int));
            headers.push(format!("for (var {name}: i32 = {first}; {name} <= {last}; {name}++) {{"));
        }
        self.nest(&headers, &mut |e| {
            for stmt in window.body().into_iter().flat_map(|b| b.statements()) {
                e.statement(&stmt);
            }
        });
    }

    /// The loops `headers` open, one inside the other, around what `body` writes.
    pub fn nest(&mut self, headers: &[String], body: &mut dyn FnMut(&mut Self)) {
        match headers.split_first() {
            None => body(self),
            Some((first, rest)) => self.breakable(first.clone(), |e| e.nest(rest, body)),
        }
    }
}
