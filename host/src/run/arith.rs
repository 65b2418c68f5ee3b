//! C's arithmetic and conversions on the interpreter's values: `int` and `unsigned int`
//! operations (wrapping, shifts modulo 32), floating point (`%` as `fmod`), comparisons,
//! implicit conversions on assignment, truth of a condition, and indexing through a pointer.

use super::{
    ir::{Arith, BinOp, CmpOp, Conv},
    value::{Pointer, Value},
};

/// What `base[…]` indexes: a pointer, or why not.
#[inline]
pub(super) fn pointer(base: &Value) -> Result<&Pointer, String> {
    match base {
        Value::Ptr(p) => Ok(p),
        other => Err(format!("indexing a {}", describe(other))),
    }
}

fn describe(value: &Value) -> String {
    match value {
        Value::Null | Value::Void => "null pointer (nothing was allocated)".into(),
        other => other.kind().into(),
    }
}

/// A value as a condition: numbers are true when not zero, pointers and objects when not null.
#[inline]
pub(super) fn truthy(value: &Value) -> bool {
    match value {
        Value::Bool(b) => *b,
        Value::Int(v) => *v != 0,
        Value::UInt(v) => *v != 0,
        Value::Float(v) => *v != 0.0,
        Value::Void | Value::Null => false,
        Value::Str(_) | Value::Ptr(_) | Value::Object(_) => true,
    }
}

/// A number as a C `int` (wrapping, truncating).
#[inline]
pub(super) fn int(value: &Value) -> i32 {
    match value {
        Value::Int(v) => *v,
        Value::UInt(v) => *v as i32,
        Value::Bool(b) => *b as i32,
        Value::Float(v) => *v as i64 as i32,
        _ => 0,
    }
}

#[inline]
pub(super) fn float(value: &Value) -> f64 {
    value.number().map_or(0.0, |n| n.as_f64())
}

/// `value` converted as C converts it on assignment.
pub(super) fn convert(conv: Conv, value: Value) -> Result<Value, String> {
    Ok(match conv {
        Conv::Keep => value,
        Conv::Bool => Value::Bool(truthy(&value)),
        Conv::Int => match value {
            Value::Int(_) => value,
            ref v if v.number().is_some() => Value::Int(int(v)),
            other => return Err(format!("a {} is not a number", other.kind())),
        },
        Conv::UInt => match value {
            Value::UInt(_) => value,
            ref v if v.number().is_some() => Value::UInt(int(v) as u32),
            other => return Err(format!("a {} is not a number", other.kind())),
        },
        Conv::Float => match value.number() {
            Some(n) => Value::Float(n.as_f64()),
            None => return Err(format!("a {} is not a number", value.kind())),
        },
        Conv::Pointer(element) => match value {
            Value::Ptr(p) if p.element == element => Value::Ptr(p),
            Value::Ptr(p) => Value::Ptr(p.cast(element)),
            Value::Null | Value::Void => Value::Null,
            other => return Err(format!("a {} is not a pointer", other.kind())),
        },
    })
}

pub(super) fn binary(op: BinOp, arith: Arith, l: &Value, r: &Value) -> Result<Value, String> {
    Ok(match arith {
        Arith::Int => Value::Int(int_binary(op, int(l), int(r)).ok_or_else(|| undefined(op, arith))?),
        Arith::UInt => Value::UInt(uint_binary(op, int(l) as u32, int(r) as u32).ok_or_else(|| undefined(op, arith))?),
        Arith::Float => Value::Float(float_binary(op, float(l), float(r)).ok_or_else(|| undefined(op, arith))?),
    })
}

/// Why `op` in `arith` has no result: the message for a `None` of the operations below.
#[cold]
pub(super) fn undefined(_op: BinOp, arith: Arith) -> String {
    match arith {
        Arith::Float => "a bit operation on floating-point numbers".into(),
        _ => "division by zero".into(),
    }
}

/// C's floating-point arithmetic (`%` as `fmod`); `None` for a bit operation.
#[inline]
pub(super) fn float_binary(op: BinOp, a: f64, b: f64) -> Option<f64> {
    Some(match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
        _ => return None,
    })
}

/// C's `int` arithmetic (wrapping; shifts by the amount modulo 32); `None` for a division by
/// zero.
#[inline]
pub(super) fn int_binary(op: BinOp, a: i32, b: i32) -> Option<i32> {
    Some(match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        BinOp::Div | BinOp::Rem if b == 0 => return None,
        BinOp::Div => a.wrapping_div(b),
        BinOp::Rem => a.wrapping_rem(b),
        BinOp::Shl => a.wrapping_shl(b as u32),
        BinOp::Shr => a.wrapping_shr(b as u32),
        BinOp::BitAnd => a & b,
        BinOp::BitOr => a | b,
        BinOp::BitXor => a ^ b,
    })
}

/// C's `unsigned int` arithmetic; `None` for a division by zero.
#[inline]
pub(super) fn uint_binary(op: BinOp, a: u32, b: u32) -> Option<u32> {
    Some(match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        BinOp::Div | BinOp::Rem if b == 0 => return None,
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
        BinOp::Shl => a.wrapping_shl(b),
        BinOp::Shr => a.wrapping_shr(b),
        BinOp::BitAnd => a & b,
        BinOp::BitOr => a | b,
        BinOp::BitXor => a ^ b,
    })
}

pub(super) fn ordered(op: CmpOp, ordering: std::cmp::Ordering) -> bool {
    match op {
        CmpOp::Eq => ordering.is_eq(),
        CmpOp::Ne => ordering.is_ne(),
        CmpOp::Lt => ordering.is_lt(),
        CmpOp::Le => ordering.is_le(),
        CmpOp::Gt => ordering.is_gt(),
        CmpOp::Ge => ordering.is_ge(),
    }
}

/// `==` of non-numbers: the same memory and address, the same object, both null, equal text.
pub(super) fn same(l: &Value, r: &Value) -> bool {
    match (l, r) {
        (Value::Null | Value::Void, Value::Null | Value::Void) => true,
        (Value::Ptr(a), Value::Ptr(b)) => std::rc::Rc::ptr_eq(&a.memory, &b.memory) && a.offset == b.offset,
        (Value::Object(a), Value::Object(b)) => std::rc::Rc::ptr_eq(a, b),
        (Value::Str(a), Value::Str(b)) => a == b,
        (a, b) => match (a.number(), b.number()) {
            (Some(a), Some(b)) => a.as_f64() == b.as_f64(),
            _ => false,
        },
    }
}
