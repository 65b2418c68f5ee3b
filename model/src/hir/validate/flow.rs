//! Control flow of an activity diagram: one start node, transitions to nodes that exist with the
//! arguments their targets take (never into the start node, never out of a final one), guarded
//! transitions out of decisions, joins of several flows, every node reachable from the start,
//! and a final node reachable from every node.

use std::collections::{HashMap, HashSet, VecDeque};

use super::{Ctx, DiagnosticCode};
use crate::{
    ast::{self, AstNode, HasName},
    hir::{diagnostics::arguments, spelling::closest},
};

/// Start nodes, transition targets and arities, reachability and paths to a final node.
pub(super) fn check(ctx: &mut Ctx, diagram: &ast::ActivityDiagram, nodes: &[ast::ActivityNode]) {
    let by_name: HashMap<String, &ast::ActivityNode> =
        nodes.iter().filter_map(|n| Some((n.name()?.text(), n))).rev().collect();
    let starts: Vec<&ast::ActivityNode> = nodes.iter().filter(|n| n.kind() == ast::NodeKind::Start).collect();
    let diagram_name = diagram.name().map(|n| n.text()).unwrap_or_default();
    let header_range = diagram.name().map_or_else(|| diagram.syntax().text_range(), |n| n.syntax().text_range());
    if starts.is_empty() && !nodes.is_empty() {
        ctx.sink.error(
            DiagnosticCode::MissingStartNode,
            header_range,
            format!("activity diagram `{diagram_name}` has no start node: add `start S {{ => first; }}`"),
        );
    }
    for extra in starts.iter().skip(1) {
        let range = extra.name().map_or_else(|| extra.syntax().text_range(), |n| n.syntax().text_range());
        ctx.sink.error(
            DiagnosticCode::DuplicateStartNode,
            range,
            format!("activity diagram `{diagram_name}` has more than one start node"),
        );
    }
    let mut edges: HashMap<String, Vec<String>> = HashMap::new();
    for node in nodes {
        let Some(source) = node.name().map(|n| n.text()) else { continue };
        for transition in node.transitions() {
            let Some(target) = transition.target() else { continue };
            let target_name = target.text();
            let Some(target_node) = by_name.get(&target_name) else {
                let mut names: Vec<&str> = by_name.keys().map(String::as_str).collect();
                names.sort_unstable();
                ctx.sink.error_with_suggestion(
                    DiagnosticCode::UnresolvedTransitionTarget,
                    target.syntax().text_range(),
                    format!("no node `{target_name}` in activity diagram `{diagram_name}`"),
                    closest(&target_name, names),
                );
                continue;
            };
            edges.entry(source.clone()).or_default().push(target_name.clone());
            transition_arity(ctx, &transition, &target, target_node);
            if target_node.kind() == ast::NodeKind::Start {
                ctx.sink.error(
                    DiagnosticCode::InvalidTransition,
                    target.syntax().text_range(),
                    format!("no transition enters the start node `{target_name}`: it only begins the activity"),
                );
            }
        }
        node_transitions(ctx, node, &source);
    }
    joins_of_one_flow(ctx, nodes, &edges);
    // Reachability from the start node(s).
    let reachable = reach(starts.iter().filter_map(|s| s.name().map(|n| n.text())), &edges);
    if !starts.is_empty() {
        for node in nodes {
            let Some(name) = node.name() else { continue };
            if !reachable.contains(&name.text()) {
                ctx.sink.warn(
                    DiagnosticCode::UnreachableNode,
                    name.syntax().text_range(),
                    format!("node `{}` is never reached from the start node", name.text()),
                );
            }
        }
    }
    // A final node must be reachable from every reachable node.
    let finals: Vec<String> =
        nodes.iter().filter(|n| n.kind() == ast::NodeKind::Final).filter_map(|n| n.name().map(|n| n.text())).collect();
    let mut reverse: HashMap<String, Vec<String>> = HashMap::new();
    for (source, targets) in &edges {
        for target in targets {
            reverse.entry(target.clone()).or_default().push(source.clone());
        }
    }
    let reaches_final = reach(finals.iter().cloned(), &reverse);
    for node in nodes {
        let Some(name) = node.name() else { continue };
        if reachable.contains(&name.text()) && !reaches_final.contains(&name.text()) {
            ctx.sink.warn(
                DiagnosticCode::NoPathToFinal,
                name.syntax().text_range(),
                format!("no path leads from node `{}` to a final node", name.text()),
            );
        }
    }
}

/// A final node has no way out; a decision chooses by guards.
fn node_transitions(ctx: &mut Ctx, node: &ast::ActivityNode, name: &str) {
    match node.kind() {
        ast::NodeKind::Final => {
            for transition in node.transitions() {
                ctx.sink.error(
                    DiagnosticCode::InvalidTransition,
                    transition.syntax().text_range(),
                    format!("the final node `{name}` ends the activity: no transition leaves it"),
                );
            }
        }
        ast::NodeKind::Decision => {
            let guarded = node.transitions().any(|t| t.guard().is_some_and(|g| g.condition().is_some()));
            if !guarded {
                let range = node.name().map_or_else(|| node.syntax().text_range(), |n| n.syntax().text_range());
                ctx.sink.error(
                    DiagnosticCode::UnguardedDecision,
                    range,
                    format!("decision `{name}` has no guarded transition: guard them (`[condition] => node;`, `[] => otherwise;`)"),
                );
            }
        }
        _ => {}
    }
}

/// A join waits for the flows a fork started: one incoming transition is a mistake.
fn joins_of_one_flow(ctx: &mut Ctx, nodes: &[ast::ActivityNode], edges: &HashMap<String, Vec<String>>) {
    for join in nodes.iter().filter(|n| n.kind() == ast::NodeKind::Join) {
        let Some(name) = join.name() else { continue };
        let incoming = edges.values().flatten().filter(|target| **target == name.text()).count();
        if incoming == 1 {
            ctx.sink.warn(
                DiagnosticCode::JoinOfOneFlow,
                name.syntax().text_range(),
                format!(
                    "join `{}` has one incoming transition: a join waits for several flows (those a fork starts)",
                    name.text()
                ),
            );
        }
    }
}

/// A transition passes the target's parameters, after the work size of a calc node
/// (3 dimensions) or the ranges of a calcRange node (global then local range: 2, 4 or 6
/// values for 1, 2 or 3 dimensions; Listing 32 passes 4).
fn transition_arity(ctx: &mut Ctx, transition: &ast::Transition, target: &ast::NameRef, node: &ast::ActivityNode) {
    let params = node.params().count();
    let given = transition.args().count();
    // A transition without arguments to a node with parameters takes them from the flow.
    if transition.arg_list().is_none() && !matches!(node.kind(), ast::NodeKind::Calc | ast::NodeKind::CalcRange) {
        return;
    }
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

fn reach(from: impl Iterator<Item = String>, edges: &HashMap<String, Vec<String>>) -> HashSet<String> {
    let mut seen: HashSet<String> = HashSet::new();
    let mut queue: VecDeque<String> = from.collect();
    while let Some(node) = queue.pop_front() {
        if seen.insert(node.clone()) {
            if let Some(next) = edges.get(&node) {
                queue.extend(next.iter().cloned());
            }
        }
    }
    seen
}
