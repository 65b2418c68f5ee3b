//! Compiling a lowered program to closures before it runs. Every expression becomes a closure
//! of the type it is used as — an `int` (the bits of an `unsigned int` too), a floating-point
//! number, a condition, a value, or an effect whose value is not used — so that arithmetic,
//! comparisons and element accesses run on machine numbers in registers; only what is not a
//! number (pointers, objects, strings, framework calls) goes through [`Value`]s. Each closure
//! does what the C of its construct does, errors included; which closure a construct gets is
//! decided once, here, not on every evaluation.

mod expr;

use super::{
    arith::{binary, convert, float, float_binary, int, int_binary, pointer, uint_binary, undefined},
    ir::{Arith, BinOp, Conv, Expr, Place, Program, Slot, Span, Stmt},
    machine::{failed, run_block, Block, Code, Compiled, EdgeCode, Flow, Machine, NodeCode, Outcome},
    native,
    value::{Pointer, Value},
    RunError,
};

/// Compiles `program`; loops of numbers to machine code too where `native` (see `native/`).
pub(super) fn program(program: &Program, native: bool) -> Compiled {
    let compiler = Compiler { slots: &program.slots, native };
    let nodes = program.nodes.iter().map(|node| NodeCode {
        body: compiler.block(&node.body),
        edges: (node.edges.iter())
            .map(|edge| EdgeCode {
                guard: edge.guard.as_ref().map(|guard| compiler.truth(guard)),
                args: edge.args.iter().map(|(slot, value)| (*slot, compiler.value(value))).collect(),
                work: edge.work.iter().map(|work| compiler.int(work)).collect(),
                outs: (edge.outs.iter().zip(&program.nodes[edge.target].outs))
                    .map(|(place, param)| compiler.assign(place, &Expr::Var(*param)))
                    .collect(),
            })
            .collect(),
        result: node.result.as_ref().map(|result| compiler.value(result)),
    });
    let inits = program.diagrams.iter().map(|diagram| compiler.block(&diagram.init)).collect();
    Compiled { inits, nodes: nodes.collect() }
}

/// Boxes `f` as compiled code (the machine's lifetimes left free).
fn code<T>(f: impl Fn(&mut Machine<'_, '_>) -> Outcome<T> + 'static) -> Code<T> {
    Box::new(f)
}

/// An effect: `f`, whose value is not used.
fn effect<T>(f: impl Fn(&mut Machine<'_, '_>) -> Outcome<T> + 'static) -> Code<Flow> {
    code(move |m| f(m).map(|_| Flow::Next))
}

struct Compiler<'p> {
    /// Each slot's conversion ([`Program::slots`]).
    slots: &'p [Conv],
    /// Whether loops are compiled to machine code where they can be.
    native: bool,
}

impl Compiler<'_> {
    fn block(&self, stmts: &[Stmt]) -> Block {
        stmts.iter().map(|stmt| self.stmt(stmt)).collect()
    }

    fn stmt(&self, stmt: &Stmt) -> Code<Flow> {
        match stmt {
            Stmt::Expr(expr) => self.effect(expr),
            // The value is converted already; converting again keeps it as it is.
            Stmt::Declare(slot, value) => self.set(*slot, self.slots[*slot], value),
            Stmt::If(condition, then, other) => {
                let (condition, then, other) = (self.truth(condition), self.block(then), self.block(other));
                code(move |m| if condition(m)? { run_block(m, &then) } else { run_block(m, &other) })
            }
            Stmt::Loop { test, body, step, test_after } => {
                match self.native.then(|| native::compile(stmt, self.slots)).flatten() {
                    Some(native) => {
                        // The fallback's inner loops are part of the native code already.
                        let closures = Compiler { slots: self.slots, native: false };
                        let interpreted = closures.loop_closure(test.as_ref(), body, step, *test_after);
                        code(move |m| match native.run(m)? {
                            Some(flow) => Ok(flow),
                            None => interpreted(m),
                        })
                    }
                    // Loops inside it may still be native.
                    None => self.loop_closure(test.as_ref(), body, step, *test_after),
                }
            }
            Stmt::Switch(value, cases, default) => {
                let value = self.int(value);
                let cases: Vec<(i32, Block)> = cases.iter().map(|(label, body)| (*label, self.block(body))).collect();
                let default = self.block(default);
                code(move |m| {
                    let value = value(m)?;
                    let body = cases.iter().find(|(label, _)| *label == value).map_or(&default, |(_, body)| body);
                    Ok(match run_block(m, body)? {
                        Flow::Break => Flow::Next,
                        other => other,
                    })
                })
            }
            Stmt::Return => code(|_| Ok(Flow::Return)),
            Stmt::Break => code(|_| Ok(Flow::Break)),
            Stmt::Continue => code(|_| Ok(Flow::Continue)),
            Stmt::Block(stmts) => {
                let block = self.block(stmts);
                code(move |m| run_block(m, &block))
            }
            &Stmt::Flow(start) => code(move |m| {
                let container = m.node;
                let code = std::rc::Rc::clone(&m.code);
                m.flow(&code, start)?;
                m.node = container;
                Ok(Flow::Next)
            }),
        }
    }

    /// A loop of any form as closures (where the loop is not native code, or as the fallback of
    /// native code).
    fn loop_closure(&self, test: Option<&Expr>, body: &[Stmt], step: &[Stmt], test_after: bool) -> Code<Flow> {
        let test = test.map(|test| self.truth(test));
        let (body, step) = (self.block(body), self.block(step));
        code(move |m| {
            loop {
                if let (Some(test), false) = (&test, test_after) {
                    if !test(m)? {
                        break;
                    }
                }
                match run_block(m, &body)? {
                    Flow::Break => break,
                    Flow::Return => return Ok(Flow::Return),
                    Flow::Next | Flow::Continue => {}
                }
                run_block(m, &step)?;
                if let (Some(test), true) = (&test, test_after) {
                    if !test(m)? {
                        break;
                    }
                }
                m.iterated()?;
            }
            Ok(Flow::Next)
        })
    }

    /// `expr` as a statement: what it does, not what it gives.
    fn effect(&self, expr: &Expr) -> Code<Flow> {
        match expr {
            Expr::Assign(place, value) => self.assign(place, value),
            Expr::Update(place, op, arith, operand, _, span) => self
                .update_in_register(place, *op, *arith, operand, *span, |_, _| Flow::Next)
                .unwrap_or_else(|| effect(self.value(expr))),
            _ => effect(self.value(expr)),
        }
    }

    /// `slot = value`, converted as `conv` says.
    fn set(&self, slot: Slot, conv: Conv, value: &Expr) -> Code<Flow> {
        if self.numeric(value) {
            match conv {
                Conv::Int | Conv::UInt => {
                    let value = self.int_operand(value);
                    return code(move |m| {
                        let value = value.get(m)?;
                        match conv {
                            Conv::UInt => m.frame[slot].set_uint(value as u32),
                            _ => m.frame[slot].set_int(value),
                        }
                        Ok(Flow::Next)
                    });
                }
                Conv::Float => {
                    let value = self.float(value);
                    return code(move |m| {
                        let value = value(m)?;
                        m.frame[slot].set_float(value);
                        Ok(Flow::Next)
                    });
                }
                Conv::Bool => {
                    let value = self.truth(value);
                    return code(move |m| {
                        let value = value(m)?;
                        m.frame[slot].set_bool(value);
                        Ok(Flow::Next)
                    });
                }
                Conv::Keep | Conv::Pointer(_) => {}
            }
        }
        let value = self.value(value);
        code(move |m| {
            let value = convert(conv, value(m)?).map_err(|message| Box::new(RunError::failed(None, message)))?;
            m.frame[slot] = value;
            Ok(Flow::Next)
        })
    }

    /// `place = value` as a statement.
    fn assign(&self, place: &Place, value: &Expr) -> Code<Flow> {
        match place {
            Place::Var(slot, conv) => self.set(*slot, *conv, value),
            Place::Index(base, at, span) => match self.number(value) {
                // A number is stored without becoming a value.
                Some(number) => {
                    self.element(base, at, *span, number, |p, at, number| p.store(at, number).map(|()| Flow::Next))
                }
                None => self.element(base, at, *span, self.value(value), |p, at, value| {
                    p.write(at, &value).map(|()| Flow::Next)
                }),
            },
        }
    }

    /// `x op= v`, `++x`, `x++` on a variable of the operation's own arithmetic, done on its
    /// number; `finish` makes the result of the old and the new value. `None` for any other.
    fn update_in_register<R: 'static>(
        &self,
        place: &Place,
        op: BinOp,
        arith: Arith,
        operand: &Expr,
        span: Span,
        finish: impl Fn(Value, Value) -> R + 'static,
    ) -> Option<Code<R>> {
        let &Place::Var(slot, conv) = place else { return None };
        let no_result = move || failed(span, undefined(op, arith));
        match (conv, arith) {
            (Conv::Int, Arith::Int) | (Conv::UInt, Arith::UInt) => {
                let operand = self.int_operand(operand);
                let wrap = move |v: i32| if arith == Arith::UInt { Value::UInt(v as u32) } else { Value::Int(v) };
                let unsigned = arith == Arith::UInt;
                Some(code(move |m| {
                    let operand = operand.get(m)?;
                    let old = int(&m.frame[slot]);
                    let new = match arith {
                        Arith::UInt => uint_binary(op, old as u32, operand as u32).map(|v| v as i32),
                        _ => int_binary(op, old, operand),
                    }
                    .ok_or_else(no_result)?;
                    if unsigned {
                        m.frame[slot].set_uint(new as u32);
                    } else {
                        m.frame[slot].set_int(new);
                    }
                    Ok(finish(wrap(old), wrap(new)))
                }))
            }
            (Conv::Float, Arith::Float) => {
                let operand = self.float(operand);
                Some(code(move |m| {
                    let old = float(&m.frame[slot]);
                    let new = float_binary(op, old, operand(m)?).ok_or_else(no_result)?;
                    m.frame[slot].set_float(new);
                    Ok(finish(Value::Float(old), Value::Float(new)))
                }))
            }
            _ => None,
        }
    }

    /// `x op= v`, `++x`, `x++` giving its value (the old one for `x++`): as C does it, the place
    /// evaluated once (`a[i++] += 1` steps `i` once).
    fn update(&self, place: &Place, op: BinOp, arith: Arith, operand: &Expr, postfix: bool, span: Span) -> Code<Value> {
        let pick = move |old, new| if postfix { old } else { new };
        if let Some(update) = self.update_in_register(place, op, arith, operand, span, pick) {
            return update;
        }
        let operand = self.value(operand);
        let combine = move |old: &Value, operand: &Value| binary(op, arith, old, operand).map_err(|m| failed(span, m));
        match place {
            &Place::Var(slot, conv) => code(move |m| {
                let operand = operand(m)?;
                let old = m.frame[slot].clone();
                let new = combine(&old, &operand)?;
                m.frame[slot] = convert(conv, new.clone()).map_err(|message| failed(span, message))?;
                Ok(pick(old, new))
            }),
            Place::Index(base, at, at_span) => {
                self.element(base, at, *at_span, operand, move |pointer, at, operand| {
                    let old = pointer.read(at)?;
                    let new = binary(op, arith, &old, &operand)?;
                    pointer.write(at, &new)?;
                    Ok(pick(old, new))
                })
            }
        }
    }

    /// Does `then` to the element `base[at]` with what `first` gives: `first`, the index and the
    /// pointer are evaluated in that order, as C does for `base[at] = first` (a pointer in a
    /// variable is used where it is, not copied).
    fn element<V: 'static, R: 'static>(
        &self,
        base: &Expr,
        at: &Expr,
        span: Span,
        first: impl Fn(&mut Machine<'_, '_>) -> Outcome<V> + 'static,
        then: impl Fn(&Pointer, i64, V) -> Result<R, String> + 'static,
    ) -> Code<R> {
        let at = self.int_operand(at);
        match base {
            &Expr::Var(slot) => code(move |m| {
                let first = first(m)?;
                let at = at.get(m)? as i64;
                pointer(&m.frame[slot]).and_then(|p| then(p, at, first)).map_err(|message| failed(span, message))
            }),
            base => {
                let base = self.value(base);
                code(move |m| {
                    let first = first(m)?;
                    let at = at.get(m)? as i64;
                    let base = base(m)?;
                    pointer(&base).and_then(|p| then(p, at, first)).map_err(|message| failed(span, message))
                })
            }
        }
    }
}
