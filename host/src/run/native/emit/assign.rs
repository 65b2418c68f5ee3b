//! Assignments in native code: `=` to a variable or an element (the value converted to the
//! place's kind), and updates (`++`, `--`, `+=` …) computed in their arithmetic and stored back
//! in the place's kind, giving the old value after a postfix operator.

use cranelift_codegen::ir::Value as Ir;

use super::{arith_kind, Emitter, Kind};
use crate::run::ir::{Arith, BinOp, Expr, Place, Span};

impl Emitter<'_> {
    /// `place = value`, whose value is the one assigned.
    pub(super) fn assigned(&mut self, place: &Place, value: &Expr) -> Ir {
        let (value, kind) = self.natural(value);
        match place {
            &Place::Var(slot, conv) => {
                let (var, to) = self.vars[&slot];
                debug_assert_eq!(Kind::of_conv(conv), Some(to));
                let converted = self.convert(value, kind, to);
                self.b.def_var(var, converted);
            }
            Place::Index(base, at, span) => {
                let at = self.expr(at, Kind::Int);
                let address = self.element(base, at, *span);
                self.store(base, address, value, kind);
            }
        }
        value
    }

    /// `place op= operand` (or `++`/`--`): the new value, or the old one after a postfix
    /// operator.
    pub(super) fn updated(
        &mut self,
        place: &Place,
        (op, arith): (BinOp, Arith),
        operand: &Expr,
        postfix: bool,
        span: Span,
    ) -> Ir {
        let computed = arith_kind(arith);
        let (old, new) = match *place {
            Place::Var(slot, _) => {
                let operand = self.expr(operand, computed);
                let (var, var_kind) = self.vars[&slot];
                let old = self.b.use_var(var);
                let left = self.convert(old, var_kind, computed);
                let new = self.binary(op, arith, left, operand, span);
                let stored = self.convert(new, computed, var_kind);
                self.b.def_var(var, stored);
                (old, new)
            }
            Place::Index(ref base, ref at, at_span) => {
                let operand = self.expr(operand, computed);
                let at = self.expr(at, Kind::Int);
                let address = self.element(base, at, at_span);
                let old = self.load(base, address);
                let old_kind = self.element_kind(base);
                let left = self.convert(old, old_kind, computed);
                let new = self.binary(op, arith, left, operand, at_span);
                self.store(base, address, new, computed);
                (old, new)
            }
        };
        if postfix {
            old
        } else {
            new
        }
    }
}
