//! An activity diagram's control flow as WGSL: structured (`structured.rs`) where the graph
//! allows it, otherwise a state loop over its nodes (correct for any graph). Either way a node
//! runs its statements — inside the loops of a loop or loopWindow node — then takes the first
//! transition whose guard holds, the unguarded one otherwise; a final node, or no transition to
//! take, ends the work-item. Transition arguments go to the target node's parameters, which live
//! across nodes. In the state loop each node is a `case`.

use std::collections::HashMap;

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::{BodyTypes, Ty},
};

use crate::{
    emitter::{bare, ident, Emitter, GENERATED},
    types::value_type,
};

/// The state that ends the kernel.
const DONE: &str = "0xffffffffu";

impl Emitter<'_> {
    /// The body of the entry point for `nodes` (all nodes of the diagram, swimlanes flattened).
    pub fn control_flow(&mut self, diagram: &ast::ActivityDiagram, nodes: &[ast::ActivityNode]) {
        let index: HashMap<String, usize> =
            nodes.iter().enumerate().filter_map(|(i, n)| Some((n.name()?.text(), i))).collect();
        let targets = nodes
            .iter()
            .map(|n| n.transitions().map(|t| t.target().and_then(|t| index.get(&t.text()).copied())).collect())
            .collect();
        let graph = Graph {
            nodes: nodes.to_vec(),
            index,
            targets,
            types: nodes.iter().map(|n| self.sema.body_types(n.syntax())).collect(),
        };
        let Some(start) = nodes.iter().position(|n| n.kind() == ast::NodeKind::Start) else {
            self.unsupported(diagram.syntax(), "a diagram without a start node cannot run");
            return;
        };
        // The parameters of nodes that take arguments, declared once for all cases.
        for (node, types) in nodes.iter().zip(&graph.types) {
            for param in node.params() {
                let Some(name) = param.name().map(|n| n.text()) else { continue };
                let ty = types.locals.get(&name).cloned().unwrap_or(Ty::Unknown);
                match value_type(&ty) {
                    Some(wgsl) => self.line(format!("var {}: {wgsl};", carrier(node, &name))),
                    None => {
                        self.unsupported(param.syntax(), format!("a `{ty}` node parameter has no WGSL value type"));
                    }
                }
            }
        }
        let checkpoint = self.checkpoint();
        if self.structured(&graph, start).is_some() {
            return;
        }
        self.restore(checkpoint);
        self.state_loop(&graph, start);
    }

    /// The general form: `loop { switch state { case node: … } }`.
    fn state_loop(&mut self, graph: &Graph, start: usize) {
        let nodes = &graph.nodes;
        self.line(format!("var {GENERATED}state: u32 = {start}u;"));
        self.block("loop {", |e| {
            e.line(format!("if {GENERATED}state == {DONE} {{ break; }}"));
            e.block(format!("switch {GENERATED}state {{"), |e| {
                for (i, node) in nodes.iter().enumerate() {
                    let name = node.name().map(|n| n.text()).unwrap_or_default();
                    e.line(format!("// {} `{name}`", keyword(node.kind())));
                    e.types = graph.types[i].clone();
                    e.block(format!("case {i}u: {{"), |e| e.node(node, graph));
                }
                e.line(format!("default: {{ {GENERATED}state = {DONE}; }}"));
            });
        });
    }

    /// One node's case (`self.types` are the node's).
    fn node(&mut self, node: &ast::ActivityNode, graph: &Graph) {
        if self.node_body(node) {
            self.transitions(node, graph);
        } else {
            self.line(format!("{GENERATED}state = {DONE};"));
        }
    }

    /// A node's parameters and statements (`self.types` are the node's); whether transitions
    /// follow (not after a final node, nor after one that cannot be generated).
    pub(crate) fn node_body(&mut self, node: &ast::ActivityNode) -> bool {
        for param in node.params() {
            if let Some(name) = param.name().map(|n| n.text()) {
                self.line(format!("var {} = {};", ident(&name), carrier(node, &name)));
            }
        }
        match node.kind() {
            ast::NodeKind::Final => {
                if let Some(value) = node.return_value() {
                    self.unsupported(value.syntax(), "a kernel returns no value");
                }
                self.statements(node);
                return false;
            }
            ast::NodeKind::Loop | ast::NodeKind::LoopWindow => self.loop_node(node),
            ast::NodeKind::Fork | ast::NodeKind::Join => {
                self.unsupported(node.syntax(), "forks and joins run in parallel: a work-item has one flow");
                return false;
            }
            ast::NodeKind::Calc | ast::NodeKind::CalcRange => {
                self.unsupported(node.syntax(), "calc and calcRange nodes start kernels: they belong to host diagrams");
                return false;
            }
            _ => self.statements(node),
        }
        true
    }

    fn statements(&mut self, node: &ast::ActivityNode) {
        for stmt in node.statements() {
            self.statement(&stmt);
        }
    }

    /// `loop n(init; test; step)` and `loopWindow n(u = …, v = …; …; …)`: the body runs in one
    /// loop per section part (the first outermost); the transitions follow the loops.
    fn loop_node(&mut self, node: &ast::ActivityNode) {
        let Some(header) = node.loop_header() else {
            self.unsupported(node.syntax(), "a loop node needs `(init; test; step)`");
            return;
        };
        let sections: Vec<Vec<ast::LoopPart>> = header.sections().map(|s| s.parts().collect()).collect();
        let mut loops = Vec::new();
        match &sections[..] {
            // `loop n(test)`: a while loop.
            [tests] => {
                for test in tests {
                    let ast::LoopPart::Expr(test) = test else { continue };
                    let test = self.expr_as(test, &Ty::Bool);
                    loops.push(format!("while {test} {{"));
                }
            }
            [inits, tests, steps] if inits.len() == tests.len() && tests.len() == steps.len() => {
                for ((init, test), step) in inits.iter().zip(tests).zip(steps) {
                    let init = self.loop_init(init);
                    let test = match test {
                        ast::LoopPart::Expr(test) => bare(self.expr_as(test, &Ty::Bool)),
                        ast::LoopPart::Decl(decl) => self.unsupported(decl.syntax(), "a declaration as a loop test"),
                    };
                    let step = match step {
                        ast::LoopPart::Expr(step) => self.expr_statement(step),
                        ast::LoopPart::Decl(decl) => self.unsupported(decl.syntax(), "a declaration as a loop step"),
                    };
                    loops.push(format!("for ({init}; {test}; {step}) {{"));
                }
            }
            _ => {
                self.unsupported(header.syntax(), "a loop header is `(init; test; step)` with as many parts in each");
                return;
            }
        }
        self.nest(&loops, &mut |e| e.statements(node));
    }

    /// The first transition whose guard holds is taken; an unguarded one is the else branch.
    fn transitions(&mut self, node: &ast::ActivityNode, graph: &Graph) {
        let transitions: Vec<ast::Transition> = node.transitions().collect();
        let (guarded, unguarded): (Vec<_>, Vec<_>) =
            transitions.iter().partition(|t| t.guard().and_then(|g| g.condition()).is_some());
        if unguarded.len() > 1 {
            self.unsupported(node.syntax(), "several unguarded transitions fork the flow: a work-item has one flow");
            return;
        }
        let mut first = true;
        for transition in &guarded {
            let Some(cond) = transition.guard().and_then(|g| g.condition()) else { continue };
            let cond = self.expr_as(&cond, &Ty::Bool);
            let opener = if first { format!("if {cond} {{") } else { format!("else if {cond} {{") };
            first = false;
            self.block(opener, |e| e.take(transition, graph));
        }
        match unguarded.first() {
            Some(transition) if first => self.take(transition, graph),
            Some(transition) => self.block("else {", |e| e.take(transition, graph)),
            None if first => self.line(format!("{GENERATED}state = {DONE};")),
            None => self.line(format!("else {{ {GENERATED}state = {DONE}; }}")),
        }
    }

    /// Moves to a transition's target.
    fn take(&mut self, transition: &ast::Transition, graph: &Graph) {
        if let Some(state) = self.hand_over(transition, graph) {
            self.line(format!("{GENERATED}state = {state}u;"));
        }
    }

    /// Hands a transition's arguments to its target's parameters; the target.
    pub(crate) fn hand_over(&mut self, transition: &ast::Transition, graph: &Graph) -> Option<usize> {
        let target = transition.target().map(|t| t.text()).unwrap_or_default();
        let Some(&state) = graph.index.get(&target) else {
            self.unsupported(transition.syntax(), format!("no node `{target}`"));
            return None;
        };
        let target_node = &graph.nodes[state];
        let params: Vec<ast::Param> = target_node.params().collect();
        for (arg, param) in transition.args().zip(&params) {
            let Some(name) = param.name().map(|n| n.text()) else { continue };
            let ty = graph.types[state].locals.get(&name).cloned().unwrap_or(Ty::Unknown);
            let value = bare(self.expr_as(&arg, &ty));
            self.line(format!("{} = {value};", carrier(target_node, &name)));
        }
        Some(state)
    }
}

/// The nodes of a diagram, their indexes by name, the node each transition leads to (in the
/// order written; `None` for an unknown name), and the types of each one's body (computed
/// once: a node's own code and the transitions into it read them).
pub(crate) struct Graph {
    pub nodes: Vec<ast::ActivityNode>,
    pub index: HashMap<String, usize>,
    pub targets: Vec<Vec<Option<usize>>>,
    pub types: Vec<BodyTypes>,
}

/// The variable that carries a node parameter between cases.
fn carrier(node: &ast::ActivityNode, param: &str) -> String {
    let node = node.name().map(|n| n.text()).unwrap_or_default();
    format!("{GENERATED}{node}_{param}")
}

pub(crate) fn keyword(kind: ast::NodeKind) -> &'static str {
    use ast::NodeKind::*;
    match kind {
        Start => "start",
        Final => "final",
        Action => "action",
        Decision => "decision",
        Fork => "fork",
        Join => "join",
        Loop => "loop",
        LoopWindow => "loopWindow",
        Calc => "calc",
        CalcRange => "calcRange",
    }
}
