//! What a host diagram is lowered to before it runs: nodes, transitions, statements and
//! expressions with every name resolved to a slot, every operator to its C arithmetic and every
//! call to the framework method or kernel it reaches. It holds no syntax tree and no database,
//! so a run needs neither (an editor goes on editing while it runs).

use gudsl_model::{db::SourceFile, syntax::TextRange};

use super::{
    framework::Method,
    value::{Constant, Scalar},
};

/// Where something is written: for errors at run time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Span {
    pub file: SourceFile,
    pub range: TextRange,
}

/// A variable's index in the run's frame (diagram variables, node parameters and every local).
pub type Slot = usize;

/// The C arithmetic an operator is done in (the operands' usual arithmetic conversion).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Arith {
    Int,
    UInt,
    Float,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Shl,
    Shr,
    BitAnd,
    BitOr,
    BitXor,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmpOp {
    Eq,
    Ne,
    Lt,
    Le,
    Gt,
    Ge,
}

/// What a value is converted to when it is stored or passed (C's implicit conversions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Conv {
    /// Kept as it is (strings, objects, unknown types).
    Keep,
    Bool,
    Int,
    UInt,
    Float,
    /// A pointer to elements of this scalar (`ref unsigned byte p = q`).
    Pointer(Scalar),
}

pub enum Expr {
    Const(Constant),
    Var(Slot),
    Binary(BinOp, Arith, Box<Expr>, Box<Expr>, Span),
    Compare(CmpOp, Arith, Box<Expr>, Box<Expr>),
    /// Equality of non-numbers (pointers, objects, `null`).
    Same(bool, Box<Expr>, Box<Expr>),
    And(Box<Expr>, Box<Expr>),
    Or(Box<Expr>, Box<Expr>),
    Not(Box<Expr>),
    Negate(Arith, Box<Expr>),
    BitNot(Arith, Box<Expr>),
    Convert(Conv, Box<Expr>),
    /// `p + n` / `p - n` on a pointer.
    Offset(Box<Expr>, Box<Expr>, bool),
    Index(Box<Expr>, Box<Expr>, Span),
    Assign(Box<Place>, Box<Expr>),
    /// `x op= v`, `++x`, `x++`: the place, the operation and operand, whether the old value
    /// is the result.
    Update(Box<Place>, BinOp, Arith, Box<Expr>, bool, Span),
    Ternary(Box<Expr>, Box<Expr>, Box<Expr>),
    /// A framework method or function: its receiver (if any) first among the arguments.
    Call(Method, Vec<Expr>, Span),
    /// `new T[n]`: `n` zeroed elements.
    NewArray(Scalar, Box<Expr>, Span),
    /// `call C::m(…)` in a calc or calcRange node: kernel `kernel` of the run's table.
    Launch(usize, Vec<Expr>, Span),
    /// `call behavior D(…)`: diagram `diagram` of the program run with `args` (converted to
    /// its parameters); each `out` parameter's value then stored through a slot of the
    /// caller's into the place the argument names. Its value is what the final node returns.
    CallDiagram {
        diagram: usize,
        args: Vec<Expr>,
        outs: Vec<OutArg>,
        span: Span,
    },
}

/// Where a called diagram's `out` parameter goes (one per `out` parameter, in order): its
/// value is put in `slot` (the caller's) once the call has returned, then stored in `place`.
pub struct OutArg {
    pub slot: Slot,
    pub place: Place,
}

/// What can be assigned to: a variable (with the conversion its type asks) or an element.
pub enum Place {
    Var(Slot, Conv),
    Index(Expr, Expr, Span),
}

pub enum Stmt {
    Expr(Expr),
    /// `var T x = init;` or a declaration without one (the type's zero).
    Declare(Slot, Expr),
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    /// A loop of any form: `init`, then while `test` holds, the body then `step`.
    Loop {
        test: Option<Expr>,
        body: Vec<Stmt>,
        step: Vec<Stmt>,
        test_after: bool,
    },
    /// `switch v { case … }`: the cases' labels and statements, then the default's (each
    /// case ends where the next begins).
    Switch(Expr, Vec<(i32, Vec<Stmt>)>, Vec<Stmt>),
    Return,
    Break,
    Continue,
    Block(Vec<Stmt>),
    /// The flow a node holds (Sec. 9.2.2.3), from its start node (an index into
    /// [`Program::nodes`]) to a final node of it, or a node of it with no transition to take.
    Flow(usize),
}

/// How a node is entered and left.
pub struct Node {
    pub name: String,
    pub kind: NodeKind,
    pub span: Span,
    /// Its statements (a loop node's inside its loops).
    pub body: Vec<Stmt>,
    pub edges: Vec<Edge>,
    /// `out` parameters: written back to the caller's variable when the node has run.
    pub outs: Vec<Slot>,
    /// A final node's `return` value (a called diagram's result).
    pub result: Option<Expr>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    Start,
    Final,
    Action,
    Loop,
    Calc,
    CalcRange,
}

/// A transition: taken when its guard holds (no guard: when none of the others does).
pub struct Edge {
    pub guard: Option<Expr>,
    pub target: usize,
    /// The target's parameters and the values they get.
    pub args: Vec<(Slot, Expr)>,
    /// Work sizes of a calc node, ranges of a calcRange node.
    pub work: Vec<Expr>,
    /// For each `out` parameter of the target: where its value goes when the target has run.
    pub outs: Vec<Place>,
}

/// A lowered diagram and the diagrams it calls, theirs too, in one table of nodes and one
/// frame of slots.
pub struct Program {
    /// The diagram that runs first, `diagrams[0]`.
    pub diagram: String,
    pub nodes: Vec<Node>,
    /// The diagram run and then each diagram called with `call behavior`, in the order the
    /// calls were found.
    pub diagrams: Vec<Diagram>,
    /// Each slot's conversion: what its variable's type makes of what is stored in it.
    pub slots: Vec<Conv>,
    /// Names of the diagram variables and their slots (a finished run can be inspected).
    pub variables: Vec<(String, Slot)>,
}

/// One diagram of a program.
pub struct Diagram {
    pub name: String,
    pub start: usize,
    /// Its variables' initialisation, in order (after its parameters got their values).
    pub init: Vec<Stmt>,
    /// Its parameters' slots, in order, and whether each is `out`.
    pub params: Vec<(Slot, bool)>,
    /// Every slot of its own (parameters, variables, nodes' parameters, locals): saved and
    /// restored around a call that finds the diagram running already (recursion).
    pub frame: std::ops::Range<Slot>,
}
