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
                let base = postfix_operand(self.expr(&base));
                let at = bare(self.expr_as(&at, &Ty::Int));
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
            match (literal.value(), ty.dereferenced()) {
                (Some(ast::LiteralValue::Int { value, .. }), Ty::Float) => return format!("{value}.0"),
                // A literal is written as the type wanted (`x << 2u`, not `x << u32(2i)`).
                (Some(ast::LiteralValue::Int { value, .. }), Ty::UInt) if value <= u64::from(u32::MAX) => {
                    return format!("{value}u")
                }
                _ => {}
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
        let parent = op.kind();
        match parent {
            AMP2 | PIPE2 => {
                let l = self.operand(&lhs, &Ty::Bool, parent, true);
                let r = self.operand(&rhs, &Ty::Bool, parent, false);
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
                let l = self.operand(&lhs, &operands, parent, true);
                let r = self.operand(&rhs, &operands, parent, false);
                format!("({l} {} {r})", op.text())
            }
        }
    }

    /// An operand of the operator `parent` (on its `left` or right) as `ty`: without the
    /// parentheses of an operation or a negation inside it where WGSL reads the same without
    /// them (`a * b + c`, `x - -y`); with them where its grammar needs them (`(a + b) << 2u`,
    /// `(a & b) == c`: WGSL neither mixes bitwise with other operators nor takes a shift's
    /// operand unparenthesized).
    fn operand(&mut self, expr: &ast::Expr, ty: &Ty, parent: SyntaxKind, left: bool) -> String {
        let converted = self.ty(expr).dereferenced() != ty.dereferenced();
        let code = self.expr_as(expr, ty);
        let redundant = match innermost(expr) {
            // A negation is a unary expression: any operator's operand.
            ast::Expr::PrefixExpr(p) => {
                p.op().is_some_and(|o| matches!(o.kind(), SyntaxKind::MINUS | SyntaxKind::TILDE))
            }
            ast::Expr::BinExpr(inner) if !inner.is_assignment() => {
                inner.op().and_then(|o| tier(o.kind())).is_some_and(|inner| same_meaning(parent, inner, left))
            }
            _ => false,
        };
        if redundant && !converted {
            bare(code)
        } else {
            code
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
            Some(letters) => format!("{}.{letters}", postfix_operand(self.expr(&receiver))),
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

/// The operand of an index or a member access: a dereference (`*p`, an `out` parameter) in
/// parentheses, since WGSL's postfix binds tighter than its `*`.
fn postfix_operand(code: String) -> String {
    if code.starts_with('*') {
        format!("({code})")
    } else {
        code
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

/// WGSL's operator tiers (its grammar, not C's precedence table).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Tier {
    Multiplicative,
    Additive,
    Shift,
    Relational,
    /// `&`, `|` or `^`: chains of one of them only.
    Bitwise(SyntaxKind),
    And,
    Or,
}

fn tier(op: SyntaxKind) -> Option<Tier> {
    use SyntaxKind::*;
    Some(match op {
        STAR | SLASH | PERCENT => Tier::Multiplicative,
        PLUS | MINUS => Tier::Additive,
        SHL | SHR => Tier::Shift,
        L_ANGLE | R_ANGLE | LTEQ | GTEQ | EQ2 | NEQ => Tier::Relational,
        AMP | PIPE | CARET => Tier::Bitwise(op),
        AMP2 => Tier::And,
        PIPE2 => Tier::Or,
        _ => return None,
    })
}

/// Whether an operation of tier `inner`, written without parentheses as the `left` (or right)
/// operand of `parent`, is read by WGSL as that operand: its grammar's operand rules
/// (multiplicative and additive chains associate to the left; a relational operator takes
/// additive and shift operands; `&&` and `||` take relational ones; shift and bitwise operators
/// take unary ones only).
fn same_meaning(parent: SyntaxKind, inner: Tier, left: bool) -> bool {
    use Tier::*;
    match tier(parent) {
        Some(Multiplicative) => left && inner == Multiplicative,
        Some(Additive) => inner == Multiplicative || (left && inner == Additive),
        Some(Relational) => matches!(inner, Multiplicative | Additive | Shift),
        Some(Bitwise(op)) => left && inner == Bitwise(op),
        Some(And) => matches!(inner, Multiplicative | Additive | Shift | Relational) || (left && inner == And),
        Some(Or) => matches!(inner, Multiplicative | Additive | Shift | Relational) || (left && inner == Or),
        Some(Shift) | None => false,
    }
}

/// The expression inside any parentheses written around it.
fn innermost(expr: &ast::Expr) -> ast::Expr {
    match expr {
        ast::Expr::ParenExpr(paren) => paren.expr().map_or_else(|| expr.clone(), |inner| innermost(&inner)),
        other => other.clone(),
    }
}
