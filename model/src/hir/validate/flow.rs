//! Control flow of an activity diagram: one start node, transitions to nodes that exist with the
//! arguments their targets take (never into the start node, never out of a final one), guarded
//! transitions out of decisions, joins of several flows, every node reachable from the start,
//! and a final node reachable from every node.

use std::collections::HashMap;

use super::{Ctx, DiagnosticCode};
use crate::{
    ast::{self, AstNode, HasName},
    hir::{diagnostics::arguments, spelling::closest},
};

/// The flows of a diagram — its own and the one each container node holds (Sec. 9.2.2.3) —
/// each checked alone: `nodes` are every node, nested ones included.
pub(super) fn check(ctx: &mut Ctx, diagram: &ast::ActivityDiagram, nodes: &[ast::ActivityNode]) {
    // A diagram with a syntax error may have lost nodes to it (`strat S { … }`): what depends on
    // every node — a start node, targets, reachability — is told once the syntax is fixed, so
    // that one mistake is one diagnostic.
    let complete = !ctx.syntax_error_in(diagram.syntax().text_range());
    let mut levels: Vec<(Option<ast::ActivityNode>, Vec<ast::ActivityNode>)> = Vec::new();
    let mut level_of: HashMap<Option<crate::syntax::TextSize>, usize> = HashMap::new();
    for node in nodes {
        let index = *level_of.entry(node.flow()).or_insert_with(|| {
            levels.push((node.container(), Vec::new()));
            levels.len() - 1
        });
        levels[index].1.push(node.clone());
    }
    // The nodes of a node that holds none are reported as such (E0252), not also as a flow.
    for (container, level) in levels.iter().filter(|(c, _)| c.as_ref().is_none_or(|c| c.may_hold_nodes())) {
        let flow = Flow { diagram, container: container.as_ref(), every_node: nodes, complete };
        flow.check(ctx, level);
    }
}

/// One flow: the diagram's own, or the one a container node holds.
struct Flow<'a> {
    diagram: &'a ast::ActivityDiagram,
    container: Option<&'a ast::ActivityNode>,
    /// Every node of the diagram, nested ones too.
    every_node: &'a [ast::ActivityNode],
    complete: bool,
}

impl Flow<'_> {
    /// How the flow is named in messages: "activity diagram `Ad`", "node `outer`".
    fn describe(&self) -> String {
        match self.container {
            Some(container) => format!("node `{}`", container.name().map(|n| n.text()).unwrap_or_default()),
            None => format!("activity diagram `{}`", self.diagram.name().map(|n| n.text()).unwrap_or_default()),
        }
    }

    /// A transition to `target`, a node of the diagram that is not in this flow.
    fn target_elsewhere(&self, ctx: &mut Ctx, target: &ast::NameRef) -> bool {
        let name = target.text();
        let Some(elsewhere) = self.every_node.iter().find(|n| n.name().is_some_and(|n| n.text() == name)) else {
            return false;
        };
        let message = match elsewhere.container() {
            Some(container) => format!(
                "`{}` is nested in node `{}`: its flow begins at that node's start node, and no transition from outside enters it",
                target.text(),
                container.name().map(|n| n.text()).unwrap_or_default()
            ),
            None => format!(
                "`{}` is outside {}: a nested flow ends at its final node, and its container's transitions go on from there",
                target.text(),
                self.describe()
            ),
        };
        ctx.sink.error(DiagnosticCode::UnresolvedTransitionTarget, target.syntax().text_range(), message);
        true
    }

    /// Start nodes, transition targets and arities, reachability and paths to a final node.
    fn check(&self, ctx: &mut Ctx, nodes: &[ast::ActivityNode]) {
        let complete = self.complete;
        let names: Vec<Option<String>> = nodes.iter().map(|n| n.name().map(|n| n.text())).collect();
        let mut by_name: HashMap<&str, usize> = HashMap::new();
        for (i, name) in names.iter().enumerate().rev() {
            if let Some(name) = name {
                by_name.insert(name, i);
            }
        }
        let starts: Vec<usize> = (0..nodes.len()).filter(|&i| nodes[i].kind() == ast::NodeKind::Start).collect();
        if complete {
            self.start_nodes(ctx, nodes, &starts);
        }
        let mut edges: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
        let mut unresolved = false;
        for (source, node) in nodes.iter().enumerate() {
            let Some(source_name) = &names[source] else { continue };
            for transition in node.transitions() {
                let Some(target) = transition.target() else { continue };
                let target_name = target.text();
                let Some(&target_index) = by_name.get(target_name.as_str()) else {
                    // Where a transition goes nowhere, what is reached is told once it is fixed.
                    unresolved = true;
                    if !complete || self.target_elsewhere(ctx, &target) {
                        continue;
                    }
                    let mut candidates: Vec<&str> = by_name.keys().copied().collect();
                    candidates.sort_unstable();
                    ctx.sink.error_with_suggestion(
                        DiagnosticCode::UnresolvedTransitionTarget,
                        target.syntax().text_range(),
                        format!("no node `{target_name}` in {}", self.describe()),
                        closest(&target_name, candidates),
                    );
                    continue;
                };
                edges[source].push(target_index);
                let target_node = &nodes[target_index];
                transition_arity(ctx, &transition, &target, target_node);
                if target_node.kind() == ast::NodeKind::Start {
                    ctx.sink.error(
                        DiagnosticCode::InvalidTransition,
                        target.syntax().text_range(),
                        format!("no transition enters the start node `{target_name}`: it only begins the activity"),
                    );
                }
            }
            node_transitions(ctx, node, source_name, self.container.is_some());
        }
        forks_and_joins_of_one_flow(ctx, nodes, &edges);
        // A second node of a name is reported as a duplicate (E0205), not again as unreachable.
        let first_of_its_name: Vec<bool> =
            names.iter().enumerate().map(|(i, name)| name.as_ref().is_some_and(|n| by_name[n.as_str()] == i)).collect();
        if complete && !unresolved {
            reachability(ctx, nodes, &first_of_its_name, &starts, &edges);
        }
    }

    /// One start node, named in the diagram's header (or the container's name) when it is
    /// missing.
    fn start_nodes(&self, ctx: &mut Ctx, nodes: &[ast::ActivityNode], starts: &[usize]) {
        if starts.len() == 1 || nodes.is_empty() {
            return;
        }
        let flow_name = self.describe();
        if starts.is_empty() {
            let named = match self.container {
                Some(container) => container.name().map(|n| n.syntax().clone()),
                None => self.diagram.name().map(|n| n.syntax().clone()),
            };
            let range = named.map_or_else(|| self.diagram.syntax().text_range(), |n| n.text_range());
            let message = match self.container {
                Some(_) => {
                    format!("{flow_name} holds nodes but no start node: add `start S {{ => first; }}` among them")
                }
                None => format!("{flow_name} has no start node: add `start S {{ => first; }}`"),
            };
            ctx.sink.error(DiagnosticCode::MissingStartNode, range, message);
        }
        for &extra in starts.iter().skip(1) {
            let extra = &nodes[extra];
            let range = extra.name().map_or_else(|| extra.syntax().text_range(), |n| n.syntax().text_range());
            ctx.sink.error(
                DiagnosticCode::DuplicateStartNode,
                range,
                format!("{flow_name} has more than one start node"),
            );
        }
    }
}

/// Every `checked` node is reached from a start node, and reaches a final node.
fn reachability(ctx: &mut Ctx, nodes: &[ast::ActivityNode], checked: &[bool], starts: &[usize], edges: &[Vec<usize>]) {
    if starts.is_empty() {
        return;
    }
    let reachable = reach(starts.iter().copied(), edges);
    let mut reverse: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
    for (source, targets) in edges.iter().enumerate() {
        for &target in targets {
            reverse[target].push(source);
        }
    }
    let finals = (0..nodes.len()).filter(|&i| nodes[i].kind() == ast::NodeKind::Final);
    let reaches_final = reach(finals, &reverse);
    for (i, node) in nodes.iter().enumerate().filter(|&(i, _)| checked[i]) {
        let Some(name) = node.name() else { continue };
        if !reachable[i] {
            ctx.sink.warn(
                DiagnosticCode::UnreachableNode,
                name.syntax().text_range(),
                format!("node `{}` is never reached from the start node", name.text()),
            );
        } else if !reaches_final[i] {
            ctx.sink.warn(
                DiagnosticCode::NoPathToFinal,
                name.syntax().text_range(),
                format!("no path leads from node `{}` to a final node", name.text()),
            );
        }
    }
}

/// A final node has no way out; a decision chooses by guards.
fn node_transitions(ctx: &mut Ctx, node: &ast::ActivityNode, name: &str, nested: bool) {
    match node.kind() {
        ast::NodeKind::Final => {
            let ends = if nested { "its container's flow" } else { "the activity" };
            for transition in node.transitions() {
                ctx.sink.error(
                    DiagnosticCode::InvalidTransition,
                    transition.syntax().text_range(),
                    format!("the final node `{name}` ends {ends}: no transition leaves it"),
                );
            }
        }
        ast::NodeKind::Decision => decision_guards(ctx, node, name),
        _ => {}
    }
}

/// A decision chooses by guards: at least one, and one `[]` (otherwise) at most.
fn decision_guards(ctx: &mut Ctx, node: &ast::ActivityNode, name: &str) {
    let guarded = node.transitions().any(|t| t.guard().is_some_and(|g| g.condition().is_some()));
    if !guarded {
        let range = node.name().map_or_else(|| node.syntax().text_range(), |n| n.syntax().text_range());
        ctx.sink.error(
            DiagnosticCode::UnguardedDecision,
            range,
            format!(
                "decision `{name}` has no guarded transition: guard them (`[condition] => node;`, `[] => otherwise;`)"
            ),
        );
    }
    let otherwise = node.transitions().filter_map(|t| t.guard()).filter(|g| g.condition().is_none());
    for extra in otherwise.skip(1) {
        ctx.sink.error(
            DiagnosticCode::UnguardedDecision,
            extra.syntax().text_range(),
            format!("decision `{name}` has a second `[]` transition: only one is taken otherwise — guard this one or remove it"),
        );
    }
}

/// A fork starts several flows and a join waits for several: one outgoing transition out of a
/// fork, or one incoming into a join, is a mistake.
fn forks_and_joins_of_one_flow(ctx: &mut Ctx, nodes: &[ast::ActivityNode], edges: &[Vec<usize>]) {
    let mut incoming = vec![0usize; nodes.len()];
    edges.iter().flatten().for_each(|&target| incoming[target] += 1);
    for (i, node) in nodes.iter().enumerate() {
        let message = match node.kind() {
            ast::NodeKind::Join if incoming[i] == 1 => {
                "has one incoming transition: a join waits for several flows (those a fork starts)"
            }
            ast::NodeKind::Fork if edges[i].len() == 1 => {
                "has one outgoing transition: a fork starts several flows (an action passes one on)"
            }
            _ => continue,
        };
        let Some(name) = node.name() else { continue };
        let what = if node.kind() == ast::NodeKind::Join { "join" } else { "fork" };
        ctx.sink.warn(
            DiagnosticCode::ForkOrJoinOfOneFlow,
            name.syntax().text_range(),
            format!("{what} `{}` {message}", name.text()),
        );
    }
}

/// A transition passes the target's parameters, after the work size of a calc node
/// (3 dimensions) or the ranges of a calcRange node (global then local range: 2, 4 or 6
/// values for 1, 2 or 3 dimensions; Listing 32 passes 4).
fn transition_arity(ctx: &mut Ctx, transition: &ast::Transition, target: &ast::NameRef, node: &ast::ActivityNode) {
    // A transition without arguments to a node with parameters takes them from the flow.
    if transition.arg_list().is_none() && !matches!(node.kind(), ast::NodeKind::Calc | ast::NodeKind::CalcRange) {
        return;
    }
    let params = node.params().count();
    let given = transition.args().count();
    let (allowed, what): (Vec<usize>, &str) = match node.kind() {
        ast::NodeKind::Calc => (vec![params + 3], " (3 work-size dimensions first)"),
        ast::NodeKind::CalcRange => {
            (vec![params + 2, params + 4, params + 6], " (global and local range first: 2, 4 or 6 values)")
        }
        _ => (vec![params], ""),
    };
    let expected = *allowed.last().unwrap_or(&params);
    if !allowed.contains(&given) {
        let range = transition.arg_list().map_or_else(|| target.syntax().text_range(), |a| a.syntax().text_range());
        ctx.sink.error(
            DiagnosticCode::TransitionArity,
            range,
            format!("node `{}` takes {}{what}, {given} given", target.text(), arguments(expected)),
        );
    }
}

/// The nodes reached from `from` along `edges`, by index.
fn reach(from: impl Iterator<Item = usize>, edges: &[Vec<usize>]) -> Vec<bool> {
    let mut seen = vec![false; edges.len()];
    let mut stack: Vec<usize> = from.collect();
    while let Some(node) = stack.pop() {
        if !std::mem::replace(&mut seen[node], true) {
            stack.extend(&edges[node]);
        }
    }
    seen
}
