//! Loops of numbers compiled to machine code with Cranelift: a host loop whose statements only
//! compute with `int`, `unsigned int`, floating-point and boolean variables, read and write
//! elements through pointers it does not reassign, and call `rand()` runs as native code, the
//! same C arithmetic the closures do (`compile/`), errors included (division by zero, an index
//! outside its memory — each at its expression; `rand()` steps the framework's state inline). Everything else — and every run where a
//! variable the loop reads holds no number yet, or a pointer is null — runs as closures. The
//! native code reads and writes the loop's variables in a block of machine numbers, copied from
//! and back to the frame around the loop; the pointers' memory is addressed directly.

mod emit;

use std::{collections::BTreeMap, ffi::c_void, rc::Rc};

use cranelift_jit::JITModule;

use super::{
    framework::Method,
    ir::{Conv, Expr, Place, Slot, Span, Stmt},
    machine::{failed, Flow, Machine, Outcome},
    value::{Constant, Scalar, Value},
};

/// What a number is in native code: `int`, `unsigned int` (both 32 bits), `double`, `bool`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Int,
    UInt,
    Float,
    Bool,
}

impl Kind {
    fn of_conv(conv: Conv) -> Option<Kind> {
        match conv {
            Conv::Int => Some(Kind::Int),
            Conv::UInt => Some(Kind::UInt),
            Conv::Float => Some(Kind::Float),
            Conv::Bool => Some(Kind::Bool),
            Conv::Keep | Conv::Pointer(_) => None,
        }
    }

    /// What reading an element gives (`Scalar::value`).
    fn of_element(element: Scalar) -> Kind {
        match element {
            Scalar::U8 | Scalar::U16 | Scalar::U32 => Kind::UInt,
            Scalar::I8 | Scalar::I16 | Scalar::I32 => Kind::Int,
            Scalar::F32 | Scalar::F64 => Kind::Float,
        }
    }
}

/// Why native code stopped early; the codes after [`CODE_ERRORS`] index [`Native::errors`].
const CODE_NEXT: u32 = 0;
const CODE_RETURN: u32 = 1;
const CODE_CANCELLED: u32 = 2;
const CODE_ERRORS: u32 = 3;

/// An error the native code found, with what the message needs.
enum NativeError {
    /// An operation without a result (division by zero).
    Undefined { span: Span, message: String },
    /// An element outside its memory: through pointer number `pointer`, at the index the
    /// native code left in [`Context::error_index`].
    Outside { span: Span, pointer: usize },
}

/// What native code is called with.
#[repr(C)]
struct Context {
    /// The loop's variables as machine numbers (the bits of an `i32`, of an `f64`, 0 or 1).
    numbers: *mut u64,
    /// Per pointer: the first byte of its memory, its byte offset and the memory's length.
    pointers: *const PointerArg,
    machine: *mut c_void,
    error_index: i64,
    /// `rand()`'s state, stepped in place.
    rand_state: *mut u32,
}

#[repr(C)]
struct PointerArg {
    base: *mut u8,
    offset: i64,
    len: i64,
}

/// A loop compiled to machine code.
pub(super) struct Native {
    /// The module that owns the code (freed when the last closure holding it goes).
    _code: Rc<Code>,
    function: unsafe extern "C" fn(*mut Context) -> u32,
    /// The variables the loop uses, in the order of [`Context::numbers`].
    numbers: Vec<Local>,
    /// The pointers the loop indexes, in the order of [`Context::pointers`], with the element
    /// the code was compiled for.
    pointers: Vec<(Slot, Scalar)>,
    errors: Vec<NativeError>,
}

/// A variable a native loop uses.
struct Local {
    slot: Slot,
    kind: Kind,
    /// Whether the loop assigns it (it is copied back to the frame).
    written: bool,
    /// Whether the loop declares it (it need not hold a number before the loop).
    declared: bool,
}

/// The JIT module of one loop; its memory is freed with it.
struct Code(Option<JITModule>);

impl Drop for Code {
    fn drop(&mut self) {
        if let Some(module) = self.0.take() {
            // SAFETY: the only pointer into the code is `Native::function`, whose `Native`
            // holds this `Code` and is gone when it is dropped.
            unsafe { module.free_memory() };
        }
    }
}

/// The loop `stmt` (a [`Stmt::Loop`]) compiled to machine code, where all of it can be.
pub(super) fn compile(stmt: &Stmt, slots: &[Conv]) -> Option<Native> {
    // The closures keep memory little-endian; native loads and stores use the machine's order.
    if cfg!(target_endian = "big") {
        return None;
    }
    let mut uses = Uses { slots, numbers: BTreeMap::new(), pointers: BTreeMap::new(), declared: Vec::new() };
    if !uses.stmt(stmt) {
        return None;
    }
    if uses.pointers.keys().any(|slot| uses.numbers.contains_key(slot)) {
        return None;
    }
    let numbers: Vec<Local> = (uses.numbers.into_iter())
        .map(|(slot, (kind, written))| Local { slot, kind, written, declared: uses.declared.contains(&slot) })
        .collect();
    let pointers: Vec<(Slot, Scalar)> = uses.pointers.into_iter().collect();
    let (module, function, errors) = emit::function(stmt, &numbers, &pointers)?;
    // SAFETY: the function was compiled with this signature.
    let function = unsafe { std::mem::transmute::<*const u8, unsafe extern "C" fn(*mut Context) -> u32>(function) };
    Some(Native { _code: Rc::new(Code(Some(module))), function, numbers, pointers, errors })
}

impl Native {
    /// Runs the loop natively; `None` where this run cannot (a variable it reads holds no
    /// number, a pointer is null or of another element, its memory is borrowed): the caller
    /// runs the closures instead.
    pub fn run(&self, m: &mut Machine<'_, '_>) -> Outcome<Option<Flow>> {
        let mut numbers = Vec::with_capacity(self.numbers.len());
        for local in &self.numbers {
            let bits = match (&m.frame[local.slot], local.kind) {
                (Value::Int(v), Kind::Int) => *v as u32 as u64,
                (Value::UInt(v), Kind::UInt) => *v as u64,
                (Value::Float(v), Kind::Float) => v.to_bits(),
                (Value::Bool(v), Kind::Bool) => *v as u64,
                _ if local.declared => 0,
                // Not yet assigned (or not a number): the closures do what C would.
                _ => return Ok(None),
            };
            numbers.push(bits);
        }
        let mut pointers = Vec::with_capacity(self.pointers.len());
        for &(slot, element) in &self.pointers {
            let Value::Ptr(pointer) = &m.frame[slot] else { return Ok(None) };
            if pointer.element != element || pointer.memory.try_borrow_mut().is_err() {
                return Ok(None);
            }
            // SAFETY: nothing borrows the memory while the native code runs (it calls only
            // `rand()` and the observer), and its length does not change.
            let bytes = unsafe { &mut *pointer.memory.as_ptr() };
            pointers.push(PointerArg { base: bytes.as_mut_ptr(), offset: pointer.offset, len: bytes.len() as i64 });
        }
        // Both from one raw pointer: `native_cancelled` makes a `&mut Machine` of it while the
        // code holds the state's address.
        let machine: *mut Machine<'_, '_> = m;
        let mut context = Context {
            numbers: numbers.as_mut_ptr(),
            pointers: pointers.as_ptr(),
            machine: machine as *mut c_void,
            error_index: 0,
            // SAFETY: `machine` is `m`, live for this call.
            rand_state: unsafe { std::ptr::addr_of_mut!((*machine).framework.rand_state) },
        };
        // SAFETY: the context points at live arrays of the lengths the code was compiled for.
        let code = unsafe { (self.function)(&mut context) };
        m.native_loops += 1;
        for (local, bits) in self.numbers.iter().zip(&numbers) {
            let slot = &mut m.frame[local.slot];
            match local.kind {
                _ if !local.written => {}
                Kind::Int => slot.set_int(*bits as u32 as i32),
                Kind::UInt => slot.set_uint(*bits as u32),
                Kind::Float => slot.set_float(f64::from_bits(*bits)),
                Kind::Bool => slot.set_bool(*bits & 1 != 0),
            }
        }
        match code {
            CODE_NEXT => Ok(Some(Flow::Next)),
            CODE_RETURN => Ok(Some(Flow::Return)),
            CODE_CANCELLED => Err(m.cancellation()),
            error => Err(match &self.errors[(error - CODE_ERRORS) as usize] {
                NativeError::Undefined { span, message } => failed(*span, message.clone()),
                NativeError::Outside { span, pointer } => {
                    let Value::Ptr(p) = &m.frame[self.pointers[*pointer].0] else { unreachable!("checked above") };
                    failed(*span, p.outside(context.error_index))
                }
            }),
        }
    }
}

/// Native code's question whether to stop (every 65 536 iterations): 1 to stop.
extern "C" fn native_cancelled(machine: *mut c_void) -> u32 {
    // SAFETY: `machine` is the machine running the native code, not otherwise used meanwhile.
    let machine = unsafe { &mut *(machine as *mut Machine<'_, '_>) };
    machine.observer.cancelled() as u32
}

/// C's `fmod`, as the closures compute `%` of floating-point numbers.
extern "C" fn native_fmod(a: f64, b: f64) -> f64 {
    a % b
}

/// The variables and pointers a loop uses, and whether every construct in it compiles.
struct Uses<'s> {
    slots: &'s [Conv],
    /// Numeric variables: their kind, and whether the loop writes them.
    numbers: BTreeMap<Slot, (Kind, bool)>,
    /// Pointers indexed (never assigned in the loop), with their element.
    pointers: BTreeMap<Slot, Scalar>,
    /// Variables declared in the loop (assigned before they are read).
    declared: Vec<Slot>,
}

impl Uses<'_> {
    fn stmt(&mut self, stmt: &Stmt) -> bool {
        match stmt {
            Stmt::Expr(expr) => self.expr(expr),
            Stmt::Declare(slot, value) => {
                self.declared.push(*slot);
                self.variable(*slot, true) && self.expr(value)
            }
            Stmt::If(condition, then, other) => self.expr(condition) && self.block(then) && self.block(other),
            Stmt::Loop { test, body, step, .. } => {
                test.as_ref().is_none_or(|test| self.expr(test)) && self.block(body) && self.block(step)
            }
            Stmt::Block(stmts) => self.block(stmts),
            Stmt::Return | Stmt::Break | Stmt::Continue => true,
            Stmt::Switch(..) | Stmt::Flow(_) => false,
        }
    }

    fn block(&mut self, stmts: &[Stmt]) -> bool {
        stmts.iter().all(|stmt| self.stmt(stmt))
    }

    fn variable(&mut self, slot: Slot, written: bool) -> bool {
        let Some(kind) = Kind::of_conv(self.slots[slot]) else { return false };
        self.numbers.entry(slot).or_insert((kind, false)).1 |= written;
        true
    }

    fn pointer(&mut self, base: &Expr) -> bool {
        let &Expr::Var(slot) = base else { return false };
        let Conv::Pointer(element) = self.slots[slot] else { return false };
        self.pointers.insert(slot, element);
        true
    }

    fn place(&mut self, place: &Place) -> bool {
        match place {
            Place::Var(slot, conv) => Kind::of_conv(*conv).is_some() && self.variable(*slot, true),
            Place::Index(base, at, _) => self.pointer(base) && self.expr(at),
        }
    }

    fn expr(&mut self, expr: &Expr) -> bool {
        match expr {
            Expr::Const(value) => {
                matches!(value, Constant::Int(_) | Constant::UInt(_) | Constant::Float(_) | Constant::Bool(_))
            }
            Expr::Var(slot) => self.variable(*slot, false),
            Expr::Binary(_, _, l, r, _) | Expr::Compare(_, _, l, r) | Expr::And(l, r) | Expr::Or(l, r) => {
                self.expr(l) && self.expr(r)
            }
            Expr::Not(inner) | Expr::Negate(_, inner) | Expr::BitNot(_, inner) => self.expr(inner),
            Expr::Convert(conv, inner) => Kind::of_conv(*conv).is_some() && self.expr(inner),
            Expr::Index(base, at, _) => self.pointer(base) && self.expr(at),
            Expr::Assign(place, value) => self.place(place) && self.expr(value),
            Expr::Update(place, _, _, operand, _, _) => self.place(place) && self.expr(operand),
            Expr::Ternary(c, a, b) => self.expr(c) && self.expr(a) && self.expr(b),
            Expr::Call(Method::Rand, args, _) => args.is_empty(),
            Expr::Same(..)
            | Expr::Offset(..)
            | Expr::Call(..)
            | Expr::NewArray(..)
            | Expr::Launch(..)
            | Expr::CallDiagram { .. } => false,
        }
    }
}
