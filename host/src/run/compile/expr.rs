//! Expressions in each of the types they are used as. `int`, `float` and `truth` compute the
//! arithmetic, comparisons and element reads they know on machine numbers and leave the rest
//! to `value`, converting its result as C does; `value` makes the number a [`Value`] only where
//! one is needed. `numeric` says, before the run, which expressions are sure to give a number.

use super::{
    super::{
        arith::{convert, float, float_binary, int, int_binary, ordered, same, truthy, uint_binary, undefined},
        framework::Method,
        ir::{Arith, CmpOp, Conv, Expr, Place, Slot},
        machine::{failed, Flow, Machine, Outcome},
        value::{Number, Value},
        RunError,
    },
    code, Code, Compiler,
};

/// An `int` operand: a variable or a constant is read in place, anything else is run.
pub(super) enum IntOperand {
    Var(Slot),
    Const(i32),
    Code(Code<i32>),
}

impl IntOperand {
    #[inline(always)]
    pub(super) fn get(&self, m: &mut Machine<'_, '_>) -> Outcome<i32> {
        match self {
            IntOperand::Var(slot) => Ok(int(&m.frame[*slot])),
            IntOperand::Const(value) => Ok(*value),
            IntOperand::Code(code) => code(m),
        }
    }
}

impl Compiler<'_> {
    /// `expr` as an `int` operand.
    pub(super) fn int_operand(&self, expr: &Expr) -> IntOperand {
        match expr {
            &Expr::Var(slot) => IntOperand::Var(slot),
            Expr::Const(value) => IntOperand::Const(int(&value.value())),
            Expr::Convert(Conv::Int | Conv::UInt, inner) if self.numeric(inner) => self.int_operand(inner),
            other => IntOperand::Code(self.int(other)),
        }
    }

    /// `expr` as a C `int` (the bits of an `unsigned int`).
    pub(super) fn int(&self, expr: &Expr) -> Code<i32> {
        match expr {
            Expr::Const(value) => {
                let value = int(&value.value());
                code(move |_| Ok(value))
            }
            &Expr::Var(slot) => code(move |m| Ok(int(&m.frame[slot]))),
            &Expr::Binary(op, arith @ (Arith::Int | Arith::UInt), ref l, ref r, span) => {
                let (l, r) = (self.int_operand(l), self.int_operand(r));
                code(move |m| {
                    let (l, r) = (l.get(m)?, r.get(m)?);
                    match arith {
                        Arith::UInt => uint_binary(op, l as u32, r as u32).map(|v| v as i32),
                        _ => int_binary(op, l, r),
                    }
                    .ok_or_else(|| failed(span, undefined(op, arith)))
                })
            }
            Expr::Call(Method::Rand, args, _) if args.is_empty() => code(|m| Ok(m.framework.rand())),
            Expr::Binary(_, Arith::Float, ..) => {
                let value = self.float(expr);
                code(move |m| Ok(value(m)? as i64 as i32))
            }
            Expr::Convert(Conv::Int | Conv::UInt, inner) if self.numeric(inner) => self.int(inner),
            Expr::Compare(..) | Expr::And(..) | Expr::Or(..) | Expr::Not(_) => {
                let truth = self.truth(expr);
                code(move |m| Ok(truth(m)? as i32))
            }
            Expr::Index(base, at, span) => {
                self.element(base, at, *span, |_| Ok(()), |p, at, ()| p.load(at).map(|n| n.as_i64() as i32))
            }
            other => {
                let value = self.value(other);
                code(move |m| Ok(int(&value(m)?)))
            }
        }
    }

    /// `expr` as a floating-point number.
    pub(super) fn float(&self, expr: &Expr) -> Code<f64> {
        match expr {
            Expr::Const(value) => {
                let value = float(&value.value());
                code(move |_| Ok(value))
            }
            &Expr::Var(slot) => code(move |m| Ok(float(&m.frame[slot]))),
            &Expr::Binary(op, Arith::Float, ref l, ref r, span) => {
                let (l, r) = (self.float(l), self.float(r));
                code(move |m| float_binary(op, l(m)?, r(m)?).ok_or_else(|| failed(span, undefined(op, Arith::Float))))
            }
            Expr::Binary(_, Arith::UInt, ..) => {
                let value = self.int(expr);
                code(move |m| Ok(value(m)? as u32 as f64))
            }
            Expr::Binary(_, Arith::Int, ..) => {
                let value = self.int(expr);
                code(move |m| Ok(value(m)? as f64))
            }
            Expr::Convert(Conv::Float, inner) if self.numeric(inner) => self.float(inner),
            Expr::Index(base, at, span) => {
                self.element(base, at, *span, |_| Ok(()), |p, at, ()| p.load(at).map(Number::as_f64))
            }
            other => {
                let value = self.value(other);
                code(move |m| Ok(float(&value(m)?)))
            }
        }
    }

    /// `expr` as a condition.
    pub(super) fn truth(&self, expr: &Expr) -> Code<bool> {
        match expr {
            &Expr::Compare(op, arith @ (Arith::Int | Arith::UInt), ref l, ref r) => {
                let (l, r) = (self.int_operand(l), self.int_operand(r));
                code(move |m| {
                    let (l, r) = (l.get(m)?, r.get(m)?);
                    Ok(ordered(op, if arith == Arith::UInt { (l as u32).cmp(&(r as u32)) } else { l.cmp(&r) }))
                })
            }
            &Expr::Compare(op, Arith::Float, ref l, ref r) => {
                let (l, r) = (self.float(l), self.float(r));
                code(move |m| {
                    let (l, r) = (l(m)?, r(m)?);
                    // NaN: only `!=` holds.
                    Ok(l.partial_cmp(&r).map_or(op == CmpOp::Ne, |ordering| ordered(op, ordering)))
                })
            }
            Expr::And(l, r) => {
                let (l, r) = (self.truth(l), self.truth(r));
                code(move |m| Ok(l(m)? && r(m)?))
            }
            Expr::Or(l, r) => {
                let (l, r) = (self.truth(l), self.truth(r));
                code(move |m| Ok(l(m)? || r(m)?))
            }
            Expr::Not(inner) => {
                let inner = self.truth(inner);
                code(move |m| Ok(!inner(m)?))
            }
            Expr::Convert(Conv::Bool, inner) => self.truth(inner),
            other => {
                let value = self.value(other);
                code(move |m| Ok(truthy(&value(m)?)))
            }
        }
    }

    /// `expr` as a [`Number`] to store in memory, where it is sure to be one; `None` where it
    /// may be something else (then the value is stored, and refused if it is not a number).
    pub(super) fn number(&self, expr: &Expr) -> Option<Code<Number>> {
        let as_int = |value: Code<i32>| code(move |m| Ok(Number::Int(value(m)? as i64)));
        let as_uint = |value: Code<i32>| code(move |m| Ok(Number::Int(value(m)? as u32 as i64)));
        Some(match expr {
            Expr::Index(base, at, span) => {
                self.element(base, at, *span, |_| Ok(()), |pointer, at, ()| pointer.load(at))
            }
            Expr::Binary(_, Arith::Int, ..) | Expr::Convert(Conv::Int, _) if self.numeric(expr) => {
                as_int(self.int(expr))
            }
            Expr::Binary(_, Arith::UInt, ..) | Expr::Convert(Conv::UInt, _) if self.numeric(expr) => {
                as_uint(self.int(expr))
            }
            Expr::Binary(_, Arith::Float, ..) | Expr::Convert(Conv::Float, _) if self.numeric(expr) => {
                let value = self.float(expr);
                code(move |m| Ok(Number::Float(value(m)?)))
            }
            &Expr::Var(slot) => match self.slots[slot] {
                Conv::Int | Conv::UInt | Conv::Float | Conv::Bool => code(move |m| {
                    let value = &m.frame[slot];
                    value.number().ok_or_else(|| {
                        let message = format!("a {} cannot be stored in memory of numbers", value.kind());
                        Box::new(RunError::failed(None, message))
                    })
                }),
                _ => return None,
            },
            _ => return None,
        })
    }

    /// Whether `expr` gives a number (or stops the run) whatever the values it reads: then
    /// `int`, `float` and `truth` of it are what C's conversions make of its value.
    pub(super) fn numeric(&self, expr: &Expr) -> bool {
        let numeric_conv = |conv: Conv| matches!(conv, Conv::Bool | Conv::Int | Conv::UInt | Conv::Float);
        match expr {
            Expr::Const(value) => value.value().number().is_some(),
            &Expr::Var(slot) => numeric_conv(self.slots[slot]),
            Expr::Binary(..)
            | Expr::Compare(..)
            | Expr::Same(..)
            | Expr::And(..)
            | Expr::Or(..)
            | Expr::Not(_)
            | Expr::Negate(..)
            | Expr::BitNot(..)
            | Expr::Index(..) => true,
            Expr::Convert(conv, inner) => numeric_conv(*conv) && (*conv == Conv::Bool || self.numeric(inner)),
            Expr::Update(place, ..) => matches!(place.as_ref(), Place::Var(_, conv) if numeric_conv(*conv)),
            Expr::Ternary(_, a, b) => self.numeric(a) && self.numeric(b),
            _ => false,
        }
    }

    /// `expr` as a value.
    pub(super) fn value(&self, expr: &Expr) -> Code<Value> {
        match expr {
            Expr::Const(value) => {
                let value = value.clone();
                code(move |_| Ok(value.value()))
            }
            &Expr::Var(slot) => code(move |m| Ok(m.frame[slot].clone())),
            Expr::Binary(_, Arith::Int, ..) => {
                let value = self.int(expr);
                code(move |m| Ok(Value::Int(value(m)?)))
            }
            Expr::Binary(_, Arith::UInt, ..) => {
                let value = self.int(expr);
                code(move |m| Ok(Value::UInt(value(m)? as u32)))
            }
            Expr::Binary(_, Arith::Float, ..) => {
                let value = self.float(expr);
                code(move |m| Ok(Value::Float(value(m)?)))
            }
            Expr::Compare(..) | Expr::And(..) | Expr::Or(..) | Expr::Not(_) => {
                let truth = self.truth(expr);
                code(move |m| Ok(Value::Bool(truth(m)?)))
            }
            &Expr::Same(equal, ref l, ref r) => {
                let (l, r) = (self.value(l), self.value(r));
                code(move |m| Ok(Value::Bool(same(&l(m)?, &r(m)?) == equal)))
            }
            &Expr::Negate(arith, ref inner) => self.negated(arith, inner),
            &Expr::BitNot(arith, ref inner) => {
                let inner = self.int(inner);
                match arith {
                    Arith::UInt => code(move |m| Ok(Value::UInt(!(inner(m)? as u32)))),
                    _ => code(move |m| Ok(Value::Int(!inner(m)?))),
                }
            }
            &Expr::Convert(conv, ref inner) => self.converted(conv, inner),
            &Expr::Offset(ref base, ref n, minus) => {
                let (base, n) = (self.value(base), self.int(n));
                code(move |m| {
                    let (base, n) = (base(m)?, n(m)? as i64);
                    match base {
                        Value::Ptr(p) => Ok(Value::Ptr(p.add(if minus { -n } else { n }))),
                        other => {
                            Err(Box::new(RunError::failed(None, format!("pointer arithmetic on a {}", other.kind()))))
                        }
                    }
                })
            }
            Expr::Index(base, at, span) => {
                self.element(base, at, *span, |_| Ok(()), |pointer, at, ()| pointer.read(at))
            }
            Expr::Assign(place, value) => self.assigned(place, value),
            &Expr::Update(ref place, op, arith, ref operand, postfix, span) => {
                self.update(place, op, arith, operand, postfix, span)
            }
            Expr::Ternary(c, a, b) => {
                let (c, a, b) = (self.truth(c), self.value(a), self.value(b));
                code(move |m| if c(m)? { a(m) } else { b(m) })
            }
            &Expr::Call(method, ref args, span) => {
                let args = self.arguments(args);
                code(move |m| {
                    let args = args(m)?;
                    m.call(method, &args, span)
                })
            }
            &Expr::NewArray(element, ref count, span) => {
                let count = self.value(count);
                code(move |m| {
                    let count = count(m)?;
                    m.new_array(element, &count, span)
                })
            }
            &Expr::CallDiagram { diagram, ref args, ref outs, span } => {
                let args = self.arguments(args);
                let outs: Vec<(Slot, Code<Flow>)> =
                    outs.iter().map(|out| (out.slot, self.assign(&out.place, &Expr::Var(out.slot)))).collect();
                code(move |m| {
                    let args = args(m)?;
                    let (result, values) = m.call_diagram(diagram, args, span)?;
                    for ((slot, store), value) in outs.iter().zip(values) {
                        m.frame[*slot] = value;
                        store(m)?;
                    }
                    Ok(result)
                })
            }
            &Expr::Launch(kernel, ref args, span) => {
                let args = self.arguments(args);
                code(move |m| {
                    let args = args(m)?;
                    m.launch_kernel(kernel, &args, span)
                })
            }
        }
    }

    /// `-inner` in its arithmetic (integers wrap, as C's do in practice).
    fn negated(&self, arith: Arith, inner: &Expr) -> Code<Value> {
        match arith {
            Arith::Int => {
                let inner = self.int(inner);
                code(move |m| Ok(Value::Int(inner(m)?.wrapping_neg())))
            }
            Arith::UInt => {
                let inner = self.int(inner);
                code(move |m| Ok(Value::UInt((inner(m)? as u32).wrapping_neg())))
            }
            Arith::Float => {
                let inner = self.float(inner);
                code(move |m| Ok(Value::Float(-inner(m)?)))
            }
        }
    }

    /// `inner` converted by `conv`: on machine numbers where it is a number.
    fn converted(&self, conv: Conv, inner: &Expr) -> Code<Value> {
        match conv {
            Conv::Int if self.numeric(inner) => {
                let inner = self.int(inner);
                code(move |m| Ok(Value::Int(inner(m)?)))
            }
            Conv::Float if self.numeric(inner) => {
                let inner = self.float(inner);
                code(move |m| Ok(Value::Float(inner(m)?)))
            }
            _ => {
                let inner = self.value(inner);
                code(move |m| convert(conv, inner(m)?).map_err(|message| Box::new(RunError::failed(None, message))))
            }
        }
    }

    /// `place = value`, whose value is the one assigned (before the place's conversion).
    fn assigned(&self, place: &Place, value: &Expr) -> Code<Value> {
        let value = self.value(value);
        match place {
            &Place::Var(slot, conv) => code(move |m| {
                let value = value(m)?;
                m.frame[slot] =
                    convert(conv, value.clone()).map_err(|message| Box::new(RunError::failed(None, message)))?;
                Ok(value)
            }),
            Place::Index(base, at, span) => self.element(base, at, *span, value, |pointer, at, value| {
                pointer.write(at, &value)?;
                Ok(value)
            }),
        }
    }

    /// The arguments of a call, evaluated in order.
    fn arguments(&self, args: &[Expr]) -> Code<Vec<Value>> {
        let args: Vec<Code<Value>> = args.iter().map(|arg| self.value(arg)).collect();
        code(move |m| args.iter().map(|arg| arg(m)).collect())
    }
}
