//! Expressions lowered for the host: operators in the C arithmetic of their operands' types
//! (integer division, wrapping 32-bit `int` and `unsigned int`, shifts, comparisons), pointer
//! arithmetic and indexing, assignments with C's conversions, casts, enum constants, the
//! framework's methods and functions, `new`, and `call C::m(…)` in calc nodes (a kernel).

use gudsl_model::{
    ast::{self, AstNode, HasModifiers, HasName, LiteralValue},
    hir::{DefKind, Scope, Ty},
    syntax::{SyntaxKind, SyntaxNode},
};

use super::{conv, conv_to, stmt::arith, Lowering};
use crate::run::{
    framework::Method,
    ir::{Arith, BinOp, CmpOp, Conv, Expr, OutArg, Place},
    value::{Constant, Scalar},
};

impl Lowering<'_, '_> {
    pub(super) fn ty(&self, expr: &ast::Expr) -> Ty {
        self.types.of(expr).clone()
    }

    /// `expr` as a condition (a number is true when it is not zero).
    pub(super) fn condition(&mut self, expr: &ast::Expr) -> Expr {
        self.converted_to(expr, Conv::Bool)
    }

    /// `expr` converted for a variable of type `ty` written as `type_ref`.
    pub(super) fn converted(&mut self, expr: &ast::Expr, ty: &Ty, type_ref: Option<&ast::TypeRef>) -> Expr {
        self.converted_to(expr, conv(ty, type_ref))
    }

    pub(super) fn converted_to(&mut self, expr: &ast::Expr, conv: Conv) -> Expr {
        let lowered = self.expr(expr);
        // A number already of the type it is converted to stays as it is.
        let already =
            matches!(conv, Conv::Bool | Conv::Int | Conv::UInt | Conv::Float) && conv_to(&self.ty(expr)) == conv;
        match (conv, &lowered) {
            (Conv::Keep, _) => lowered,
            _ if already => lowered,
            // Constants are converted once, here.
            (_, Expr::Const(value)) => match super::super::arith::convert(conv, value.value()).map(Constant::of) {
                Ok(Some(value)) => Expr::Const(value),
                _ => Expr::Convert(conv, Box::new(lowered)),
            },
            _ => Expr::Convert(conv, Box::new(lowered)),
        }
    }

    pub(super) fn expr(&mut self, expr: &ast::Expr) -> Expr {
        use ast::Expr::*;
        match expr {
            Literal(literal) => match literal.value() {
                Some(LiteralValue::Int { value, unsigned: true }) => Expr::Const(Constant::UInt(value as u32)),
                Some(LiteralValue::Int { value, unsigned: false }) => Expr::Const(Constant::Int(value as i32)),
                Some(LiteralValue::Float(value)) => Expr::Const(Constant::Float(value)),
                Some(LiteralValue::Char(code)) => Expr::Const(Constant::Int(code as i32)),
                Some(LiteralValue::Str(text)) => Expr::Const(Constant::Str(text.into())),
                Some(LiteralValue::Bool(value)) => Expr::Const(Constant::Bool(value)),
                Some(LiteralValue::Null) => Expr::Const(Constant::Null),
                None => self.unsupported(expr.syntax(), "an integer wider than 64 bits"),
            },
            NameExpr(name) => {
                let text = name.name_ref().map(|n| n.text()).unwrap_or_default();
                match self.lookup(&text) {
                    Some(local) => Expr::Var(local.slot),
                    None => self.unsupported(expr.syntax(), format!("`{text}` is not a variable of the run")),
                }
            }
            ParenExpr(paren) => match paren.expr() {
                Some(inner) => self.expr(&inner),
                None => self.unsupported(expr.syntax(), "an empty parenthesis"),
            },
            BinExpr(bin) => self.binary(bin),
            PrefixExpr(prefix) => self.prefix(prefix),
            PostfixExpr(postfix) => {
                let (Some(operand), Some(op)) = (postfix.operand(), postfix.op()) else {
                    return self.unsupported(expr.syntax(), "an incomplete `++`/`--`");
                };
                let op = if op.kind() == SyntaxKind::PLUS2 { BinOp::Add } else { BinOp::Sub };
                self.increment(expr.syntax(), &operand, op, true)
            }
            TernaryExpr(ternary) => {
                let (Some(cond), Some(then), Some(other)) =
                    (ternary.condition(), ternary.then_expr(), ternary.else_expr())
                else {
                    return self.unsupported(expr.syntax(), "an incomplete `?:`");
                };
                let result = conv_to(&self.ty(expr));
                let cond = self.condition(&cond);
                let (then, other) = (self.converted_to(&then, result), self.converted_to(&other, result));
                Expr::Ternary(Box::new(cond), Box::new(then), Box::new(other))
            }
            CastExpr(cast) => self.cast(expr, cast.operand(), cast.type_ref()),
            AsExpr(cast) => self.cast(expr, cast.operand(), cast.type_ref()),
            IndexExpr(index) => {
                let (Some(base), Some(at)) = (index.base(), index.index()) else {
                    return self.unsupported(expr.syntax(), "an incomplete index");
                };
                let (base, at) = (self.expr(&base), self.converted_to(&at, Conv::Int));
                Expr::Index(Box::new(base), Box::new(at), self.span(expr.syntax()))
            }
            MemberExpr(member) => {
                let (Some(receiver), Some(name)) = (member.receiver(), member.member()) else {
                    return self.unsupported(expr.syntax(), "an incomplete member access");
                };
                self.constant(expr, &receiver, &name.text())
            }
            ScopeExpr(scope) => {
                let (Some(receiver), Some(name)) = (scope.scope(), scope.member()) else {
                    return self.unsupported(expr.syntax(), "an incomplete `::`");
                };
                self.constant(expr, &receiver, &name.text())
            }
            CallExpr(call) => self.call(expr, call),
            NewExpr(new) => self.construct(expr, new),
            CallMethodExpr(call) => self.launch(expr, call),
            CallBehaviorExpr(call) => self.call_behavior(expr, call),
            CallInterfaceExpr(_) => self.unsupported(
                expr.syntax(),
                "interface calls belong to component diagrams: they do not run in a host diagram",
            ),
            ThisExpr(_) => self.unsupported(expr.syntax(), "a run of a diagram has no `this`"),
        }
    }

    fn binary(&mut self, bin: &ast::BinExpr) -> Expr {
        let (Some(lhs), Some(rhs), Some(op)) = (bin.lhs(), bin.rhs(), bin.op()) else {
            return self.unsupported(bin.syntax(), "an incomplete operation");
        };
        use SyntaxKind::*;
        let span = self.span(bin.syntax());
        let (lt, rt) = (self.ty(&lhs), self.ty(&rhs));
        let pointer =
            |ty: &Ty| matches!(ty, Ty::Ref { .. } | Ty::Array(_)) && !matches!(ty.dereferenced(), Ty::Named(_));
        if bin.is_assignment() {
            let Some(place) = self.place(&lhs) else { return Expr::Const(Constant::Void) };
            if op.kind() == EQ {
                let value = match &place {
                    Place::Var(_, conv) => self.converted_to(&rhs, *conv),
                    Place::Index(..) => self.expr(&rhs),
                };
                return Expr::Assign(Box::new(place), Box::new(value));
            }
            let Some(operation) = bin_op(op.kind()) else {
                return self.unsupported(bin.syntax(), format!("`{}` is not an operator", op.text()));
            };
            if pointer(&lt) {
                return self.unsupported(bin.syntax(), "compound assignment to a pointer: write `p = p + n`");
            }
            let arith = if matches!(operation, BinOp::Shl | BinOp::Shr) { arith(&lt) } else { common(&lt, &rt) };
            let value = self.converted_to(&rhs, super::stmt::conv_of_arith(arith));
            return Expr::Update(Box::new(place), operation, arith, Box::new(value), false, span);
        }
        match op.kind() {
            AMP2 | PIPE2 => {
                let (l, r) = (Box::new(self.condition(&lhs)), Box::new(self.condition(&rhs)));
                if op.kind() == AMP2 {
                    Expr::And(l, r)
                } else {
                    Expr::Or(l, r)
                }
            }
            PLUS | MINUS if pointer(&lt) => {
                let (l, r) = (self.expr(&lhs), self.converted_to(&rhs, Conv::Int));
                Expr::Offset(Box::new(l), Box::new(r), op.kind() == MINUS)
            }
            PLUS if pointer(&rt) => {
                let (l, r) = (self.converted_to(&lhs, Conv::Int), self.expr(&rhs));
                Expr::Offset(Box::new(r), Box::new(l), false)
            }
            EQ2 | NEQ | L_ANGLE | LTEQ | R_ANGLE | GTEQ => {
                let cmp = match op.kind() {
                    EQ2 => CmpOp::Eq,
                    NEQ => CmpOp::Ne,
                    L_ANGLE => CmpOp::Lt,
                    LTEQ => CmpOp::Le,
                    R_ANGLE => CmpOp::Gt,
                    _ => CmpOp::Ge,
                };
                let numeric = |t: &Ty| t.dereferenced().is_numeric() || matches!(t.dereferenced(), Ty::Bool);
                if numeric(&lt) && numeric(&rt) && !pointer(&lt) && !pointer(&rt) {
                    let arith = common(&lt, &rt);
                    let conv = super::stmt::conv_of_arith(arith);
                    let (l, r) = (self.converted_to(&lhs, conv), self.converted_to(&rhs, conv));
                    Expr::Compare(cmp, arith, Box::new(l), Box::new(r))
                } else if matches!(cmp, CmpOp::Eq | CmpOp::Ne) {
                    let (l, r) = (self.expr(&lhs), self.expr(&rhs));
                    Expr::Same(cmp == CmpOp::Eq, Box::new(l), Box::new(r))
                } else {
                    self.unsupported(bin.syntax(), format!("`{lt}` and `{rt}` are not ordered"))
                }
            }
            kind => {
                let Some(operation) = bin_op(kind) else {
                    return self.unsupported(bin.syntax(), format!("`{}` is not an operator", op.text()));
                };
                let arith = if matches!(operation, BinOp::Shl | BinOp::Shr) { arith(&lt) } else { common(&lt, &rt) };
                if arith == Arith::Float
                    && !matches!(operation, BinOp::Add | BinOp::Sub | BinOp::Mul | BinOp::Div | BinOp::Rem)
                {
                    return self.unsupported(bin.syntax(), format!("`{}` on floating-point numbers", op.text()));
                }
                let conv = super::stmt::conv_of_arith(arith);
                let (l, r) = (self.converted_to(&lhs, conv), self.converted_to(&rhs, conv));
                Expr::Binary(operation, arith, Box::new(l), Box::new(r), span)
            }
        }
    }

    fn prefix(&mut self, prefix: &ast::PrefixExpr) -> Expr {
        let (Some(op), Some(operand)) = (prefix.op(), prefix.operand()) else {
            return self.unsupported(prefix.syntax(), "an incomplete operation");
        };
        let arith = arith(&self.ty(&operand));
        match op.kind() {
            SyntaxKind::BANG => Expr::Not(Box::new(self.condition(&operand))),
            SyntaxKind::MINUS => {
                let value = self.converted_to(&operand, super::stmt::conv_of_arith(arith));
                match value {
                    Expr::Const(Constant::Int(v)) => Expr::Const(Constant::Int(v.wrapping_neg())),
                    Expr::Const(Constant::Float(v)) => Expr::Const(Constant::Float(-v)),
                    value => Expr::Negate(arith, Box::new(value)),
                }
            }
            SyntaxKind::TILDE => {
                Expr::BitNot(arith, Box::new(self.converted_to(&operand, super::stmt::conv_of_arith(arith))))
            }
            SyntaxKind::PLUS => self.expr(&operand),
            SyntaxKind::PLUS2 => self.increment(prefix.syntax(), &operand, BinOp::Add, false),
            SyntaxKind::MINUS2 => self.increment(prefix.syntax(), &operand, BinOp::Sub, false),
            _ => self.unsupported(prefix.syntax(), format!("`{}` does not run on the host", op.text())),
        }
    }

    /// `++x`, `x--`, …: the old value is the result of a postfix operator.
    fn increment(&mut self, node: &SyntaxNode, operand: &ast::Expr, op: BinOp, postfix: bool) -> Expr {
        let Some(place) = self.place(operand) else { return Expr::Const(Constant::Void) };
        let ty = self.ty(operand);
        if matches!(ty, Ty::Ref { .. } | Ty::Array(_)) {
            return self.unsupported(node, "`++`/`--` on a pointer: write `p = p + 1`");
        }
        let arith = arith(&ty);
        let one = match arith {
            Arith::Float => Constant::Float(1.0),
            Arith::UInt => Constant::UInt(1),
            Arith::Int => Constant::Int(1),
        };
        let span = self.span(node);
        Expr::Update(Box::new(place), op, arith, Box::new(Expr::Const(one)), postfix, span)
    }

    /// What `expr` names as the target of an assignment.
    pub(super) fn place(&mut self, expr: &ast::Expr) -> Option<Place> {
        match expr {
            ast::Expr::ParenExpr(paren) => self.place(&paren.expr()?),
            ast::Expr::NameExpr(name) => {
                let text = name.name_ref().map(|n| n.text()).unwrap_or_default();
                match self.lookup(&text) {
                    Some(local) => Some(Place::Var(local.slot, local.conv)),
                    None => {
                        self.error(expr.syntax(), format!("`{text}` is not a variable of the run"));
                        None
                    }
                }
            }
            ast::Expr::IndexExpr(index) => {
                let (base, at) = (index.base()?, index.index()?);
                let (base, at) = (self.expr(&base), self.converted_to(&at, Conv::Int));
                Some(Place::Index(base, at, self.span(expr.syntax())))
            }
            _ => {
                self.error(expr.syntax(), "only variables and elements can be assigned on the host");
                None
            }
        }
    }

    /// `(T)x` and `x as T`: a number converted, or a pointer read as other elements.
    fn cast(&mut self, expr: &ast::Expr, operand: Option<ast::Expr>, type_ref: Option<ast::TypeRef>) -> Expr {
        let Some(operand) = operand else { return self.unsupported(expr.syntax(), "an incomplete cast") };
        let target = self.ty(expr);
        let conv = conv(&target, type_ref.as_ref());
        self.converted_to(&operand, conv)
    }

    /// `E.member` / `E::member` for an enum `E`: the constant's number.
    fn constant(&mut self, expr: &ast::Expr, receiver: &ast::Expr, member: &str) -> Expr {
        if let Some(fqn) = self.type_named(receiver) {
            if let Some(value) = self.enum_constant(&fqn, member) {
                return Expr::Const(Constant::Int(value));
            }
        }
        match self.ty(receiver).dereferenced() {
            Ty::Vector(..) => {
                self.unsupported(expr.syntax(), "vectors are device values: they do not run on the host yet")
            }
            _ => self.unsupported(expr.syntax(), "fields of objects do not run on the host yet (enum constants do)"),
        }
    }

    /// The type a name or path expression denotes (`QImageFormat`, `CPPMethods`), unless it is a
    /// variable.
    fn type_named(&self, expr: &ast::Expr) -> Option<String> {
        let ast::Expr::NameExpr(name) = expr else { return None };
        let text = name.name_ref()?.text();
        if self.lookup(&text).is_some() {
            return None;
        }
        let scope = gudsl_model::hir::Scope::at(expr.syntax());
        let def = self.sema.resolve(&scope, &text)?;
        matches!(def.kind, DefKind::Type(_)).then(|| def.fqn.clone())
    }

    /// `receiver.m(…)` on a framework object, `Class::f(…)` of `CPPMethods`.
    fn call(&mut self, expr: &ast::Expr, call: &ast::CallExpr) -> Expr {
        let args: Vec<ast::Expr> = call.args().collect();
        let (receiver, class, name) = match call.callee() {
            Some(ast::Expr::MemberExpr(member)) => {
                let (Some(receiver), Some(name)) = (member.receiver(), member.member()) else {
                    return self.unsupported(expr.syntax(), "an incomplete call");
                };
                match self.type_named(&receiver) {
                    Some(class) => (None, class, name.text()),
                    None => match self.ty(&receiver).dereferenced().clone() {
                        Ty::Named(class) => (Some(receiver), class, name.text()),
                        other => {
                            return self
                                .unsupported(expr.syntax(), format!("methods of `{other}` do not run on the host"))
                        }
                    },
                }
            }
            Some(ast::Expr::ScopeExpr(scope)) => {
                let (Some(receiver), Some(name)) = (scope.scope(), scope.member()) else {
                    return self.unsupported(expr.syntax(), "an incomplete call");
                };
                match self.type_named(&receiver) {
                    Some(class) => (None, class, name.text()),
                    None => return self.unsupported(expr.syntax(), "`::` calls a function of a class"),
                }
            }
            _ => {
                return self.unsupported(
                    expr.syntax(),
                    "calls of the owner's methods do not run on the host yet (the framework's do)",
                )
            }
        };
        let Some(simple) = self.framework_class(&class) else {
            return self.unsupported(
                expr.syntax(),
                format!("methods of the workspace's class `{class}` do not run on the host yet (the framework's do)"),
            );
        };
        let Some(method) = Method::resolve(simple, &name, args.len()) else {
            return self.unsupported(
                expr.syntax(),
                format!(
                    "`{simple}::{name}` with {} argument(s) is not part of the framework the host runs",
                    args.len()
                ),
            );
        };
        let mut lowered: Vec<Expr> = receiver.iter().map(|r| self.expr(r)).collect();
        lowered.extend(args.iter().map(|a| self.expr(a)));
        Expr::Call(method, lowered, self.span(expr.syntax()))
    }

    /// `new T(…)` of a framework class; `new T[n]`.
    fn construct(&mut self, expr: &ast::Expr, new: &ast::NewExpr) -> Expr {
        let Some(type_ref) = new.type_ref() else { return self.unsupported(expr.syntax(), "an incomplete `new`") };
        let span = self.span(expr.syntax());
        if let Some(size) = new.array_size() {
            let size = self.converted_to(&size, Conv::Int);
            return Expr::NewArray(Scalar::of_type_ref(&type_ref), Box::new(size), span);
        }
        let class = match self.ty(expr).dereferenced() {
            Ty::Named(fqn) => fqn.clone(),
            other => return self.unsupported(expr.syntax(), format!("`new {other}(…)`: only classes are constructed")),
        };
        let element = type_ref.type_args().next().map(|t| Scalar::of_type_ref(&t));
        let constructor = self.framework_class(&class).and_then(|simple| Method::constructor(simple, element));
        let Some(method) = constructor else {
            return self.unsupported(
                expr.syntax(),
                format!("objects of `{class}` are not made on the host yet (the framework's are)"),
            );
        };
        let args = new.arg_list().into_iter().flat_map(|l| l.args()).map(|a| self.expr(&a)).collect();
        Expr::Call(method, args, span)
    }

    /// `call C::m(…)` in a calc or calcRange node: the kernel generated from the device
    /// diagram that implements `m`, launched with the node's work sizes.
    fn launch(&mut self, expr: &ast::Expr, call: &ast::CallMethodExpr) -> Expr {
        if !self.in_calc {
            return self.unsupported(
                expr.syntax(),
                "`call C::m(…)` starts a GPU kernel: it belongs in a calc or calcRange node",
            );
        }
        let (Some(class), Some(method)) = (call.class(), call.method()) else {
            return self.unsupported(expr.syntax(), "an incomplete call");
        };
        let Some(class) = self.sema.resolve_path(&class) else {
            return self.unsupported(expr.syntax(), format!("no class `{}`", class.text()));
        };
        let method = method.text();
        let diagram = match gudsl_codegen::implementation(self.sema, class, &method) {
            Ok(diagram) => diagram,
            Err(message) => return self.unsupported(expr.syntax(), message),
        };
        let kernel = match self.kernels.iter().position(|k| k.diagram == diagram.fqn) {
            Some(index) => index,
            None => match gudsl_codegen::generate(self.sema, diagram) {
                Ok(kernel) => {
                    self.kernels.push(kernel);
                    self.kernels.len() - 1
                }
                Err(errors) => {
                    let first = errors.first().map(|e| e.message.clone()).unwrap_or_default();
                    let message = format!(
                        "the kernel of `{}` cannot be generated ({} problem(s); `gudsl wgsl` lists them): {first}",
                        diagram.fqn,
                        errors.len()
                    );
                    return self.unsupported(expr.syntax(), message);
                }
            },
        };
        let args = call.args().map(|a| self.expr(&a)).collect();
        Expr::Launch(kernel, args, self.span(expr.syntax()))
    }
}

impl Lowering<'_, '_> {
    /// `call behavior D(…)` of a host diagram: the arguments converted to its parameters, each
    /// `out` argument a place its value is stored in when the call returns.
    fn call_behavior(&mut self, expr: &ast::Expr, call: &ast::CallBehaviorExpr) -> Expr {
        let Some(path) = call.behavior() else { return self.unsupported(expr.syntax(), "an incomplete call") };
        let sema = self.sema;
        let def = sema.resolve(&Scope::at(call.syntax()), &path.text());
        let Some(def) = def.filter(|def| matches!(def.kind, DefKind::Activity(_))) else {
            return self.unsupported(expr.syntax(), format!("`{}` is no activity diagram", path.text()));
        };
        if gudsl_codegen::is_device_diagram(sema, def) {
            return self.unsupported(
                expr.syntax(),
                format!(
                    "`{}` is a device diagram: it runs on the GPU, launched from a calc node (`call C::m(…)`)",
                    def.fqn
                ),
            );
        }
        let Some(diagram) = sema.declaration(def).and_then(|(node, _)| ast::ActivityDiagram::cast(node)) else {
            return self.unsupported(expr.syntax(), format!("`{}` is no activity diagram", def.fqn));
        };
        let (params, args): (Vec<ast::Param>, Vec<ast::Expr>) = (diagram.params().collect(), call.args().collect());
        if params.len() != args.len() {
            return self.unsupported(
                expr.syntax(),
                format!("`{}` takes {} argument(s), {} are given", def.fqn, params.len(), args.len()),
            );
        }
        let types = sema.body_types(diagram.syntax());
        let mut lowered = Vec::new();
        let mut outs = Vec::new();
        for (param, arg) in params.iter().zip(&args) {
            let name = param.name().map(|n| n.text()).unwrap_or_default();
            let ty = types.locals.get(&name).cloned().unwrap_or(Ty::Unknown);
            lowered.push(self.converted(arg, &ty, param.type_ref().as_ref()));
            if param.has_modifier(SyntaxKind::OUT_KW) {
                if let Some(place) = self.place(arg) {
                    outs.push(OutArg { slot: self.slot(Conv::Keep), place });
                }
            }
        }
        let diagram = self.called_index(def, diagram);
        Expr::CallDiagram { diagram, args: lowered, outs, span: self.span(expr.syntax()) }
    }
}

/// The binary operation of an operator or compound assignment token.
fn bin_op(kind: SyntaxKind) -> Option<BinOp> {
    use SyntaxKind::*;
    Some(match kind {
        PLUS | PLUSEQ => BinOp::Add,
        MINUS | MINUSEQ => BinOp::Sub,
        STAR | STAREQ => BinOp::Mul,
        SLASH | SLASHEQ => BinOp::Div,
        PERCENT | PERCENTEQ => BinOp::Rem,
        SHL | SHLEQ => BinOp::Shl,
        SHR | SHREQ => BinOp::Shr,
        AMP | AMPEQ => BinOp::BitAnd,
        PIPE | PIPEEQ => BinOp::BitOr,
        CARET | CARETEQ => BinOp::BitXor,
        _ => return None,
    })
}

/// C's usual arithmetic conversions: the arithmetic two operands are computed in.
fn common(a: &Ty, b: &Ty) -> Arith {
    match (arith(a), arith(b)) {
        (Arith::Float, _) | (_, Arith::Float) => Arith::Float,
        (Arith::UInt, _) | (_, Arith::UInt) => Arith::UInt,
        _ => Arith::Int,
    }
}
