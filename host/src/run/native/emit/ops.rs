//! The operations of native code: C's conversions between `int`, `unsigned int`, `double` and
//! `bool`, its integer and floating-point arithmetic and comparisons, and element addresses
//! checked against their memory, with the loads and stores through them.

use cranelift_codegen::ir::{
    condcodes::{FloatCC, IntCC},
    types, InstBuilder, MemFlagsData, Value as Ir,
};

use super::{Base, Emitter, Kind, NativeError};
use crate::run::{
    arith::undefined,
    ir::{Arith, BinOp, CmpOp, Expr, Span},
    value::Scalar,
};

impl Emitter<'_> {
    /// C's conversion of a number of kind `from` to `to` (as the closures' `int`, `float` and
    /// `truth` do it).
    pub(super) fn convert(&mut self, value: Ir, from: Kind, to: Kind) -> Ir {
        let ins = self.b.ins();
        match (from, to) {
            (a, b) if a == b => value,
            (Kind::Int | Kind::UInt, Kind::Int | Kind::UInt) => value,
            (Kind::Int, Kind::Float) => ins.fcvt_from_sint(types::F64, value),
            (Kind::UInt, Kind::Float) => ins.fcvt_from_uint(types::F64, value),
            (Kind::Bool, Kind::Float) => {
                let wide = ins.uextend(types::I32, value);
                self.b.ins().fcvt_from_uint(types::F64, wide)
            }
            (Kind::Float, Kind::Int | Kind::UInt) => {
                let wide = ins.fcvt_to_sint_sat(types::I64, value);
                self.b.ins().ireduce(types::I32, wide)
            }
            (Kind::Bool, Kind::Int | Kind::UInt) => ins.uextend(types::I32, value),
            (Kind::Int | Kind::UInt, Kind::Bool) => ins.icmp_imm_s(IntCC::NotEqual, value, 0),
            (Kind::Float, Kind::Bool) => {
                let zero = ins.f64const(0.0);
                self.b.ins().fcmp(FloatCC::NotEqual, value, zero)
            }
            _ => unreachable!("every pair of kinds is above"),
        }
    }

    /// `l op r` in the arithmetic `arith` (operands of its kind).
    pub(super) fn binary(&mut self, op: BinOp, arith: Arith, l: Ir, r: Ir, span: Span) -> Ir {
        let undefined = |arith| NativeError::Undefined { span, message: undefined(op, arith) };
        if arith == Arith::Float {
            return match op {
                BinOp::Add => self.b.ins().fadd(l, r),
                BinOp::Sub => self.b.ins().fsub(l, r),
                BinOp::Mul => self.b.ins().fmul(l, r),
                BinOp::Div => self.b.ins().fdiv(l, r),
                BinOp::Rem => {
                    let call = self.b.ins().call(self.helpers[1], &[l, r]);
                    self.b.inst_results(call)[0]
                }
                _ => {
                    self.fail(undefined(arith), None);
                    self.b.ins().f64const(0.0)
                }
            };
        }
        let unsigned = arith == Arith::UInt;
        match op {
            BinOp::Add => self.b.ins().iadd(l, r),
            BinOp::Sub => self.b.ins().isub(l, r),
            BinOp::Mul => self.b.ins().imul(l, r),
            BinOp::Div | BinOp::Rem => {
                let zero = self.b.ins().icmp_imm_s(IntCC::Equal, r, 0);
                self.fail_if(zero, undefined(arith), None);
                if unsigned {
                    return match op {
                        BinOp::Div => self.b.ins().udiv(l, r),
                        _ => self.b.ins().urem(l, r),
                    };
                }
                // INT_MIN / -1 wraps (and its remainder is 0) where the machine would trap.
                let minus_one = self.b.ins().icmp_imm_s(IntCC::Equal, r, -1);
                let one = self.b.ins().iconst(types::I32, 1);
                let divisor = self.b.ins().select(minus_one, one, r);
                match op {
                    BinOp::Div => {
                        let quotient = self.b.ins().sdiv(l, divisor);
                        let negated = self.b.ins().ineg(l);
                        self.b.ins().select(minus_one, negated, quotient)
                    }
                    _ => self.b.ins().srem(l, divisor),
                }
            }
            BinOp::Shl => self.b.ins().ishl(l, r),
            BinOp::Shr if unsigned => self.b.ins().ushr(l, r),
            BinOp::Shr => self.b.ins().sshr(l, r),
            BinOp::BitAnd => self.b.ins().band(l, r),
            BinOp::BitOr => self.b.ins().bor(l, r),
            BinOp::BitXor => self.b.ins().bxor(l, r),
        }
    }

    pub(super) fn compare(&mut self, op: CmpOp, arith: Arith, l: Ir, r: Ir) -> Ir {
        if arith == Arith::Float {
            // Ordered comparisons; `!=` holds for NaN.
            let cc = match op {
                CmpOp::Eq => FloatCC::Equal,
                CmpOp::Ne => FloatCC::NotEqual,
                CmpOp::Lt => FloatCC::LessThan,
                CmpOp::Le => FloatCC::LessThanOrEqual,
                CmpOp::Gt => FloatCC::GreaterThan,
                CmpOp::Ge => FloatCC::GreaterThanOrEqual,
            };
            return self.b.ins().fcmp(cc, l, r);
        }
        let unsigned = arith == Arith::UInt;
        let cc = match op {
            CmpOp::Eq => IntCC::Equal,
            CmpOp::Ne => IntCC::NotEqual,
            CmpOp::Lt if unsigned => IntCC::UnsignedLessThan,
            CmpOp::Le if unsigned => IntCC::UnsignedLessThanOrEqual,
            CmpOp::Gt if unsigned => IntCC::UnsignedGreaterThan,
            CmpOp::Ge if unsigned => IntCC::UnsignedGreaterThanOrEqual,
            CmpOp::Lt => IntCC::SignedLessThan,
            CmpOp::Le => IntCC::SignedLessThanOrEqual,
            CmpOp::Gt => IntCC::SignedGreaterThan,
            CmpOp::Ge => IntCC::SignedGreaterThanOrEqual,
        };
        self.b.ins().icmp(cc, l, r)
    }

    /// The address of element `at` of the pointer `base`, checked to lie inside its memory.
    pub(super) fn element(&mut self, base: &Expr, at: Ir, span: Span) -> Ir {
        let Expr::Var(slot) = base else {
            self.supported = false;
            return self.b.ins().iconst(types::I64, 0);
        };
        let Some(&Base { number, element, base, offset, starts }) = self.bases.get(slot) else {
            self.supported = false;
            return self.b.ins().iconst(types::I64, 0);
        };
        let index = self.b.ins().sextend(types::I64, at);
        // Element sizes are 1, 2, 4 or 8 bytes.
        let bytes = self.b.ins().ishl_imm_s(index, element.size().trailing_zeros() as i64);
        let start = self.b.ins().iadd(bytes, offset);
        // Negative starts are huge unsigned ones.
        let outside = self.b.ins().icmp(IntCC::UnsignedGreaterThanOrEqual, start, starts);
        self.fail_if(outside, NativeError::Outside { span, pointer: number }, Some(index));
        self.b.ins().iadd(base, start)
    }

    pub(super) fn pointer_element(&self, base: &Expr) -> Scalar {
        match base {
            Expr::Var(slot) => self.bases.get(slot).map_or(Scalar::U8, |base| base.element),
            _ => Scalar::U8,
        }
    }

    /// The element at `address`, in its kind.
    pub(super) fn load(&mut self, base: &Expr, address: Ir) -> Ir {
        let flags = MemFlagsData::new().with_notrap();
        let element = self.pointer_element(base);
        let ins = self.b.ins();
        match element {
            Scalar::I8 => ins.sload8(types::I32, flags, address, 0),
            Scalar::U8 => ins.uload8(types::I32, flags, address, 0),
            Scalar::I16 => ins.sload16(types::I32, flags, address, 0),
            Scalar::U16 => ins.uload16(types::I32, flags, address, 0),
            Scalar::I32 | Scalar::U32 => ins.load(types::I32, flags, address, 0),
            Scalar::F32 => {
                let single = ins.load(types::F32, flags, address, 0);
                self.b.ins().fpromote(types::F64, single)
            }
            Scalar::F64 => ins.load(types::F64, flags, address, 0),
        }
    }

    /// Stores `value` (of `kind`) at `address`, converted as C converts on assignment.
    pub(super) fn store(&mut self, base: &Expr, address: Ir, value: Ir, kind: Kind) {
        let flags = MemFlagsData::new().with_notrap();
        match self.pointer_element(base) {
            element @ (Scalar::F32 | Scalar::F64) => {
                let double = self.convert(value, kind, Kind::Float);
                let stored = match element {
                    Scalar::F32 => self.b.ins().fdemote(types::F32, double),
                    _ => double,
                };
                self.b.ins().store(flags, stored, address, 0);
            }
            element => {
                let bits = self.convert(value, kind, Kind::Int);
                match element.size() {
                    1 => self.b.ins().istore8(flags, bits, address, 0),
                    2 => self.b.ins().istore16(flags, bits, address, 0),
                    _ => self.b.ins().store(flags, bits, address, 0),
                };
            }
        }
    }
}
