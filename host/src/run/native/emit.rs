//! Cranelift IR of a native loop (see the parent module): each expression computed in the kind
//! it has (`int`, `unsigned int`, `double`, `bool`) and converted as the closures convert it,
//! C's arithmetic on 32-bit integers (wrapping; shifts modulo 32; division by zero an error,
//! `INT_MIN / -1` wrapping), `%` of doubles by `fmod`, elements read and written through
//! bounds-checked addresses, `&&`, `||` and `?:` evaluated lazily, and every exit — the loop's
//! end, `return`, an error, a cancellation — through one block that stores the variables the
//! loop wrote back into the context.

use std::collections::HashMap;

use cranelift_codegen::{
    ir::{condcodes::IntCC, types, AbiParam, Block, FuncRef, InstBuilder, MemFlagsData, Type, Value as Ir},
    settings::{self, Configurable},
};
use cranelift_frontend::{FunctionBuilder, FunctionBuilderContext, Variable};
use cranelift_jit::{JITBuilder, JITModule};
use cranelift_module::{Linkage, Module};

mod assign;
mod branches;
mod ops;

use super::{
    native_cancelled, native_fmod, Kind, Local, NativeError, CODE_CANCELLED, CODE_ERRORS, CODE_NEXT, CODE_RETURN,
};
use crate::run::{
    framework::Method,
    ir::{Arith, Expr, Place, Slot, Stmt},
    value::{Constant, Scalar},
};

/// The kind of an operation's arithmetic.
pub(super) fn arith_kind(arith: Arith) -> Kind {
    match arith {
        Arith::Int => Kind::Int,
        Arith::UInt => Kind::UInt,
        Arith::Float => Kind::Float,
    }
}

fn ir_type(kind: Kind) -> Type {
    match kind {
        Kind::Int | Kind::UInt => types::I32,
        Kind::Float => types::F64,
        Kind::Bool => types::I8,
    }
}

/// Byte offsets of [`super::Context`]'s fields (64-bit pointers).
const NUMBERS_AT: i32 = 0;
const POINTERS_AT: i32 = 8;
const MACHINE_AT: i32 = 16;
const ERROR_INDEX_AT: i32 = 24;
const RAND_STATE_AT: i32 = 32;
/// Bytes of one [`super::PointerArg`].
const POINTER_ARG_SIZE: i32 = 24;

/// Loop iterations between two questions whether to stop (as the closures ask).
const CANCEL_MASK: i64 = (1 << 16) - 1;

/// Compiles the loop `stmt` to a function of a fresh JIT module: the module, the function's
/// address and the errors its codes stand for. `None` where Cranelift has no backend for this
/// machine or the function does not compile.
pub(super) fn function(
    stmt: &Stmt,
    numbers: &[Local],
    pointers: &[(Slot, Scalar)],
) -> Option<(JITModule, *const u8, Vec<NativeError>)> {
    let mut flags = settings::builder();
    flags.set("opt_level", "speed").ok()?;
    let isa = cranelift_native::builder().ok()?.finish(settings::Flags::new(flags)).ok()?;
    if isa.pointer_type() != types::I64 {
        return None;
    }
    let mut jit = JITBuilder::with_isa(isa, cranelift_module::default_libcall_names());
    jit.symbol("native_cancelled", native_cancelled as *const u8);
    jit.symbol("native_fmod", native_fmod as *const u8);
    let mut module = JITModule::new(jit);
    let mut declare = |name: &str, params: &[Type], returns: Type| {
        let mut signature = module.make_signature();
        signature.params.extend(params.iter().map(|&t| AbiParam::new(t)));
        signature.returns.push(AbiParam::new(returns));
        module.declare_function(name, Linkage::Import, &signature).ok()
    };
    let cancelled = declare("native_cancelled", &[types::I64], types::I32)?;
    let fmod = declare("native_fmod", &[types::F64, types::F64], types::F64)?;

    let mut context = module.make_context();
    context.func.signature.params.push(AbiParam::new(types::I64));
    context.func.signature.returns.push(AbiParam::new(types::I32));
    let mut builder_context = FunctionBuilderContext::new();
    let mut b = FunctionBuilder::new(&mut context.func, &mut builder_context);
    let helpers = [cancelled, fmod].map(|id| module.declare_func_in_func(id, b.func));
    let entry = b.create_block();
    b.append_block_params_for_function_params(entry);
    b.switch_to_block(entry);
    let ctx = b.block_params(entry)[0];
    let flags = MemFlagsData::new().with_notrap();
    let numbers_at = b.ins().load(types::I64, flags, ctx, NUMBERS_AT);
    let pointers_at = b.ins().load(types::I64, flags, ctx, POINTERS_AT);
    let machine = b.ins().load(types::I64, flags, ctx, MACHINE_AT);
    let rand_state_at = b.ins().load(types::I64, flags, ctx, RAND_STATE_AT);
    let rand_state = b.declare_var(types::I32);
    let state = b.ins().load(types::I32, flags, rand_state_at, 0);
    b.def_var(rand_state, state);
    let mut vars = HashMap::new();
    for (i, &Local { slot, kind, .. }) in numbers.iter().enumerate() {
        let bits = b.ins().load(types::I64, flags, numbers_at, 8 * i as i32);
        let value = match kind {
            Kind::Int | Kind::UInt => b.ins().ireduce(types::I32, bits),
            Kind::Float => b.ins().bitcast(types::F64, MemFlagsData::new(), bits),
            Kind::Bool => b.ins().ireduce(types::I8, bits),
        };
        let var = b.declare_var(ir_type(kind));
        b.def_var(var, value);
        vars.insert(slot, (var, kind));
    }
    let mut bases = HashMap::new();
    for (j, &(slot, element)) in pointers.iter().enumerate() {
        let at = POINTER_ARG_SIZE * j as i32;
        let base = b.ins().load(types::I64, flags, pointers_at, at);
        let offset = b.ins().load(types::I64, flags, pointers_at, at + 8);
        let len = b.ins().load(types::I64, flags, pointers_at, at + 16);
        // An element starting at byte s lies inside when 0 <= s < len - size + 1: one unsigned
        // comparison with that count, clamped at 0.
        let starts = b.ins().iadd_imm_s(len, 1 - element.size() as i64);
        let none = b.ins().iconst(types::I64, 0);
        let starts = b.ins().smax(starts, none);
        bases.insert(slot, Base { number: j, element, base, offset, starts });
    }
    let iterations = b.declare_var(types::I32);
    let zero = b.ins().iconst(types::I32, 0);
    b.def_var(iterations, zero);
    let exit = b.create_block();
    b.append_block_param(exit, types::I32);

    let mut emitter = Emitter {
        b,
        vars,
        bases,
        ctx,
        machine,
        exit,
        loops: Vec::new(),
        iterations,
        rand_state,
        errors: Vec::new(),
        helpers,
        supported: true,
    };
    emitter.stmt(stmt);
    emitter.leave(CODE_NEXT);

    // The exit: the written variables back into the context, then the code.
    let Emitter { mut b, vars, errors, supported, .. } = emitter;
    b.switch_to_block(exit);
    let state = b.use_var(rand_state);
    b.ins().store(flags, state, rand_state_at, 0);
    for (i, &Local { slot, kind, written, .. }) in numbers.iter().enumerate() {
        if !written {
            continue;
        }
        let value = b.use_var(vars[&slot].0);
        let bits = match kind {
            Kind::Int | Kind::UInt | Kind::Bool => b.ins().uextend(types::I64, value),
            Kind::Float => b.ins().bitcast(types::I64, MemFlagsData::new(), value),
        };
        b.ins().store(flags, bits, numbers_at, 8 * i as i32);
    }
    let code = b.block_params(exit)[0];
    b.ins().return_(&[code]);
    b.seal_all_blocks();
    b.finalize(module.target_config());
    if !supported {
        return None;
    }
    let id = module.declare_function("native_loop", Linkage::Local, &context.func.signature).ok()?;
    module.define_function(id, &mut context).ok()?;
    module.clear_context(&mut context);
    module.finalize_definitions().ok()?;
    let address = module.get_finalized_function(id);
    Some((module, address, errors))
}

/// A pointer the loop indexes: its number in the context, element and memory.
struct Base {
    number: usize,
    element: Scalar,
    base: Ir,
    /// The pointer's byte offset into its memory.
    offset: Ir,
    /// How many byte offsets an element can start at inside the memory.
    starts: Ir,
}

struct Emitter<'f> {
    b: FunctionBuilder<'f>,
    vars: HashMap<Slot, (Variable, Kind)>,
    bases: HashMap<Slot, Base>,
    ctx: Ir,
    machine: Ir,
    exit: Block,
    /// Innermost last: where `continue` and `break` go.
    loops: Vec<(Block, Block)>,
    iterations: Variable,
    /// `rand()`'s state while the loop runs.
    rand_state: Variable,
    errors: Vec<NativeError>,
    /// `cancelled`, `fmod`.
    helpers: [FuncRef; 2],
    /// False when something turned out not to compile (the loop then runs as closures).
    supported: bool,
}

impl Emitter<'_> {
    /// Jumps to the exit with `code`; what follows is unreachable.
    fn leave(&mut self, code: u32) {
        let code = self.b.ins().iconst(types::I32, code as i64);
        self.b.ins().jump(self.exit, &[code.into()]);
        self.unreachable();
    }

    /// Goes on in a block nothing jumps to (after a jump).
    fn unreachable(&mut self) {
        let dead = self.b.create_block();
        self.b.switch_to_block(dead);
    }

    /// Leaves with `error`; `index` is the element index an [`NativeError::Outside`] reports.
    fn fail(&mut self, error: NativeError, index: Option<Ir>) {
        if let Some(index) = index {
            self.b.ins().store(MemFlagsData::new().with_notrap(), index, self.ctx, ERROR_INDEX_AT);
        }
        self.errors.push(error);
        self.leave(CODE_ERRORS + self.errors.len() as u32 - 1);
    }

    /// Leaves with `error` where `failed` holds, goes on where it does not.
    fn fail_if(&mut self, failed: Ir, error: NativeError, index: Option<Ir>) {
        let (bad, good) = (self.b.create_block(), self.b.create_block());
        self.b.ins().brif(failed, bad, &[], good, &[]);
        self.b.switch_to_block(bad);
        self.fail(error, index);
        self.b.switch_to_block(good);
    }

    fn stmt(&mut self, stmt: &Stmt) {
        match stmt {
            Stmt::Expr(expr) => self.effect(expr),
            Stmt::Declare(slot, value) => self.set(*slot, value),
            Stmt::If(condition, then, other) => {
                let condition = self.truth(condition);
                let (then_block, else_block, merge) =
                    (self.b.create_block(), self.b.create_block(), self.b.create_block());
                self.b.ins().brif(condition, then_block, &[], else_block, &[]);
                for (block, stmts) in [(then_block, then), (else_block, other)] {
                    self.b.switch_to_block(block);
                    stmts.iter().for_each(|stmt| self.stmt(stmt));
                    self.b.ins().jump(merge, &[]);
                }
                self.b.switch_to_block(merge);
            }
            Stmt::Loop { test, body, step, test_after } => {
                let [header, body_block, step_block, latch, poll, after] = [(); 6].map(|()| self.b.create_block());
                self.b.ins().jump(header, &[]);
                self.b.switch_to_block(header);
                match test {
                    Some(test) if !test_after => {
                        let holds = self.truth(test);
                        self.b.ins().brif(holds, body_block, &[], after, &[]);
                    }
                    _ => {
                        self.b.ins().jump(body_block, &[]);
                    }
                }
                self.b.switch_to_block(body_block);
                self.loops.push((step_block, after));
                body.iter().for_each(|stmt| self.stmt(stmt));
                self.b.ins().jump(step_block, &[]);
                self.b.switch_to_block(step_block);
                step.iter().for_each(|stmt| self.stmt(stmt));
                self.loops.pop();
                match test {
                    Some(test) if *test_after => {
                        let holds = self.truth(test);
                        self.b.ins().brif(holds, latch, &[], after, &[]);
                    }
                    _ => {
                        self.b.ins().jump(latch, &[]);
                    }
                }
                // Every 65 536 iterations: whether to stop.
                self.b.switch_to_block(latch);
                let count = self.b.use_var(self.iterations);
                let count = self.b.ins().iadd_imm_s(count, 1);
                self.b.def_var(self.iterations, count);
                let due = self.b.ins().band_imm_s(count, CANCEL_MASK);
                self.b.ins().brif(due, header, &[], poll, &[]);
                self.b.switch_to_block(poll);
                let call = self.b.ins().call(self.helpers[0], &[self.machine]);
                let stop = self.b.inst_results(call)[0];
                let (stopped, go_on) = (self.b.create_block(), header);
                self.b.ins().brif(stop, stopped, &[], go_on, &[]);
                self.b.switch_to_block(stopped);
                self.leave(CODE_CANCELLED);
                self.b.switch_to_block(after);
            }
            Stmt::Block(stmts) => stmts.iter().for_each(|stmt| self.stmt(stmt)),
            Stmt::Return => self.leave(CODE_RETURN),
            Stmt::Break | Stmt::Continue => match self.loops.last() {
                Some(&(next, after)) => {
                    self.b.ins().jump(if matches!(stmt, Stmt::Break) { after } else { next }, &[]);
                    self.unreachable();
                }
                None => self.supported = false,
            },
            Stmt::Switch(..) | Stmt::Flow(_) => self.supported = false,
        }
    }

    /// `slot = value` (a declaration or an assignment), converted to the variable's kind.
    fn set(&mut self, slot: Slot, value: &Expr) {
        let (var, kind) = self.vars[&slot];
        let value = self.expr(value, kind);
        self.b.def_var(var, value);
    }

    /// An expression whose value is not used.
    fn effect(&mut self, expr: &Expr) {
        match expr {
            Expr::Assign(place, value) => match place.as_ref() {
                Place::Var(slot, _) => self.set(*slot, value),
                Place::Index(base, at, span) => {
                    let (value, kind) = self.natural(value);
                    let at = self.expr(at, Kind::Int);
                    let address = self.element(base, at, *span);
                    self.store(base, address, value, kind);
                }
            },
            _ => {
                self.natural(expr);
            }
        }
    }

    /// `expr` converted to `kind`.
    fn expr(&mut self, expr: &Expr, kind: Kind) -> Ir {
        let (value, from) = self.natural(expr);
        self.convert(value, from, kind)
    }

    fn truth(&mut self, expr: &Expr) -> Ir {
        self.expr(expr, Kind::Bool)
    }

    /// The kind `expr` computes in, without emitting it.
    fn kind(&self, expr: &Expr) -> Kind {
        match expr {
            Expr::Const(Constant::UInt(_)) => Kind::UInt,
            Expr::Const(Constant::Float(_)) => Kind::Float,
            Expr::Const(Constant::Bool(_)) => Kind::Bool,
            Expr::Const(_) | Expr::Call(..) => Kind::Int,
            Expr::Var(slot) => self.vars.get(slot).map_or(Kind::Int, |(_, kind)| *kind),
            Expr::Binary(_, arith, ..) | Expr::Negate(arith, _) => arith_kind(*arith),
            Expr::BitNot(arith, _) => {
                if *arith == Arith::UInt {
                    Kind::UInt
                } else {
                    Kind::Int
                }
            }
            Expr::Compare(..) | Expr::And(..) | Expr::Or(..) | Expr::Not(_) | Expr::Same(..) => Kind::Bool,
            Expr::Convert(conv, _) => Kind::of_conv(*conv).unwrap_or(Kind::Int),
            Expr::Index(base, ..) => self.element_kind(base),
            Expr::Assign(_, value) => self.kind(value),
            // Postfix gives the old value (of the place's kind), prefix the new one.
            Expr::Update(place, _, arith, _, postfix, _) => match place.as_ref() {
                Place::Index(base, ..) if *postfix => self.element_kind(base),
                Place::Var(slot, _) if *postfix => self.vars.get(slot).map_or(Kind::Int, |(_, kind)| *kind),
                _ => arith_kind(*arith),
            },
            Expr::Ternary(_, a, _) => self.kind(a),
            _ => Kind::Int,
        }
    }

    fn element_kind(&self, base: &Expr) -> Kind {
        Kind::of_element(self.pointer_element(base))
    }

    /// `expr` in the kind it computes in.
    fn natural(&mut self, expr: &Expr) -> (Ir, Kind) {
        let kind = self.kind(expr);
        let value = match expr {
            Expr::Const(constant) => match *constant {
                Constant::Int(v) => self.b.ins().iconst(types::I32, v as i64),
                Constant::UInt(v) => self.b.ins().iconst(types::I32, v as i32 as i64),
                Constant::Float(v) => self.b.ins().f64const(v),
                Constant::Bool(v) => self.b.ins().iconst(types::I8, v as i64),
                _ => return self.unsupported(kind),
            },
            Expr::Var(slot) => match self.vars.get(slot) {
                Some(&(var, _)) => self.b.use_var(var),
                None => return self.unsupported(kind),
            },
            &Expr::Binary(op, arith, ref l, ref r, span) => {
                let (l, r) = (self.expr(l, kind), self.expr(r, kind));
                self.binary(op, arith, l, r, span)
            }
            &Expr::Compare(op, arith, ref l, ref r) => {
                let operands = arith_kind(arith);
                let (l, r) = (self.expr(l, operands), self.expr(r, operands));
                self.compare(op, arith, l, r)
            }
            Expr::And(l, r) => self.short_circuit(true, l, r),
            Expr::Or(l, r) => self.short_circuit(false, l, r),
            Expr::Not(inner) => {
                let inner = self.truth(inner);
                self.b.ins().icmp_imm_s(IntCC::Equal, inner, 0)
            }
            Expr::Negate(_, inner) => {
                let inner = self.expr(inner, kind);
                match kind {
                    Kind::Float => self.b.ins().fneg(inner),
                    _ => self.b.ins().ineg(inner),
                }
            }
            Expr::BitNot(_, inner) => {
                let inner = self.expr(inner, Kind::Int);
                self.b.ins().bnot(inner)
            }
            Expr::Convert(_, inner) => self.expr(inner, kind),
            &Expr::Index(ref base, ref at, span) => {
                let at = self.expr(at, Kind::Int);
                let address = self.element(base, at, span);
                self.load(base, address)
            }
            Expr::Assign(place, value) => self.assigned(place, value),
            &Expr::Update(ref place, op, arith, ref operand, postfix, span) => {
                self.updated(place, (op, arith), operand, postfix, span)
            }
            // The closures give the branch taken in its own kind: both must have one kind.
            Expr::Ternary(_, a, b) if self.kind(a) != self.kind(b) => return self.unsupported(kind),
            Expr::Ternary(condition, a, b) => self.ternary(condition, a, b, kind),
            // The framework's xorshift32 (`Framework::rand`), stepped inline.
            Expr::Call(Method::Rand, ..) => {
                let mut x = self.b.use_var(self.rand_state);
                for (left, amount) in [(true, 13), (false, 17), (true, 5)] {
                    let shifted =
                        if left { self.b.ins().ishl_imm_s(x, amount) } else { self.b.ins().ushr_imm_s(x, amount) };
                    x = self.b.ins().bxor(x, shifted);
                }
                self.b.def_var(self.rand_state, x);
                self.b.ins().ushr_imm_s(x, 1)
            }
            _ => return self.unsupported(kind),
        };
        (value, kind)
    }

    /// A stand-in for what does not compile; the loop is then not compiled at all.
    fn unsupported(&mut self, kind: Kind) -> (Ir, Kind) {
        self.supported = false;
        let value = match kind {
            Kind::Float => self.b.ins().f64const(0.0),
            other => self.b.ins().iconst(ir_type(other), 0),
        };
        (value, kind)
    }
}
