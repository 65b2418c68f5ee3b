//! Running a compiled diagram: from the start node, each node's statements, then the first
//! transition whose guard holds (the unguarded one otherwise) with its arguments handed to the
//! target's parameters, until a final node — or a node with no transition to take. The
//! observer is told of every node and asked between nodes (and every 65 536 loop iterations)
//! whether to stop. The operations the compiled code does not do inline — framework calls,
//! allocation, kernel launches — are here too.

use std::time::{Duration, Instant};

use crate::launch::Launcher;

use super::{
    arith::int,
    compile::{self, Block},
    framework::{Framework, Method},
    ir::{NodeKind, Program, Span},
    value::{memory, Pointer, Scalar, Value},
    CalcReport, Ending, Observer, RunError,
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
            frame: vec![Value::Void; program.slots.len()],
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
        let code = compile::program(program);
        run_block(self, &code.init)?;
        let mut current = program.start;
        // The node and transition the current node was entered by.
        let mut entered: Option<(usize, usize)> = None;
        loop {
            if self.observer.cancelled() {
                return Err(Box::new(RunError::cancelled(&program.nodes[current].name)));
            }
            let node = &program.nodes[current];
            let compiled = &code.nodes[current];
            self.node = current;
            self.nodes_run += 1;
            self.observer.node(&node.name);
            let started = Instant::now();
            let ran = run_block(self, &compiled.body);
            let time = &mut self.times[current];
            if time.0 == 0 {
                time.2 = self.nodes_run as usize;
            }
            time.0 += 1;
            time.1 += started.elapsed();
            ran?;
            if let Some((from, edge)) = entered {
                run_block(self, &code.nodes[from].edges[edge].outs)?;
            }
            if node.kind == NodeKind::Final {
                return Ok(Ending::Final(node.name.clone()));
            }
            let mut taken = None;
            for (i, edge) in compiled.edges.iter().enumerate() {
                let holds = match &edge.guard {
                    Some(guard) => guard(self)?,
                    None => true,
                };
                if holds {
                    taken = Some(i);
                    break;
                }
            }
            let Some(taken) = taken else { return Ok(Ending::NoTransition(node.name.clone())) };
            let edge = &compiled.edges[taken];
            // Every argument is computed before any parameter changes.
            let values = edge.args.iter().map(|(_, value)| value(self)).collect::<Outcome<Vec<_>>>()?;
            for ((slot, _), value) in edge.args.iter().zip(values) {
                self.frame[*slot] = value;
            }
            self.work = edge.work.iter().map(|w| w(self).map(i64::from)).collect::<Outcome<_>>()?;
            entered = Some((current, taken));
            current = program.nodes[current].edges[taken].target;
        }
    }

    /// Counts a loop iteration; every [`CANCEL_CHECK_INTERVAL`], whether to stop.
    #[inline]
    pub fn iterated(&mut self) -> Outcome<()> {
        self.iterations = self.iterations.wrapping_add(1);
        if self.iterations.is_multiple_of(CANCEL_CHECK_INTERVAL) && self.observer.cancelled() {
            return Err(Box::new(RunError::cancelled(&self.program.nodes[self.node].name)));
        }
        Ok(())
    }

    /// A framework method or function called with `args` (the receiver first).
    #[inline(never)]
    pub fn call(&mut self, method: Method, args: &[Value], span: Span) -> Outcome<Value> {
        let result = self.framework.call(method, args).map_err(|m| failed(span, m))?;
        if method == Method::Printf {
            if let Value::Str(text) = &result {
                self.observer.printed(text);
            }
            return Ok(Value::Int(match &result {
                Value::Str(text) => text.len() as i32,
                _ => 0,
            }));
        }
        Ok(result)
    }

    /// `new T[count]`: `count` zeroed elements.
    #[inline(never)]
    pub fn new_array(&mut self, element: Scalar, count: &Value, span: Span) -> Outcome<Value> {
        let count = int(count) as i64;
        let bytes = count.checked_mul(element.size() as i64).filter(|b| (0..=1 << 34).contains(b));
        let Some(bytes) = bytes else {
            return Err(failed(span, format!("an array of {count} elements")));
        };
        Ok(Value::Ptr(Pointer::to(memory(bytes as usize), element)))
    }

    /// Kernel `kernel` launched by the current calc node with `args`.
    #[inline(never)]
    pub fn launch_kernel(&mut self, kernel: usize, args: &[Value], span: Span) -> Outcome<Value> {
        let started = Instant::now();
        let took = self.launch(kernel, args).map_err(|m| failed(span, m))?;
        self.record(kernel, took, started.elapsed());
        Ok(Value::Void)
    }
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
