//! Expressions that branch, as blocks of native code: `&&` and `||` evaluate their right side
//! only when it decides, `?:` only the branch taken (both in one kind).

use cranelift_codegen::ir::{types, InstBuilder, Value as Ir};

use super::{ir_type, Emitter, Kind};
use crate::run::ir::Expr;

impl Emitter<'_> {
    /// `l && r` (`and`) or `l || r`, short-circuited, as a `bool`.
    pub(super) fn short_circuit(&mut self, and: bool, l: &Expr, r: &Expr) -> Ir {
        let l = self.truth(l);
        let (right, merge) = (self.b.create_block(), self.b.create_block());
        self.b.append_block_param(merge, types::I8);
        let short = self.b.ins().iconst(types::I8, (!and) as i64);
        if and {
            self.b.ins().brif(l, right, &[], merge, &[short.into()]);
        } else {
            self.b.ins().brif(l, merge, &[short.into()], right, &[]);
        }
        self.b.switch_to_block(right);
        let r = self.truth(r);
        self.b.ins().jump(merge, &[r.into()]);
        self.b.switch_to_block(merge);
        self.b.block_params(merge)[0]
    }

    /// `condition ? a : b`, both branches of `kind`.
    pub(super) fn ternary(&mut self, condition: &Expr, a: &Expr, b: &Expr, kind: Kind) -> Ir {
        let condition = self.truth(condition);
        let (then_block, else_block, merge) = (self.b.create_block(), self.b.create_block(), self.b.create_block());
        self.b.append_block_param(merge, ir_type(kind));
        self.b.ins().brif(condition, then_block, &[], else_block, &[]);
        for (block, branch) in [(then_block, a), (else_block, b)] {
            self.b.switch_to_block(block);
            let value = self.expr(branch, kind);
            self.b.ins().jump(merge, &[value.into()]);
        }
        self.b.switch_to_block(merge);
        self.b.block_params(merge)[0]
    }
}
