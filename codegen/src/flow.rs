//! An activity diagram's control flow as WGSL: structured (`structured.rs`) where the graph
//! allows it, otherwise a state loop over its nodes (correct for any graph). Either way a node
//! runs its statements — inside the loops of a loop or loopWindow node — then takes the first
//! transition whose guard holds, the unguarded one otherwise; a final node, or no transition to
//! take, ends the work-item. `return` leaves the node (its statements run in a `loop` that the
//! `return` breaks, through a flag from inside loops and `switch`es), as on the host.
//! Transition arguments go to the target node's parameters, which live across nodes. In the
//! state loop each node is a `case`.

use std::collections::HashMap;

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::{BodyTypes, Ty},
    syntax::SyntaxKind::RETURN_STMT,
};

use crate::{
    emitter::{bare, ident, Emitter, NodeExit, GENERATED, LEAVE_NODE},
    types::value_type,
};

/// The state that ends the kernel.
const DONE: &str = "0xffffffffu";

impl Emitter<'_> {
    /// The body of the entry point for `nodes` (all nodes of the diagram, swimlanes flattened).
    pub fn control_flow(&mut self, diagram: &ast::ActivityDiagram, nodes: &[ast::ActivityNode]) {
        let graph = self.graph(nodes, format!("{GENERATED}state"));
        let Some(start) = nodes.iter().position(|n| n.kind() == ast::NodeKind::Start) else {
            self.unsupported(diagram.syntax(), "a diagram without a start node cannot run");
            return;
        };
        self.node_parameters(&graph);
        let checkpoint = self.checkpoint();
        if self.structured(&graph, start).is_some() {
            return;
        }
        self.restore(checkpoint);
        self.state_loop(&graph, start);
    }

    /// The flow a container node holds (Sec. 9.2.2.3), after its statements: a state loop of
    /// its own from its start node, ended by a nested final node (or where no transition is
    /// taken); the container's code goes on after it.
    fn nested_flow(&mut self, container: &ast::ActivityNode) {
        let nodes: Vec<ast::ActivityNode> = container.nested_nodes().collect();
        if nodes.is_empty() {
            return;
        }
        let Some(start) = nodes.iter().position(|n| n.kind() == ast::NodeKind::Start) else {
            self.unsupported(container.syntax(), "a node holding nodes needs a start node among them");
            return;
        };
        let name = container.name().map(|n| n.text()).unwrap_or_default();
        let graph = self.graph(&nodes, format!("{GENERATED}state_{name}"));
        let outer = std::mem::take(&mut self.types);
        self.line(format!("// the flow node `{name}` holds"));
        self.node_parameters(&graph);
        self.state_loop(&graph, start);
        self.types = outer;
    }

    /// The nodes of one flow with their transitions (each node's in the order its guards are
    /// tried) and types; `state` names the variable of its state loop.
    fn graph(&self, nodes: &[ast::ActivityNode], state: String) -> Graph {
        let index: HashMap<String, usize> =
            nodes.iter().enumerate().filter_map(|(i, n)| Some((n.name()?.text(), i))).collect();
        let edges = nodes
            .iter()
            .map(|node| {
                let mut edges: Vec<Edge> = node
                    .transitions()
                    .map(|transition| Edge {
                        condition: transition.guard().and_then(|g| g.condition()),
                        target: transition.target().and_then(|t| index.get(&t.text()).copied()),
                        transition,
                    })
                    .collect();
                // Stable: the guarded ones as written, then the unguarded one.
                edges.sort_by_key(|edge| edge.condition.is_none());
                edges
            })
            .collect();
        Graph {
            nodes: nodes.to_vec(),
            edges,
            types: nodes.iter().map(|n| self.sema.body_types(n.syntax())).collect(),
            state,
        }
    }

    /// The parameters of the flow's nodes that take arguments, declared once for all its cases.
    fn node_parameters(&mut self, graph: &Graph) {
        for (node, types) in graph.nodes.iter().zip(&graph.types) {
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
    }

    /// The general form: `loop { switch state { case node: … } }`.
    fn state_loop(&mut self, graph: &Graph, start: usize) {
        let nodes = &graph.nodes;
        let state = &graph.state;
        self.line(format!("var {state}: u32 = {start}u;"));
        self.block("loop {", |e| {
            e.line(format!("if {state} == {DONE} {{ break; }}"));
            e.block(format!("switch {state} {{"), |e| {
                for (i, node) in nodes.iter().enumerate() {
                    let name = node.name().map(|n| n.text()).unwrap_or_default();
                    e.line(format!("// {} `{name}`", node.kind().keyword()));
                    e.types = graph.types[i].clone();
                    e.block(format!("case {i}u: {{"), |e| e.node(i, graph));
                }
                e.line(format!("default: {{ {state} = {DONE}; }}"));
            });
        });
    }

    /// One node's case (`self.types` are the node's).
    fn node(&mut self, n: usize, graph: &Graph) {
        if self.node_body(&graph.nodes[n]) {
            self.transitions(n, graph);
        } else {
            self.line(format!("{} = {DONE};", graph.state));
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
                self.statements(node);
                // `final f return v` of a diagram generated as a function gives `v`.
                let returns = self.current_function.as_ref().map(|(_, ty)| ty.clone()).filter(|ty| *ty != Ty::Void);
                match (node.return_value(), returns) {
                    (Some(value), Some(returns)) => {
                        let value = bare(self.expr_as(&value, &returns));
                        self.line(format!("return {value};"));
                    }
                    (Some(value), None) => {
                        self.unsupported(value.syntax(), "a kernel returns no value");
                    }
                    (None, _) => {}
                }
                return false;
            }
            ast::NodeKind::Loop | ast::NodeKind::LoopWindow => self.leavable(node, Self::loop_node),
            ast::NodeKind::Fork | ast::NodeKind::Join => {
                self.unsupported(node.syntax(), "forks and joins run in parallel: a work-item has one flow");
                return false;
            }
            ast::NodeKind::Calc | ast::NodeKind::CalcRange => {
                self.unsupported(node.syntax(), "calc and calcRange nodes start kernels: they belong to host diagrams");
                return false;
            }
            _ => self.leavable(node, Self::statements),
        }
        true
    }

    /// A node's code as `write` writes it; where the node `return`s, inside a `loop` that the
    /// `return` leaves (its transitions follow, as on the host).
    fn leavable(&mut self, node: &ast::ActivityNode, write: fn(&mut Self, &ast::ActivityNode)) {
        let returns = node.body().is_some_and(|body| body.syntax().descendants().any(|n| n.kind() == RETURN_STMT));
        if !returns {
            return write(self, node);
        }
        let outer = self.node_exit.replace(NodeExit { depth: 0, nested_returns: 0 });
        self.block("loop { // `return` leaves the node", |e| {
            let (start, _) = e.checkpoint();
            write(e, node);
            // A `return` inside a loop or `switch` (the node's own loops too) leaves by a flag.
            if e.node_exit.is_some_and(|exit| exit.nested_returns > 0) {
                e.insert_line(start, format!("var {LEAVE_NODE} = false;"));
            }
            e.line("break;");
        });
        self.node_exit = outer;
    }

    /// A node's statements, then the flow of the nodes it holds.
    fn statements(&mut self, node: &ast::ActivityNode) {
        for stmt in node.statements() {
            self.statement(&stmt);
        }
        self.nested_flow(node);
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
    fn transitions(&mut self, n: usize, graph: &Graph) {
        let edges = &graph.edges[n];
        if graph.forks(n) {
            let message = "several unguarded transitions fork the flow: a work-item has one flow";
            self.unsupported(graph.nodes[n].syntax(), message);
            return;
        }
        let mut first = true;
        for edge in edges {
            match &edge.condition {
                Some(condition) => {
                    let condition = self.expr_as(condition, &Ty::Bool);
                    let opener = if first { format!("if {condition} {{") } else { format!("else if {condition} {{") };
                    self.block(opener, |e| e.take(edge, graph));
                }
                None if first => self.take(edge, graph),
                None => self.block("else {", |e| e.take(edge, graph)),
            }
            first = false;
        }
        if !graph.has_else(n) {
            match first {
                true => self.line(format!("{} = {DONE};", graph.state)),
                false => self.line(format!("else {{ {} = {DONE}; }}", graph.state)),
            }
        }
    }

    /// Moves to a transition's target.
    fn take(&mut self, edge: &Edge, graph: &Graph) {
        if let Some(state) = self.hand_over(edge, graph) {
            self.line(format!("{} = {state}u;", graph.state));
        }
    }

    /// Hands a transition's arguments to its target's parameters; the target.
    pub(crate) fn hand_over(&mut self, edge: &Edge, graph: &Graph) -> Option<usize> {
        let transition = &edge.transition;
        let Some(state) = edge.target else {
            let target = transition.target().map(|t| t.text()).unwrap_or_default();
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

/// The nodes of a diagram, each one's transitions in the order their guards are tried, and the
/// types of each one's body (computed once: a node's own code and the transitions into it read
/// them).
pub(crate) struct Graph {
    pub nodes: Vec<ast::ActivityNode>,
    pub edges: Vec<Vec<Edge>>,
    pub types: Vec<BodyTypes>,
    /// The variable of the flow's state loop.
    pub state: String,
}

/// A transition: its guard's condition (`None`: unguarded, the else branch) and the index of
/// the node it leads to (`None` for an unknown name).
pub(crate) struct Edge {
    pub transition: ast::Transition,
    pub condition: Option<ast::Expr>,
    pub target: Option<usize>,
}

impl Graph {
    /// Whether node `n` has an unguarded transition, taken when no guard holds.
    pub fn has_else(&self, n: usize) -> bool {
        self.edges[n].last().is_some_and(|edge| edge.condition.is_none())
    }

    /// Whether node `n` has several unguarded transitions: a fork, not one flow.
    pub fn forks(&self, n: usize) -> bool {
        self.edges[n].iter().filter(|edge| edge.condition.is_none()).count() > 1
    }
}

/// The variable that carries a node parameter between cases.
fn carrier(node: &ast::ActivityNode, param: &str) -> String {
    let node = node.name().map(|n| n.text()).unwrap_or_default();
    format!("{GENERATED}{node}_{param}")
}
