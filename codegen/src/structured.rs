//! Structured control flow where the diagram's graph is structured: a sequence of nodes is a
//! sequence of statements, a node whose transitions branch is an `if … else if … else` whose
//! branches meet again at the node's immediate post-dominator, a node that transitions back to
//! one before it (a back edge of a reducible graph) heads a `loop { … }` left with `break` at its
//! post-dominator and re-entered with `continue`. Anything else (irreducible loops, branches that
//! join in the middle of one another, a `continue` to an outer loop) is left to the state loop:
//! [`Emitter::structured`] answers `None` and writes nothing that stays.

use std::collections::{BTreeSet, HashSet};

use gudsl_model::ast::{self, HasName};

use crate::{emitter::Emitter, flow::Graph};

/// Where control goes: a node, or the end of the work-item.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Target {
    Node(usize),
    Exit,
}

/// What the graph's shape says about each node.
struct Shape {
    /// Transitions `(from, to)` back to a node that dominates `from`: a loop's `continue`.
    back: HashSet<(usize, usize)>,
    /// The targets of back transitions: the nodes that head a loop.
    headers: HashSet<usize>,
    /// Where the paths from a node meet again, back transitions aside (`None`: all of them go
    /// back to a loop's head).
    merge: Vec<Option<Target>>,
}

/// The successors of each node in the order their guards are tried (guarded ones as written,
/// then the unguarded one), with `Exit` where no transition may be taken; `None` for a node
/// structured output does not handle.
fn successors(graph: &Graph, n: usize) -> Option<Vec<Target>> {
    let node = &graph.nodes[n];
    match node.kind() {
        ast::NodeKind::Final => return Some(vec![Target::Exit]),
        ast::NodeKind::Fork | ast::NodeKind::Join | ast::NodeKind::Calc | ast::NodeKind::CalcRange => return None,
        _ => {}
    }
    if graph.forks(n) {
        return None;
    }
    let mut out: Vec<Target> =
        graph.edges[n].iter().map(|edge| edge.target.map(Target::Node)).collect::<Option<_>>()?;
    if !graph.has_else(n) {
        out.push(Target::Exit);
    }
    Some(out)
}

impl Shape {
    fn of(graph: &Graph, start: usize) -> Option<Shape> {
        let count = graph.nodes.len();
        let mut succ = vec![Vec::new(); count];
        // Depth-first from the start: reachable nodes, back transitions (to a node on the path).
        let (mut seen, mut on_path) = (vec![false; count], vec![false; count]);
        let mut back = HashSet::new();
        let mut order = Vec::new();
        let mut stack = vec![(start, 0usize)];
        seen[start] = true;
        on_path[start] = true;
        succ[start] = successors(graph, start)?;
        while let Some((n, next)) = stack.pop() {
            match succ[n].get(next).copied() {
                Some(Target::Node(m)) => {
                    stack.push((n, next + 1));
                    if on_path[m] {
                        back.insert((n, m));
                    } else if !seen[m] {
                        seen[m] = true;
                        on_path[m] = true;
                        succ[m] = successors(graph, m)?;
                        stack.push((m, 0));
                    }
                }
                Some(Target::Exit) => stack.push((n, next + 1)),
                None => {
                    on_path[n] = false;
                    order.push(n);
                }
            }
        }
        // `order` is a post-order: reversed, a topological order of the forward transitions.
        order.reverse();
        let forward: Vec<Vec<Target>> = (0..count)
            .map(|n| {
                succ[n].iter().copied().filter(|t| !matches!(t, Target::Node(m) if back.contains(&(n, *m)))).collect()
            })
            .collect();

        // Reducible: every back transition goes to a node that dominates its source (over all
        // transitions, iterated to the fixed point).
        let all: BTreeSet<usize> = order.iter().copied().collect();
        let mut dominators: Vec<BTreeSet<usize>> = vec![all.clone(); count];
        dominators[start] = BTreeSet::from([start]);
        let mut changed = true;
        while changed {
            changed = false;
            for &n in order.iter().skip(1) {
                let preds = order.iter().filter(|&&p| succ[p].contains(&Target::Node(n)));
                let mut own = preds
                    .map(|&p| dominators[p].clone())
                    .reduce(|a, b| a.intersection(&b).copied().collect())
                    .unwrap_or_default();
                own.insert(n);
                if own != dominators[n] {
                    dominators[n] = own;
                    changed = true;
                }
            }
        }
        if back.iter().any(|(from, to)| !dominators[*from].contains(to)) {
            return None;
        }

        // Post-dominators over the forward transitions; a node whose transitions all go back
        // constrains nothing (`None`: every target post-dominates it).
        let mut post: Vec<Option<BTreeSet<Target>>> = vec![None; count];
        for &n in order.iter().rev() {
            let mut common: Option<BTreeSet<Target>> = None;
            for &t in &forward[n] {
                let of_t = match t {
                    Target::Exit => Some(BTreeSet::from([Target::Exit])),
                    Target::Node(m) => post[m].clone(),
                };
                if let Some(of_t) = of_t {
                    common = Some(match common {
                        None => of_t,
                        Some(c) => c.intersection(&of_t).copied().collect(),
                    });
                }
            }
            post[n] = common.map(|mut c| {
                c.insert(Target::Node(n));
                c
            });
        }
        // The immediate post-dominator: the strict one all the others post-dominate.
        let merge = (0..count)
            .map(|n| {
                let strict: BTreeSet<Target> =
                    post[n].as_ref()?.iter().copied().filter(|t| *t != Target::Node(n)).collect();
                strict.iter().copied().find(|t| match t {
                    Target::Exit => strict.len() == 1,
                    Target::Node(m) => post[*m].as_ref() == Some(&strict),
                })
            })
            .collect();
        let headers = back.iter().map(|(_, to)| *to).collect();
        Some(Shape { back, headers, merge })
    }
}

/// The walk through the graph while writing it.
struct Walk<'g> {
    graph: &'g Graph,
    shape: Shape,
    written: Vec<bool>,
    /// The heads of the loops being written, innermost last.
    open_loops: Vec<usize>,
}

impl Walk<'_> {
    /// Whether reaching the end of the work-item at the end of a region ending at `stop` is the
    /// end of the entry point (nothing is written after it).
    fn at_tail(&self, stop: Target) -> bool {
        stop == Target::Exit && self.open_loops.is_empty()
    }
}

impl Emitter<'_> {
    /// The diagram's control flow as structured statements, or `None` (nothing written) where
    /// its graph is not structured.
    pub(crate) fn structured(&mut self, graph: &Graph, start: usize) -> Option<()> {
        let shape = Shape::of(graph, start)?;
        let mut walk = Walk { graph, shape, written: vec![false; graph.nodes.len()], open_loops: Vec::new() };
        self.region(&mut walk, Target::Node(start), Target::Exit)
    }

    /// Writes the flow from `at` until it reaches `stop`.
    fn region(&mut self, walk: &mut Walk<'_>, mut at: Target, stop: Target) -> Option<()> {
        loop {
            let n = match at {
                _ if at == stop => return Some(()),
                Target::Exit => {
                    if !walk.at_tail(stop) {
                        self.leave();
                    }
                    return Some(());
                }
                Target::Node(n) => n,
            };
            if walk.shape.headers.contains(&n) && !walk.open_loops.contains(&n) {
                let exit = walk.shape.merge[n].unwrap_or(Target::Exit);
                self.line("loop {");
                self.shift(1);
                walk.open_loops.push(n);
                if let Some(next) = self.write_node(walk, n, exit)? {
                    self.region(walk, next, exit)?;
                }
                self.line("break;");
                walk.open_loops.pop();
                self.shift(-1);
                self.line("}");
                at = exit;
                continue;
            }
            match self.write_node(walk, n, stop)? {
                Some(next) => at = next,
                None => return Some(()),
            }
        }
    }

    /// Writes node `n` and its branches up to where they meet; where the flow goes on from
    /// there (`None` when it does not: a final node, a `continue`).
    fn write_node(&mut self, walk: &mut Walk<'_>, n: usize, stop: Target) -> Option<Option<Target>> {
        if std::mem::replace(&mut walk.written[n], true) {
            return None; // reached twice: not structured
        }
        let graph = walk.graph;
        let node = &graph.nodes[n];
        let name = node.name().map(|n| n.text()).unwrap_or_default();
        self.line(format!("// {} `{name}`", node.kind().keyword()));
        self.types = graph.types[n].clone();
        // A node's own variables live in its own block (another node may use the same names);
        // a loop node's statements are in its loops already.
        let looped = matches!(node.kind(), ast::NodeKind::Loop | ast::NodeKind::LoopWindow);
        let scoped = node.params().next().is_some()
            || (!looped && node.statements().any(|s| matches!(s, ast::Stmt::VarDecl(_))));
        if scoped {
            self.line("{");
            self.shift(1);
        }
        let goes_on = if self.node_body(node) {
            self.branches(walk, n, stop)?
        } else {
            // A final node: the work-item ends; leave the entry point unless nothing follows.
            if !walk.at_tail(stop) {
                self.leave();
            }
            None
        };
        if scoped {
            self.shift(-1);
            self.line("}");
        }
        Some(goes_on)
    }

    /// Node `n`'s transitions: straight on, or an `if` chain whose branches run to the node's
    /// merge point; where the flow goes on.
    fn branches(&mut self, walk: &mut Walk<'_>, n: usize, stop: Target) -> Option<Option<Target>> {
        let graph = walk.graph;
        let edges = &graph.edges[n];
        let Some(first) = edges.first() else {
            // No transition: the work-item ends here.
            if !walk.at_tail(stop) {
                self.leave();
            }
            return Some(None);
        };
        if first.condition.is_none() {
            self.hand_over(first, graph);
            return self.jump(walk, n, first.target?);
        }
        let merge = walk.shape.merge[n];
        let region_end = merge.unwrap_or(Target::Exit);
        let guarded = edges.iter().filter_map(|edge| Some((edge, edge.condition.as_ref()?)));
        for (i, (edge, condition)) in guarded.enumerate() {
            let condition = self.expr_as(condition, &gudsl_model::hir::Ty::Bool);
            let opener = if i == 0 { format!("if {condition} {{") } else { format!("}} else if {condition} {{") };
            self.line(opener);
            self.shift(1);
            self.hand_over(edge, graph);
            self.branch(walk, n, edge.target?, region_end)?;
            self.shift(-1);
        }
        let checkpoint = self.checkpoint();
        self.line("} else {");
        self.shift(1);
        let before_else = self.checkpoint();
        match edges.last().filter(|edge| edge.condition.is_none()) {
            Some(edge) => {
                self.hand_over(edge, graph);
                self.branch(walk, n, edge.target?, region_end)?;
            }
            None => self.region(walk, Target::Exit, region_end)?,
        }
        self.shift(-1);
        if self.checkpoint() == before_else {
            self.restore(checkpoint);
        }
        self.line("}");
        Some(merge)
    }

    /// One branch of a node's `if` chain: a `continue` for a back transition, else the region
    /// from its target to the merge point.
    fn branch(&mut self, walk: &mut Walk<'_>, from: usize, target: usize, merge: Target) -> Option<()> {
        match self.jump(walk, from, target)? {
            Some(next) => self.region(walk, next, merge),
            None => Some(()),
        }
    }

    /// Goes from `from` to `target`: `continue` when it is a back transition (to the innermost
    /// loop being written; an outer one cannot be named in WGSL), else `target` is next.
    fn jump(&mut self, walk: &mut Walk<'_>, from: usize, target: usize) -> Option<Option<Target>> {
        if walk.shape.back.contains(&(from, target)) {
            if walk.open_loops.last() != Some(&target) {
                return None;
            }
            self.line("continue;");
            return Some(None);
        }
        Some(Some(Target::Node(target)))
    }
}
