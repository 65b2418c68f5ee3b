//! The types of operations: comparisons and logic are `bool`; arithmetic follows C's usual
//! arithmetic conversions (floating point wins, then unsigned), a shift has the type of what it
//! shifts; assignments are checked against their target; increments need something mutable;
//! `?:` has its branches' type; indexing gives an element, member access a field or swizzle.

use super::{swizzle_width, InferenceCtx};
use crate::{
    ast::{self, AstNode},
    hir::{
        definitions::DefKind,
        diagnostics::{excerpt, DiagnosticCode},
        items::TypeKind,
        Ty,
    },
    syntax::SyntaxKind,
};

impl InferenceCtx<'_, '_> {
    pub(super) fn binary(&mut self, bin: &ast::BinExpr) -> Ty {
        let lhs = bin.lhs().map_or(Ty::Unknown, |e| self.infer(&e));
        let rhs = bin.rhs().map_or(Ty::Unknown, |e| self.infer(&e));
        if bin.is_assignment() {
            return self.assignment(bin, lhs, rhs);
        }
        // Arithmetic reads through references.
        let (lhs, rhs) = (lhs.dereferenced().clone(), rhs.dereferenced().clone());
        let Some(op_token) = bin.op() else { return Ty::Unknown };
        let op = op_token.kind();
        self.operands(bin, op_token.text(), op, &lhs, &rhs);
        use SyntaxKind::*;
        match op {
            EQ2 | NEQ | L_ANGLE | LTEQ | R_ANGLE | GTEQ | AMP2 | PIPE2 => Ty::Bool,
            // A shift has the type of what is shifted (no usual arithmetic conversions).
            SHL | SHR if matches!(lhs, Ty::Int | Ty::UInt) && matches!(rhs, Ty::Int | Ty::UInt) => lhs,
            _ => match (&lhs, &rhs) {
                (Ty::String, _) | (_, Ty::String) if op == PLUS => Ty::String,
                (Ty::Float, Ty::Int | Ty::UInt) | (Ty::Int | Ty::UInt, Ty::Float) => Ty::Float,
                // C's usual arithmetic conversions: unsigned wins.
                (Ty::Int, Ty::UInt) | (Ty::UInt, Ty::Int) => Ty::UInt,
                (Ty::Vector(..), _) => lhs,
                (_, Ty::Vector(..)) => rhs,
                (Ty::Int | Ty::UInt | Ty::Float, _) if lhs == rhs => lhs,
                (Ty::Array(_), _) => lhs,
                _ => Ty::Unknown,
            },
        }
    }

    /// Operands an operator takes, as in C and OpenCL C: numbers (enums too) in arithmetic and
    /// comparisons, strings joined by `+`, objects compared for identity only (`==`, `!=`,
    /// with each other or `null`), vectors with vectors of their width or with numbers.
    fn operands(&mut self, bin: &ast::BinExpr, text: &str, op: SyntaxKind, lhs: &Ty, rhs: &Ty) {
        use SyntaxKind::*;
        if matches!(op, AMP2 | PIPE2) {
            return;
        }
        let identity = matches!(op, EQ2 | NEQ);
        let problem = match (lhs, rhs) {
            (Ty::Vector(_, a), Ty::Vector(_, b)) if a != b => {
                Some(format!("`{text}` takes vectors of one width, not `{lhs}` and `{rhs}`"))
            }
            (Ty::String, _) | (_, Ty::String) if op == PLUS || identity => None,
            (a, b) if identity && self.is_object(a) && (self.is_object(b) || *b == Ty::Null) => None,
            (a, b) if identity && self.is_object(b) && *a == Ty::Null => None,
            (a, _) if self.is_object(a) => Some(format!("`{text}` does not apply to `{lhs}`")),
            (_, b) if self.is_object(b) => Some(format!("`{text}` does not apply to `{rhs}`")),
            _ => None,
        };
        if let Some(message) = problem {
            let hint = if identity { " (objects compare with objects or `null`)" } else { "" };
            self.sink.error(DiagnosticCode::OperandType, bin.syntax().text_range(), format!("{message}{hint}"));
        }
    }

    /// `scratch` of `shared int scratch`, a parameter, local or field of the owner: work-group
    /// memory.
    fn is_shared_memory(&self, expr: &ast::Expr) -> bool {
        let ast::Expr::NameExpr(name) = expr else { return false };
        let Some(name) = name.name_ref().map(|n| n.text()) else { return false };
        if self.locals.contains_key(&name) {
            return self.shared_memory.contains(&name);
        }
        let shared_field = |ty: &crate::hir::items::TypeItem| {
            ty.fields.iter().find(|f| f.name == name).map(|f| f.qualifiers.iter().any(|q| q == "shared"))
        };
        self.owner.and_then(|owner| self.sema.find_member(&owner.fqn, &shared_field)).is_some_and(|(_, shared)| shared)
    }

    /// A class or interface object, or an opaque GPU type (an image, a sampler): no number.
    fn is_object(&self, ty: &Ty) -> bool {
        match ty {
            Ty::Gpu(_) => true,
            Ty::Named(fqn) => self.sema.definition(fqn).is_some_and(|def| match &def.kind {
                DefKind::Type(item) => !matches!(item.kind, TypeKind::Enum),
                _ => false,
            }),
            _ => false,
        }
    }

    /// `!e` is `bool`; `ref g` a reference to what `g` holds; `++`/`--` need something
    /// mutable; the others have their operand's type.
    pub(super) fn prefix(&mut self, p: &ast::PrefixExpr) -> Ty {
        let op = p.op().map(|t| t.kind());
        match (op, p.operand()) {
            (Some(SyntaxKind::PLUS2 | SyntaxKind::MINUS2), Some(target)) => self.expect_mutable(&target),
            (Some(SyntaxKind::REF_KW), Some(target)) => self.expect_lvalue(&target, "referenced (`ref`)"),
            _ => {}
        }
        let operand = p.operand().map_or(Ty::Unknown, |e| self.infer(&e));
        match op {
            Some(SyntaxKind::BANG) => Ty::Bool,
            // `ref g`: a reference to what `g` holds.
            Some(SyntaxKind::REF_KW) => match operand {
                Ty::Ref { .. } | Ty::Unknown => operand,
                value => Ty::Ref { global: false, inner: Box::new(value) },
            },
            _ => operand.dereferenced().clone(),
        }
    }

    /// `e++`, `e--`: `e` must be mutable; the type is `e`'s.
    pub(super) fn postfix(&mut self, p: &ast::PostfixExpr) -> Ty {
        let operand = p.operand();
        if let Some(target) = &operand {
            self.expect_mutable(target);
        }
        operand.map_or(Ty::Unknown, |e| self.infer(&e))
    }

    /// `c ? a : b`: a `bool` condition; the type is the first branch's.
    pub(super) fn ternary(&mut self, t: &ast::TernaryExpr) -> Ty {
        if let Some(cond) = t.condition() {
            self.expect_bool(&cond, "the condition of `?:`");
        }
        let then = t.then_expr().map_or(Ty::Unknown, |e| self.infer(&e));
        if let Some(e) = t.else_expr() {
            self.infer(&e);
        }
        then
    }

    /// `base[i]`: an element of an array, a vector or a referenced buffer.
    pub(super) fn index(&mut self, i: &ast::IndexExpr) -> Ty {
        if let Some(index) = i.index() {
            self.infer(&index);
        }
        let base = i.base().map_or(Ty::Unknown, |b| self.infer(&b));
        match base {
            // `elements[i]` of a `global ref unsigned int` buffer: its elements.
            Ty::Ref { inner, .. } => match *inner {
                Ty::Array(element) => *element,
                Ty::Vector(element, _) => *element,
                element => element,
            },
            Ty::Array(inner) => *inner,
            Ty::Vector(base, _) => *base,
            Ty::Int | Ty::UInt | Ty::Float | Ty::Bool => {
                let Some(indexed) = i.base() else { return Ty::Unknown };
                if self.is_shared_memory(&indexed) {
                    return base;
                }
                self.sink.error(
                    DiagnosticCode::OperandType,
                    indexed.syntax().text_range(),
                    format!(
                        "`{}` is `{base}`: only arrays, vectors, buffers (`ref`) and containers are indexed",
                        excerpt(indexed.syntax())
                    ),
                );
                Ty::Unknown
            }
            _ => Ty::Unknown,
        }
    }

    /// `receiver.member`: a field of a class, or a vector's swizzle.
    pub(super) fn member(&mut self, m: &ast::MemberExpr) -> Ty {
        let receiver = m.receiver().map_or(Ty::Unknown, |r| self.infer(&r));
        let Some(member) = m.member() else { return Ty::Unknown };
        match receiver.dereferenced().clone() {
            // Swizzles: `v._x`, `v.x`, `v.xy`, `v.s01`, `v.lo`.
            Ty::Vector(base, width) => match swizzle_width(&member.text(), width) {
                Some(1) => *base,
                Some(n) => Ty::Vector(base, n),
                None => {
                    let vector = Ty::Vector(base, width);
                    let names =
                        ["x", "y", "z", "w"].iter().take(usize::from(width).min(4)).copied().collect::<Vec<_>>();
                    self.sink.error(
                        DiagnosticCode::UnknownMember,
                        member.syntax().text_range(),
                        format!(
                            "`{vector}` has no component `{}`: its components are {} (or `s0`…, `lo`, `hi`, `even`, `odd`)",
                            member.text(),
                            names.join(", ")
                        ),
                    );
                    Ty::Unknown
                }
            },
            Ty::Named(fqn) => self.field_ty(&fqn, &member.text(), member.syntax()),
            _ => Ty::Unknown,
        }
    }

    /// `Scope::member`: a field of the class the scope names.
    pub(super) fn scope_member(&mut self, s: &ast::ScopeExpr) -> Ty {
        let scope = s.scope().map_or(Ty::Unknown, |r| self.infer(&r));
        match (scope, s.member()) {
            (Ty::Named(fqn), Some(member)) => self.field_ty(&fqn, &member.text(), member.syntax()),
            _ => Ty::Unknown,
        }
    }
}
