//! The types of operations: comparisons and logic are `bool`; arithmetic follows C's usual
//! arithmetic conversions (floating point wins, then unsigned), a shift has the type of what it
//! shifts; assignments are checked against their target.

use super::InferenceCtx;
use crate::{ast, hir::Ty, syntax::SyntaxKind};

impl InferenceCtx<'_, '_> {
    pub(super) fn binary(&mut self, bin: &ast::BinExpr) -> Ty {
        let lhs = bin.lhs().map_or(Ty::Unknown, |e| self.infer(&e));
        let rhs = bin.rhs().map_or(Ty::Unknown, |e| self.infer(&e));
        if bin.is_assignment() {
            return self.assignment(bin, lhs, rhs);
        }
        // Arithmetic reads through references.
        let (lhs, rhs) = (lhs.dereferenced().clone(), rhs.dereferenced().clone());
        let Some(op) = bin.op().map(|t| t.kind()) else { return Ty::Unknown };
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
}
