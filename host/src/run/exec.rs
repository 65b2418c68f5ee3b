//! Running a lowered diagram: from the start node, each node's statements, then the first
//! transition whose guard holds (the unguarded one otherwise) with its arguments handed to the
//! target's parameters, until a final node — or a node with no transition to take. Statements
//! and expressions are evaluated over one frame of slots; the observer is told of every node
//! and asked between nodes (and every 65 536 loop iterations) whether to stop.

use std::time::{Duration, Instant};

use crate::launch::Launcher;

use super::{
    framework::{Framework, Method},
    ir::{Arith, BinOp, CmpOp, Conv, Expr, NodeKind, Place, Program, Span, Stmt},
    value::{memory, Pointer, Value},
    CalcReport, Ending, Observer, RunError,
};

/// How a statement ends.
enum Flow {
    Next,
    Break,
    Continue,
    Return,
}

type Outcome<T> = Result<T, Box<RunError>>;

/// Loop iterations between two questions to the observer whether to stop.
const CANCEL_CHECK_INTERVAL: u32 = 1 << 16;

pub(super) struct Machine<'r, 'g> {
    pub program: &'r Program,
    pub frame: Vec<Value>,
    pub framework: Framework<'g>,
    pub launchers: &'r [Launcher],
    pub observer: &'r mut dyn Observer,
    /// The work sizes (calc) or ranges (calcRange) the current node was entered with.
    pub work: Vec<i64>,
    pub node: usize,
    pub nodes_run: u64,
    pub calcs: Vec<CalcReport>,
    /// Per node: how often it ran, for how long in all, and the order it first ran in.
    pub times: Vec<(u32, Duration, usize)>,
    iterations: u32,
}

impl<'r, 'g> Machine<'r, 'g> {
    pub fn new(
        program: &'r Program,
        framework: Framework<'g>,
        launchers: &'r [Launcher],
        observer: &'r mut dyn Observer,
    ) -> Machine<'r, 'g> {
        Machine {
            program,
            frame: vec![Value::Void; program.slots],
            framework,
            launchers,
            observer,
            work: Vec::new(),
            node: program.start,
            nodes_run: 0,
            calcs: Vec::new(),
            times: vec![(0, Duration::ZERO, usize::MAX); program.nodes.len()],
            iterations: 0,
        }
    }

    /// Runs the diagram to its end.
    pub fn run(&mut self) -> Outcome<Ending> {
        let program = self.program;
        self.exec(&program.init)?;
        let mut current = program.start;
        // The node and transition the current node was entered by.
        let mut entered: Option<(usize, usize)> = None;
        loop {
            if self.observer.cancelled() {
                return Err(Box::new(RunError::cancelled(&program.nodes[current].name)));
            }
            let node = &program.nodes[current];
            self.node = current;
            self.nodes_run += 1;
            self.observer.node(&node.name);
            let started = Instant::now();
            let ran = self.exec(&node.body);
            let time = &mut self.times[current];
            if time.0 == 0 {
                time.2 = self.nodes_run as usize;
            }
            time.0 += 1;
            time.1 += started.elapsed();
            ran?;
            if let Some((from, edge)) = entered {
                let edge = &program.nodes[from].edges[edge];
                for (slot, place) in node.outs.iter().zip(&edge.outs) {
                    let value = self.frame[*slot].clone();
                    self.store(place, value)?;
                }
            }
            if node.kind == NodeKind::Final {
                return Ok(Ending::Final(node.name.clone()));
            }
            let mut taken = None;
            for (i, edge) in node.edges.iter().enumerate() {
                let holds = match &edge.guard {
                    Some(guard) => self.truth(guard)?,
                    None => true,
                };
                if holds {
                    taken = Some(i);
                    break;
                }
            }
            let Some(taken) = taken else { return Ok(Ending::NoTransition(node.name.clone())) };
            let edge = &node.edges[taken];
            // Every argument is computed before any parameter changes.
            let values = edge.args.iter().map(|(_, value)| self.eval(value)).collect::<Outcome<Vec<_>>>()?;
            for ((slot, _), value) in edge.args.iter().zip(values) {
                self.frame[*slot] = value;
            }
            self.work = edge.work.iter().map(|w| self.eval(w).map(|v| int(&v) as i64)).collect::<Outcome<_>>()?;
            entered = Some((current, taken));
            current = edge.target;
        }
    }

    fn exec(&mut self, stmts: &[Stmt]) -> Outcome<Flow> {
        for stmt in stmts {
            match self.stmt(stmt)? {
                Flow::Next => {}
                other => return Ok(other),
            }
        }
        Ok(Flow::Next)
    }

    fn stmt(&mut self, stmt: &Stmt) -> Outcome<Flow> {
        match stmt {
            Stmt::Expr(expr) => {
                self.eval(expr)?;
            }
            Stmt::Declare(slot, value) => {
                let value = self.eval(value)?;
                self.frame[*slot] = value;
            }
            Stmt::If(condition, then, other) => {
                let branch = if self.truth(condition)? { then } else { other };
                return self.exec(branch);
            }
            Stmt::Loop { test, body, step, test_after } => loop {
                if !test_after {
                    if let Some(test) = test {
                        if !self.truth(test)? {
                            break;
                        }
                    }
                }
                match self.exec(body)? {
                    Flow::Break => break,
                    Flow::Return => return Ok(Flow::Return),
                    Flow::Next | Flow::Continue => {}
                }
                self.exec(step)?;
                if *test_after {
                    if let Some(test) = test {
                        if !self.truth(test)? {
                            break;
                        }
                    }
                }
                self.iterations = self.iterations.wrapping_add(1);
                if self.iterations.is_multiple_of(CANCEL_CHECK_INTERVAL) && self.observer.cancelled() {
                    return Err(Box::new(RunError::cancelled(&self.program.nodes[self.node].name)));
                }
            },
            Stmt::Switch(value, cases, default) => {
                let value = int(&self.eval(value)?);
                let body = cases.iter().find(|(label, _)| *label == value).map_or(default, |(_, body)| body);
                return match self.exec(body)? {
                    Flow::Break => Ok(Flow::Next),
                    other => Ok(other),
                };
            }
            Stmt::Return => return Ok(Flow::Return),
            Stmt::Break => return Ok(Flow::Break),
            Stmt::Continue => return Ok(Flow::Continue),
            Stmt::Block(stmts) => return self.exec(stmts),
        }
        Ok(Flow::Next)
    }

    fn eval(&mut self, expr: &Expr) -> Outcome<Value> {
        Ok(match expr {
            Expr::Const(value) => value.value(),
            Expr::Var(slot) => self.frame[*slot].clone(),
            Expr::Binary(_, Arith::Int, ..) => Value::Int(self.int(expr)?),
            Expr::Binary(_, Arith::UInt, ..) => Value::UInt(self.int(expr)? as u32),
            Expr::Binary(op, Arith::Float, l, r, span) => {
                let (l, r) = (self.float(l)?, self.float(r)?);
                Value::Float(float_binary(*op, l, r).map_err(|m| failed(*span, m))?)
            }
            Expr::Compare(..) => Value::Bool(self.truth(expr)?),
            Expr::Same(equal, l, r) => {
                let (l, r) = (self.eval(l)?, self.eval(r)?);
                Value::Bool(same(&l, &r) == *equal)
            }
            Expr::And(..) | Expr::Or(..) | Expr::Not(_) => Value::Bool(self.truth(expr)?),
            Expr::Negate(arith, v) => {
                let v = self.eval(v)?;
                match arith {
                    Arith::Int => Value::Int(int(&v).wrapping_neg()),
                    Arith::UInt => Value::UInt((int(&v) as u32).wrapping_neg()),
                    Arith::Float => Value::Float(-float(&v)),
                }
            }
            Expr::BitNot(arith, v) => {
                let v = self.eval(v)?;
                match arith {
                    Arith::UInt => Value::UInt(!(int(&v) as u32)),
                    _ => Value::Int(!int(&v)),
                }
            }
            Expr::Convert(conv, v) => {
                let v = self.eval(v)?;
                convert(*conv, v).map_err(|m| Box::new(RunError::failed(None, m)))?
            }
            Expr::Offset(pointer, n, minus) => {
                let (pointer, n) = (self.eval(pointer)?, int(&self.eval(n)?) as i64);
                match pointer {
                    Value::Ptr(p) => Value::Ptr(p.add(if *minus { -n } else { n })),
                    other => {
                        return Err(Box::new(RunError::failed(
                            None,
                            format!("pointer arithmetic on a {}", other.kind()),
                        )))
                    }
                }
            }
            Expr::Index(base, at, span) => self.element(base, at, *span)?,
            Expr::Assign(place, value) => {
                let value = self.eval(value)?;
                self.store(place, value.clone())?;
                value
            }
            Expr::Update(place, op, Arith::Int, operand, postfix, span)
                if matches!(place.as_ref(), Place::Var(_, Conv::Int)) =>
            {
                let Place::Var(slot, _) = place.as_ref() else { unreachable!("matched above") };
                let operand = self.int(operand)?;
                let old = int(&self.frame[*slot]);
                let new = int_binary(*op, old, operand).map_err(|m| failed(*span, m))?;
                self.frame[*slot] = Value::Int(new);
                Value::Int(if *postfix { old } else { new })
            }
            Expr::Update(place, op, arith, operand, postfix, span) => {
                let operand = self.eval(operand)?;
                let combine = |old: &Value| binary(*op, *arith, old, &operand).map_err(|m| failed(*span, m));
                // The place is evaluated once: `a[i++] += 1` steps `i` once, as in C.
                let (old, new) = match place.as_ref() {
                    Place::Var(slot, conv) => {
                        let old = self.frame[*slot].clone();
                        let new = combine(&old)?;
                        self.frame[*slot] = convert(*conv, new.clone()).map_err(|m| failed(*span, m))?;
                        (old, new)
                    }
                    Place::Index(base, at, at_span) => {
                        let at = self.int(at)? as i64;
                        let base = self.eval(base)?;
                        let old = read(&base, at).map_err(|m| failed(*at_span, m))?;
                        let new = combine(&old)?;
                        write(&base, at, &new).map_err(|m| failed(*at_span, m))?;
                        (old, new)
                    }
                };
                if *postfix {
                    old
                } else {
                    new
                }
            }
            Expr::Ternary(c, a, b) => {
                if self.truth(c)? {
                    self.eval(a)?
                } else {
                    self.eval(b)?
                }
            }
            Expr::Call(..) | Expr::NewArray(..) | Expr::Launch(..) => self.cold(expr)?,
        })
    }

    /// The expressions that do more than compute (framework calls, allocation, kernel
    /// launches), apart so that `eval` stays small.
    #[inline(never)]
    fn cold(&mut self, expr: &Expr) -> Outcome<Value> {
        Ok(match expr {
            Expr::Call(method, args, span) => {
                let args = args.iter().map(|a| self.eval(a)).collect::<Outcome<Vec<_>>>()?;
                let result = self.framework.call(*method, &args).map_err(|m| failed(*span, m))?;
                if *method == Method::Printf {
                    if let Value::Str(text) = &result {
                        self.observer.printed(text);
                    }
                    return Ok(Value::Int(match &result {
                        Value::Str(text) => text.len() as i32,
                        _ => 0,
                    }));
                }
                result
            }
            Expr::NewArray(element, count, span) => {
                let count = int(&self.eval(count)?) as i64;
                let bytes = count.checked_mul(element.size() as i64).filter(|b| (0..=1 << 34).contains(b));
                let Some(bytes) = bytes else {
                    return Err(failed(*span, format!("an array of {count} elements")));
                };
                Value::Ptr(Pointer::to(memory(bytes as usize), *element))
            }
            Expr::Launch(kernel, args, span) => {
                let args = args.iter().map(|a| self.eval(a)).collect::<Outcome<Vec<_>>>()?;
                let started = Instant::now();
                let took = self.launch(*kernel, &args).map_err(|m| failed(*span, m))?;
                self.record(*kernel, took, started.elapsed());
                Value::Void
            }
            _ => unreachable!("only calls, allocations and launches are cold"),
        })
    }

    /// `expr` as a C `int` (the bits of an `unsigned int`), without making values where the
    /// arithmetic allows: the interpreter's hot path.
    fn int(&mut self, expr: &Expr) -> Outcome<i32> {
        Ok(match expr {
            Expr::Const(value) => int(&value.value()),
            Expr::Var(slot) => int(&self.frame[*slot]),
            Expr::Binary(op, Arith::Int, l, r, span) => {
                let (l, r) = (self.int(l)?, self.int(r)?);
                int_binary(*op, l, r).map_err(|m| failed(*span, m))?
            }
            Expr::Binary(op, Arith::UInt, l, r, span) => {
                let (l, r) = (self.int(l)? as u32, self.int(r)? as u32);
                uint_binary(*op, l, r).map_err(|m| failed(*span, m))? as i32
            }
            Expr::Convert(Conv::Int | Conv::UInt, inner) => self.int(inner)?,
            Expr::Index(base, at, span) => int(&self.element(base, at, *span)?),
            other => int(&self.eval(other)?),
        })
    }

    /// `base[at]` (a pointer in a variable is read where it is, not copied).
    fn element(&mut self, base: &Expr, at: &Expr, span: Span) -> Outcome<Value> {
        let at = self.int(at)? as i64;
        let value = match base {
            Expr::Var(slot) => read(&self.frame[*slot], at),
            base => {
                let base = self.eval(base)?;
                read(&base, at)
            }
        };
        value.map_err(|m| failed(span, m))
    }

    fn float(&mut self, expr: &Expr) -> Outcome<f64> {
        Ok(match expr {
            Expr::Const(value) => float(&value.value()),
            Expr::Var(slot) => float(&self.frame[*slot]),
            Expr::Convert(Conv::Float, inner) => self.float(inner)?,
            other => float(&self.eval(other)?),
        })
    }

    /// `expr` as a condition.
    fn truth(&mut self, expr: &Expr) -> Outcome<bool> {
        Ok(match expr {
            Expr::Compare(op, Arith::Int, l, r) => {
                let (l, r) = (self.int(l)?, self.int(r)?);
                ordered(*op, l.cmp(&r))
            }
            Expr::Compare(op, Arith::UInt, l, r) => {
                let (l, r) = (self.int(l)? as u32, self.int(r)? as u32);
                ordered(*op, l.cmp(&r))
            }
            Expr::Compare(op, Arith::Float, l, r) => {
                let (l, r) = (self.float(l)?, self.float(r)?);
                // NaN: only `!=` holds.
                l.partial_cmp(&r).map_or(*op == CmpOp::Ne, |ordering| ordered(*op, ordering))
            }
            Expr::And(l, r) => self.truth(l)? && self.truth(r)?,
            Expr::Or(l, r) => self.truth(l)? || self.truth(r)?,
            Expr::Not(v) => !self.truth(v)?,
            Expr::Convert(Conv::Bool, inner) => self.truth(inner)?,
            other => truthy(&self.eval(other)?),
        })
    }

    /// Stores `value` where `place` says.
    fn store(&mut self, place: &Place, value: Value) -> Outcome<()> {
        match place {
            Place::Var(slot, conv) => {
                self.frame[*slot] = convert(*conv, value).map_err(|m| Box::new(RunError::failed(None, m)))?;
            }
            Place::Index(base, at, span) => {
                let at = self.int(at)? as i64;
                let written = match base {
                    Expr::Var(slot) => write(&self.frame[*slot], at, &value),
                    base => {
                        let base = self.eval(base)?;
                        write(&base, at, &value)
                    }
                };
                written.map_err(|m| failed(*span, m))?;
            }
        }
        Ok(())
    }
}

pub(super) fn failed(span: Span, message: String) -> Box<RunError> {
    Box::new(RunError::failed(Some(span), message))
}

/// `base[at]`.
fn read(base: &Value, at: i64) -> Result<Value, String> {
    match base {
        Value::Ptr(p) => p.read(at),
        other => Err(format!("indexing a {}", describe(other))),
    }
}

/// `base[at] = value`.
fn write(base: &Value, at: i64, value: &Value) -> Result<(), String> {
    match base {
        Value::Ptr(p) => p.write(at, value),
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
fn truthy(value: &Value) -> bool {
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
fn int(value: &Value) -> i32 {
    match value {
        Value::Int(v) => *v,
        Value::UInt(v) => *v as i32,
        Value::Bool(b) => *b as i32,
        Value::Float(v) => *v as i64 as i32,
        _ => 0,
    }
}

fn float(value: &Value) -> f64 {
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

fn binary(op: BinOp, arith: Arith, l: &Value, r: &Value) -> Result<Value, String> {
    Ok(match arith {
        Arith::Int => Value::Int(int_binary(op, int(l), int(r))?),
        Arith::UInt => Value::UInt(uint_binary(op, int(l) as u32, int(r) as u32)?),
        Arith::Float => Value::Float(float_binary(op, float(l), float(r))?),
    })
}

/// C's floating-point arithmetic (`%` as `fmod`).
fn float_binary(op: BinOp, a: f64, b: f64) -> Result<f64, String> {
    Ok(match op {
        BinOp::Add => a + b,
        BinOp::Sub => a - b,
        BinOp::Mul => a * b,
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
        _ => return Err("a bit operation on floating-point numbers".into()),
    })
}

/// C's `int` arithmetic (wrapping; shifts by the amount modulo 32).
fn int_binary(op: BinOp, a: i32, b: i32) -> Result<i32, String> {
    Ok(match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        BinOp::Div | BinOp::Rem if b == 0 => return Err("division by zero".into()),
        BinOp::Div => a.wrapping_div(b),
        BinOp::Rem => a.wrapping_rem(b),
        BinOp::Shl => a.wrapping_shl(b as u32),
        BinOp::Shr => a.wrapping_shr(b as u32),
        BinOp::BitAnd => a & b,
        BinOp::BitOr => a | b,
        BinOp::BitXor => a ^ b,
    })
}

/// C's `unsigned int` arithmetic.
fn uint_binary(op: BinOp, a: u32, b: u32) -> Result<u32, String> {
    Ok(match op {
        BinOp::Add => a.wrapping_add(b),
        BinOp::Sub => a.wrapping_sub(b),
        BinOp::Mul => a.wrapping_mul(b),
        BinOp::Div | BinOp::Rem if b == 0 => return Err("division by zero".into()),
        BinOp::Div => a / b,
        BinOp::Rem => a % b,
        BinOp::Shl => a.wrapping_shl(b),
        BinOp::Shr => a.wrapping_shr(b),
        BinOp::BitAnd => a & b,
        BinOp::BitOr => a | b,
        BinOp::BitXor => a ^ b,
    })
}

fn ordered(op: CmpOp, ordering: std::cmp::Ordering) -> bool {
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
fn same(l: &Value, r: &Value) -> bool {
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
