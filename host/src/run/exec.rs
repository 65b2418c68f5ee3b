//! Running a compiled diagram: from the start node, each node's statements, then the first
//! transition whose guard holds (the unguarded one otherwise) with its arguments handed to the
//! target's parameters, until a final node — or a node with no transition to take. A
//! `call behavior` runs the called diagram's nodes the same way, and returns. The
//! observer is told of every node and asked between nodes (and every 65 536 loop iterations)
//! whether to stop. The operations the compiled code does not do inline — framework calls,
//! allocation, kernel launches — are here too.

use std::{
    rc::Rc,
    time::{Duration, Instant},
};

use crate::launch::Launcher;

use super::{
    arith::int,
    compile,
    framework::{Framework, Method},
    ir::{NodeKind, Program, Span},
    machine::{failed, run_block, Compiled, Machine, Outcome},
    value::{memory, Pointer, Scalar, Value},
    Ending, Observer, RunError,
};

/// Loop iterations between two questions to the observer whether to stop.
const CANCEL_CHECK_INTERVAL: u32 = 1 << 16;

/// How deep `call behavior` calls may nest (each takes stack of the thread that runs).
const MAX_CALL_DEPTH: u32 = 200;

impl<'r, 'g> Machine<'r, 'g> {
    pub fn new(
        program: &'r Program,
        framework: Framework<'g>,
        launchers: &'r [Launcher],
        observer: &'r mut dyn Observer,
        native: bool,
    ) -> Machine<'r, 'g> {
        Machine {
            program,
            code: Rc::new(compile::program(program, native)),
            frame: vec![Value::Void; program.slots.len()],
            framework,
            launchers,
            observer,
            work: Vec::new(),
            node: program.diagrams[0].start,
            nodes_run: 0,
            native_loops: 0,
            calcs: Vec::new(),
            times: vec![(0, Duration::ZERO, usize::MAX); program.nodes.len()],
            iterations: 0,
            active: vec![0; program.diagrams.len()],
            depth: 0,
        }
    }

    /// Runs the diagram to its end.
    pub fn run(&mut self) -> Outcome<Ending> {
        let code = Rc::clone(&self.code);
        self.active[0] = 1;
        run_block(self, &code.inits[0])?;
        self.flow(&code, self.program.diagrams[0].start).map(|(ending, _)| ending)
    }

    /// Runs nodes from `start` until a final node (with what it returns) or a node with no
    /// transition to take.
    pub(super) fn flow(&mut self, code: &Compiled, start: usize) -> Outcome<(Ending, Value)> {
        let program = self.program;
        let mut current = start;
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
                let result = match &compiled.result {
                    Some(result) => result(self)?,
                    None => Value::Void,
                };
                return Ok((Ending::Final(node.name.clone()), result));
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
            let Some(taken) = taken else { return Ok((Ending::NoTransition(node.name.clone()), Value::Void)) };
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

    /// `call behavior` of diagram `index` with `args` (its parameters' values): what its final
    /// node returns and the values of its `out` parameters. A diagram that is running already
    /// (recursion) has its slots saved and restored around the call.
    #[inline(never)]
    pub fn call_diagram(&mut self, index: usize, args: Vec<Value>, span: Span) -> Outcome<(Value, Vec<Value>)> {
        let program = self.program;
        let diagram = &program.diagrams[index];
        if self.depth >= MAX_CALL_DEPTH {
            return Err(failed(
                span,
                format!("calls nested {MAX_CALL_DEPTH} deep: `{}` recurses without end?", diagram.name),
            ));
        }
        let saved = (self.active[index] > 0).then(|| self.frame[diagram.frame.clone()].to_vec());
        for ((slot, _), value) in diagram.params.iter().zip(args) {
            self.frame[*slot] = value;
        }
        let (node, work) = (self.node, std::mem::take(&mut self.work));
        self.active[index] += 1;
        self.depth += 1;
        let code = Rc::clone(&self.code);
        let ran = run_block(self, &code.inits[index]).and_then(|_| self.flow(&code, diagram.start));
        self.active[index] -= 1;
        self.depth -= 1;
        let (result, outs) = match ran? {
            (Ending::NoTransition(at), _) => {
                return Err(failed(
                    span,
                    format!(
                        "`{}` stopped at node `{at}`, where no transition can be taken: a called diagram returns \
                         to its caller from a final node",
                        diagram.name
                    ),
                ))
            }
            (Ending::Final(_), result) => {
                (result, diagram.params.iter().filter(|(_, out)| *out).map(|(slot, _)| self.frame[*slot].clone()))
            }
        };
        let outs = outs.collect();
        if let Some(saved) = saved {
            self.frame[diagram.frame.clone()].clone_from_slice(&saved);
        }
        (self.node, self.work) = (node, work);
        Ok((result, outs))
    }

    /// The error of a run stopped on request in the current node.
    #[cold]
    pub fn cancellation(&self) -> Box<RunError> {
        Box::new(RunError::cancelled(&self.program.nodes[self.node].name))
    }

    /// Counts a loop iteration; every [`CANCEL_CHECK_INTERVAL`], whether to stop.
    #[inline]
    pub fn iterated(&mut self) -> Outcome<()> {
        self.iterations = self.iterations.wrapping_add(1);
        if self.iterations.is_multiple_of(CANCEL_CHECK_INTERVAL) && self.observer.cancelled() {
            return Err(self.cancellation());
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
