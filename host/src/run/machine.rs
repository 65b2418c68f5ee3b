//! The interpreter's state and the shape of compiled code: the [`Machine`] a run holds, the
//! closures [`compile`](super::compile) and [`native`](super::native) make of the program
//! ([`Code`], [`Block`], [`Compiled`]), how a statement ends ([`Flow`]) and how a run stops
//! ([`Outcome`], [`failed`]). What the machine does is `exec.rs`'s.

use std::{rc::Rc, time::Duration};

use crate::launch::Launcher;

use super::{
    framework::Framework,
    ir::{Program, Slot, Span},
    value::Value,
    CalcReport, Observer, RunError,
};

/// How a statement ends.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Flow {
    Next,
    Break,
    Continue,
    Return,
}

pub(super) type Outcome<T> = Result<T, Box<RunError>>;

/// The state of a run: the program and its compiled code, the frame of variables, the
/// framework's objects, the kernels' launchers, the observer, and what the report counts.
pub(super) struct Machine<'r, 'g> {
    pub program: &'r Program,
    pub(super) code: Rc<Compiled>,
    pub frame: Vec<Value>,
    pub framework: Framework<'g>,
    pub launchers: &'r [Launcher],
    pub observer: &'r mut dyn Observer,
    /// The work sizes (calc) or ranges (calcRange) the current node was entered with.
    pub work: Vec<i64>,
    pub node: usize,
    pub nodes_run: u64,
    /// How often a loop ran as machine code.
    pub native_loops: u64,
    pub calcs: Vec<CalcReport>,
    /// Per node: how often it ran, for how long in all, and the order it first ran in.
    pub times: Vec<(u32, Duration, usize)>,
    pub(super) iterations: u32,
    /// Per diagram: how many of its calls are running.
    pub(super) active: Vec<u32>,
    /// How many calls are running.
    pub(super) depth: u32,
}

/// A compiled piece of the program: run on the machine, it gives a `T` or stops the run.
pub(super) type Code<T> = Box<dyn Fn(&mut Machine<'_, '_>) -> Outcome<T>>;

/// Statements, in order.
pub(super) type Block = Box<[Code<Flow>]>;

/// A compiled program: each diagram's variables' initialisation, and each node.
pub(super) struct Compiled {
    pub inits: Vec<Block>,
    pub nodes: Vec<NodeCode>,
}

pub(super) struct NodeCode {
    pub body: Block,
    pub edges: Vec<EdgeCode>,
    /// A final node's return value.
    pub result: Option<Code<Value>>,
}

/// A transition's guard, arguments and work sizes, as in [`super::ir::Edge`], and the
/// assignments of the target's `out` parameters to the places the transition names.
pub(super) struct EdgeCode {
    pub guard: Option<Code<bool>>,
    pub args: Vec<(Slot, Code<Value>)>,
    pub work: Vec<Code<i32>>,
    pub outs: Block,
}

/// Runs `block`'s statements until one leaves it.
#[inline]
pub(super) fn run_block(machine: &mut Machine<'_, '_>, block: &Block) -> Outcome<Flow> {
    for stmt in block.iter() {
        match stmt(machine)? {
            Flow::Next => {}
            other => return Ok(other),
        }
    }
    Ok(Flow::Next)
}

/// An error at `span` while the diagram runs.
#[cold]
pub(super) fn failed(span: Span, message: String) -> Box<RunError> {
    Box::new(RunError::failed(Some(span), message))
}
