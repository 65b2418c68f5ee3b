//! Expressions with C's semantics in WGSL: operands converted as C's usual arithmetic
//! conversions say, numbers as conditions, shift amounts as `u32`, OpenCL swizzles and vector
//! literals, casts; calls go to `builtins`.

use gudsl_model::{
    ast::{self, AstNode},
    hir::Ty,
    syntax::SyntaxKind,
};

use crate::{
    emitter::{bare, Emitter},
    types::{common, convert, value_type},
};

impl Emitter<'_> {
    /// `expr` as WGSL, of the type the model gives it.
    pub fn expr(&mut self, expr: &ast::Expr) -> String {
        use ast::Expr::*;
        match expr {
            Literal(literal) => self.literal(literal),
            NameExpr(name) => match name.name_ref() {
                Some(name) => {
                    let text = name.text();
                    self.field_in_function(&text, expr.syntax()).unwrap_or_else(|| self.name(&text))
                }
                None => self.unsupported(expr.syntax(), "an incomplete name"),
            },
            ParenExpr(paren) => match paren.expr() {
                Some(inner) => format!("({})", bare(self.expr(&inner))),
                None => self.unsupported(expr.syntax(), "an empty parenthesis"),
            },
            BinExpr(bin) => self.binary(bin),
            PrefixExpr(prefix) => self.prefix(prefix),
            TernaryExpr(ternary) => {
                let ty = self.ty(expr);
                let (Some(cond), Some(then), Some(other)) =
                    (ternary.condition(), ternary.then_expr(), ternary.else_expr())
                else {
                    return self.unsupported(expr.syntax(), "an incomplete `?:`");
                };
                let cond = self.expr_as(&cond, &Ty::Bool);
                let (then, other) = (self.expr_as(&then, &ty), self.expr_as(&other, &ty));
                format!("select({other}, {then}, {cond})")
            }
            CastExpr(_) | AsExpr(_) => {
                let operand = match expr {
                    CastExpr(cast) => cast.operand(),
                    AsExpr(cast) => cast.operand(),
                    _ => None,
                };
                let target = self.ty(expr);
                match operand {
                    Some(operand) if value_type(&target).is_some() => self.expr_as(&operand, &target),
                    _ => self.unsupported(expr.syntax(), format!("a cast to `{target}`, which has no WGSL value type")),
                }
            }
            IndexExpr(index) => {
                if let Some((element, _)) = self.atomic_element(expr) {
                    return format!("atomicLoad(&{element})");
                }
                let (Some(base), Some(at)) = (index.base(), index.index()) else {
                    return self.unsupported(expr.syntax(), "an incomplete index");
                };
                let base = self.expr(&base);
                let at = self.expr_as(&at, &Ty::Int);
                format!("{base}[{at}]")
            }
            MemberExpr(member) => self.member(member),
            NewExpr(new) => self.vector_literal(new),
            CallExpr(call) => self.call(call),
            PostfixExpr(_) => {
                self.unsupported(expr.syntax(), "`++`/`--` inside an expression: write it as a statement of its own")
            }
            CallBehaviorExpr(call) => self.behavior_call(call),
            ThisExpr(_) | ScopeExpr(_) | CallMethodExpr(_) | CallInterfaceExpr(_) => {
                self.unsupported(expr.syntax(), "this expression is not generated for the GPU yet")
            }
        }
    }

    /// `expr` converted to `ty` (a literal is written in that type directly).
    pub fn expr_as(&mut self, expr: &ast::Expr, ty: &Ty) -> String {
        let from = self.ty(expr);
        if let ast::Expr::Literal(literal) = expr {
            if let (Some(ast::LiteralValue::Int { value, .. }), Ty::Float) = (literal.value(), ty.dereferenced()) {
                return format!("{value}.0");
            }
        }
        let code = self.expr(expr);
        convert(code, &from, ty)
    }

    fn literal(&mut self, literal: &ast::Literal) -> String {
        match literal.value() {
            Some(ast::LiteralValue::Int { value, .. }) if value > u32::MAX as u64 => {
                self.unsupported(literal.syntax(), "an integer wider than 32 bits (WGSL has none)")
            }
            Some(ast::LiteralValue::Int { value, unsigned: true }) => format!("{value}u"),
            Some(ast::LiteralValue::Int { value, unsigned: false }) => format!("{value}i"),
            Some(ast::LiteralValue::Float(value)) => format!("{value:?}f"),
            Some(ast::LiteralValue::Char(code)) => format!("{code}i"),
            Some(ast::LiteralValue::Bool(value)) => value.to_string(),
            None => self.unsupported(literal.syntax(), "an integer wider than 64 bits"),
            Some(ast::LiteralValue::Str(_) | ast::LiteralValue::Null) => {
                self.unsupported(literal.syntax(), "strings and `null` do not exist on the GPU")
            }
        }
    }

    fn binary(&mut self, bin: &ast::BinExpr) -> String {
        let (Some(lhs), Some(rhs), Some(op)) = (bin.lhs(), bin.rhs(), bin.op()) else {
            return self.unsupported(bin.syntax(), "an incomplete operation");
        };
        if bin.is_assignment() {
            return self.unsupported(bin.syntax(), "an assignment inside an expression: write it as a statement");
        }
        use SyntaxKind::*;
        let (lt, rt) = (self.ty(&lhs), self.ty(&rhs));
        match op.kind() {
            AMP2 | PIPE2 => {
                let (l, r) = (self.expr_as(&lhs, &Ty::Bool), self.expr_as(&rhs, &Ty::Bool));
                format!("({l} {} {r})", op.text())
            }
            SHL | SHR => {
                let shift = match lt.dereferenced() {
                    Ty::Vector(_, n) => Ty::Vector(Box::new(Ty::UInt), *n),
                    _ => Ty::UInt,
                };
                let (l, r) = (self.expr(&lhs), self.expr_as(&rhs, &shift));
                format!("({l} {} {r})", op.text())
            }
            _ => {
                let operands = match (lt.dereferenced(), rt.dereferenced()) {
                    (Ty::Unknown, _) => rt.clone(),
                    (_, Ty::Unknown) => lt.clone(),
                    _ => common(&lt, &rt),
                };
                let (l, r) = (self.expr_as(&lhs, &operands), self.expr_as(&rhs, &operands));
                format!("({l} {} {r})", op.text())
            }
        }
    }

    fn prefix(&mut self, prefix: &ast::PrefixExpr) -> String {
        let (Some(op), Some(operand)) = (prefix.op(), prefix.operand()) else {
            return self.unsupported(prefix.syntax(), "an incomplete operation");
        };
        match op.kind() {
            SyntaxKind::BANG => format!("!{}", self.expr_as(&operand, &Ty::Bool)),
            SyntaxKind::MINUS | SyntaxKind::TILDE => format!("({}{})", op.text(), self.expr(&operand)),
            SyntaxKind::PLUS => self.expr(&operand),
            _ => self.unsupported(prefix.syntax(), format!("`{}` here is not generated for the GPU", op.text())),
        }
    }

    /// Swizzles (`v._x`, `v.xy`, `v.s01`, `v.lo`) and enum constants (`int`s, as C numbers
    /// them: `sampler_flags.CLK_FILTER_LINEAR` is 32); fields of objects are not values on the
    /// GPU.
    fn member(&mut self, member: &ast::MemberExpr) -> String {
        let (Some(receiver), Some(name)) = (member.receiver(), member.member()) else {
            return self.unsupported(member.syntax(), "an incomplete member access");
        };
        let receiver_ty = self.ty(&receiver).dereferenced().clone();
        if let Ty::Named(fqn) = &receiver_ty {
            if let Some(value) = self.sema.enum_value(fqn, &name.text()) {
                return match i32::try_from(value) {
                    Ok(value) if value < 0 => format!("({value}i)"),
                    Ok(value) => format!("{value}i"),
                    Err(_) => self.unsupported(member.syntax(), "an enum constant wider than 32 bits"),
                };
            }
        }
        let Ty::Vector(_, width) = receiver_ty else {
            return self.unsupported(member.syntax(), "fields of objects are not generated for the GPU");
        };
        match swizzle(&name.text(), width) {
            Some(letters) => format!("{}.{letters}", self.expr(&receiver)),
            None => {
                self.unsupported(name.syntax(), format!("`{}` is no component of a {width}-wide vector", name.text()))
            }
        }
    }

    /// `new int4(a, b, c, d)`, `new float3(v)`, `new float4(xyz, 1.0f)`.
    fn vector_literal(&mut self, new: &ast::NewExpr) -> String {
        let ty = self.types.of(&ast::Expr::NewExpr(new.clone())).clone();
        let Ty::Vector(element, width) = ty.dereferenced().clone() else {
            return self.unsupported(new.syntax(), format!("`new {ty}`: only vectors are created on the GPU"));
        };
        let Some(target) = value_type(&ty) else {
            return self.unsupported(new.syntax(), format!("`{ty}`: WGSL has vectors of 2, 3 and 4 components"));
        };
        let args: Vec<ast::Expr> = new.arg_list().into_iter().flat_map(|l| l.args()).collect();
        let parts: Vec<String> = args
            .iter()
            .map(|arg| match self.ty(arg).dereferenced() {
                Ty::Vector(_, n) => {
                    let as_elements = Ty::Vector(element.clone(), *n);
                    bare(self.expr_as(arg, &as_elements))
                }
                _ => bare(self.expr_as(arg, &element)),
            })
            .collect();
        if parts.is_empty() {
            return format!("{target}()");
        }
        let _ = width;
        format!("{target}({})", parts.join(", "))
    }
}

/// An OpenCL swizzle as WGSL's `xyzw` letters; `None` if it names no component of a
/// `width`-wide vector.
fn swizzle(name: &str, width: u8) -> Option<String> {
    const LETTERS: [char; 4] = ['x', 'y', 'z', 'w'];
    let name = name.strip_prefix('_').unwrap_or(name);
    let indices: Vec<usize> = match name {
        "lo" => (0..width as usize / 2).collect(),
        "hi" => (width as usize / 2..width as usize).collect(),
        "even" => (0..width as usize).step_by(2).collect(),
        "odd" => (1..width as usize).step_by(2).collect(),
        _ => match name.strip_prefix(['s', 'S']) {
            Some(digits) if !digits.is_empty() && digits.chars().all(|c| c.is_ascii_hexdigit()) => {
                digits.chars().map(|c| c.to_digit(16).unwrap_or(99) as usize).collect()
            }
            _ => name.chars().map(|c| "xyzw".find(c).or_else(|| "rgba".find(c)).unwrap_or(99)).collect(),
        },
    };
    if indices.is_empty() || indices.len() > 4 || indices.iter().any(|&i| i >= width as usize || i >= 4) {
        return None;
    }
    Some(indices.into_iter().map(|i| LETTERS[i]).collect())
}

#[cfg(test)]
mod tests {
    use super::swizzle;

    #[test]
    fn opencl_swizzles_in_wgsl() {
        assert_eq!(swizzle("_x", 4).as_deref(), Some("x"));
        assert_eq!(swizzle("xy", 4).as_deref(), Some("xy"));
        assert_eq!(swizzle("s03", 4).as_deref(), Some("xw"));
        assert_eq!(swizzle("hi", 4).as_deref(), Some("zw"));
        assert_eq!(swizzle("odd", 4).as_deref(), Some("yw"));
        assert_eq!(swizzle("rgb", 4).as_deref(), Some("xyz"));
        assert_eq!(swizzle("z", 2), None);
        assert_eq!(swizzle("length", 4), None);
    }
}
