//! The pipeline plan of a component-instance diagram (chapter 11.3.4): its instances as stages
//! (component class, kind, parameters resolved and range-checked, ports), the bindings between
//! them normalised to provider → processor with the receiving port's `async`/`buffered` mode,
//! and the stages in the order data flows (a buffered binding carries the previous frame's
//! data, so it may close a loop). What a runtime needs to run the diagram, and the problems
//! that would stop it, before anything runs: an unbound processor port of a filter or sink
//! (E0401), a cycle without a buffered port (E0402), a parameter out of range or without a
//! value (E0403). What names nothing is left out: validation reports it.

mod params;

use std::collections::HashMap;

use super::{
    definitions::{DefKind, Definition, Fqn},
    diagnostics::{Diagnostic, DiagnosticCode, Diagnostics},
    items::{ClassKind, ConnectorRole, PortItem},
    scope::Scope,
    semantics::Semantics,
};
use crate::{
    ast::{self, AstNode, HasEnds, HasName},
    db::{Db, SourceFile, Workspace},
    syntax::{SyntaxKind, TextRange},
};

/// A component-instance diagram as a runtime sees it.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PipelinePlan {
    /// The diagram's fully qualified name.
    pub diagram: String,
    pub file: SourceFile,
    /// The range of the diagram's name.
    pub name_range: TextRange,
    /// The stages, producers before their consumers (declaration order where free).
    pub stages: Vec<Stage>,
    pub bindings: Vec<PlanBinding>,
    /// What would stop it from running, all in `file`.
    pub diagnostics: Vec<Diagnostic>,
}

/// One instance of a component.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Stage {
    pub instance: String,
    /// The range of the instance's name.
    pub range: TextRange,
    /// The component class's fully qualified name (`ToF.Demodulation`).
    pub class: String,
    pub kind: ClassKind,
    /// The types the class derives from, nearest first (a workspace component may extend one of
    /// the library's and run as it).
    pub bases: Vec<String>,
    /// The activity diagrams its own `process` method calls (`call behavior X;`), in order.
    pub behavior: Vec<BehaviorCall>,
    pub params: Vec<Param>,
    /// The component's ports, as its component diagram declares them.
    pub ports: Vec<StagePort>,
}

impl Stage {
    /// The value of parameter `name`.
    pub fn param(&self, name: &str) -> Option<&Value> {
        self.params.iter().find(|p| p.name == name).map(|p| &p.value)
    }
}

/// A `call behavior` in a component's `process`.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct BehaviorCall {
    /// The activity diagram's fully qualified name.
    pub diagram: String,
    /// Whether it is a statement of its own, without arguments (the diagram takes its
    /// parameters from the caller), outside any branch or loop: what a runtime can run.
    pub plain: bool,
}

/// A port of a stage's component and its connectors.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct StagePort {
    pub name: String,
    pub is_async: bool,
    pub is_buffered: bool,
    pub connectors: Vec<StageConnector>,
}

#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct StageConnector {
    pub name: String,
    pub role: ConnectorRole,
    /// The interface's fully qualified name (as written where it does not resolve).
    pub interface: String,
    /// What flows through it: the type its method passes and the types that type derives
    /// from, nearest first (empty where the model cannot tell).
    pub carries: Vec<String>,
}

/// A field of the component class and the value the stage runs with.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Param {
    pub name: String,
    pub value: Value,
    /// Where the instance writes it (`None`: the field's default).
    pub written: Option<TextRange>,
    /// Whether it names a file the component reads (`ToF.InputFile`).
    pub input_file: bool,
    /// What an editor's control of it offers.
    pub control: Control,
}

/// What a parameter's control in an editor offers, from its field's declaration.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct Control {
    /// The field's type as declared (`int`, `float`, `bool`, `string`, `Scene`).
    pub ty: String,
    /// Its `ToF.Range(min, max)`.
    pub range: Option<(Number, Number)>,
    /// Its `ToF.Odd`: only odd values.
    pub odd: bool,
    /// An enum's members as written in a model (`Scene.Sphere`).
    pub choices: Vec<String>,
}

/// A constant parameter value.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Value {
    Int(i64),
    Float(Number),
    Bool(bool),
    Text(String),
    /// An enum member, by name.
    Enum(String),
    /// No value written and no default (C++ default-initialises such a field).
    Missing,
}

impl Value {
    /// The value as a number, if it is one.
    pub fn number(&self) -> Option<f64> {
        match self {
            Value::Int(v) => Some(*v as f64),
            Value::Float(v) => Some(v.get()),
            _ => None,
        }
    }
}

/// A floating-point number compared by its bits (so a plan can be compared and hashed).
#[derive(Debug, Clone, Copy)]
pub struct Number(f64);

impl Number {
    pub fn get(self) -> f64 {
        self.0
    }
}

impl From<f64> for Number {
    fn from(value: f64) -> Number {
        Number(value)
    }
}

impl PartialEq for Number {
    fn eq(&self, other: &Number) -> bool {
        self.0.to_bits() == other.0.to_bits()
    }
}

impl Eq for Number {}

impl std::hash::Hash for Number {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.0.to_bits().hash(state);
    }
}

/// A binding, from the provider's connector to the processor's.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PlanBinding {
    pub provider: PlanEnd,
    pub processor: PlanEnd,
    pub range: TextRange,
    /// The receiving port's mode (Sec. 11.3.3): `async` does not block the producer,
    /// `buffered` queues up to `buffer_size` items and delivers them a frame later.
    pub is_async: bool,
    pub is_buffered: bool,
    pub buffer_size: usize,
}

/// A stage's connector: the component's port and connector names.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct PlanEnd {
    pub stage: usize,
    /// The component's port (`RawOut`).
    pub port: String,
    /// The instance's port instance of it (`Out`), as the binding names it.
    pub port_instance: String,
    pub connector: String,
}

/// The plan of the component-instance diagram `diagram` (a fully qualified name); `None` if no
/// such diagram exists.
#[salsa::tracked(returns(ref))]
pub fn pipeline_plan<'db>(db: &'db dyn Db, workspace: Workspace, diagram: Fqn<'db>) -> Option<PipelinePlan> {
    let sema = Semantics::new(db, workspace);
    let def = sema.lookup(diagram.text(db)).iter().find(|d| d.kind == DefKind::ComponentInstanceDiagram)?;
    let (node, name_range) = sema.declaration(def)?;
    let syntax = ast::ComponentInstanceDiagram::cast(node)?;
    let mut sink = Diagnostics::default();
    let (stages, nodes) = stages(&sema, &syntax, &mut sink);
    let bindings = bindings(&sema, &syntax, &stages, &nodes);
    // An instance of an unknown component, or a binding whose end is unknown, is reported
    // where it is written (E0215, E0217, …); what it would have fed is told once it is fixed.
    let names: std::collections::HashSet<String> = syntax.instances().filter_map(|i| Some(i.name()?.text())).collect();
    let written: usize = nodes.iter().map(|n| n.bindings().count()).sum();
    if stages.len() == names.len() && bindings.len() == written {
        unbound_processors(&stages, &bindings, &mut sink);
    }
    let order = data_order(&stages, &bindings, &mut sink);
    let (stages, bindings) = reorder(stages, bindings, &order);
    Some(PipelinePlan {
        diagram: def.fqn.clone(),
        file: def.file,
        name_range,
        stages,
        bindings,
        diagnostics: sink.into_vec(),
    })
}

/// A stage for each instance whose component resolves (the first of a duplicated name), with
/// its syntax node.
fn stages(
    sema: &Semantics,
    diagram: &ast::ComponentInstanceDiagram,
    sink: &mut Diagnostics,
) -> (Vec<Stage>, Vec<ast::ComponentInstance>) {
    let (mut stages, mut nodes): (Vec<Stage>, Vec<ast::ComponentInstance>) = (Vec::new(), Vec::new());
    for instance in diagram.instances() {
        let Some(name) = instance.name() else { continue };
        if stages.iter().any(|s| s.instance == name.text()) {
            continue;
        }
        let resolved = sema.instance(&instance);
        // A class can be a component of several component diagrams: the one whose ports the
        // instance's port instances name.
        let named: Vec<String> = instance.port_instances().filter_map(|p| Some(p.port()?.text())).collect();
        let component = resolved
            .components
            .iter()
            .find(|c| named.iter().all(|port| c.item.ports.iter().any(|p| &p.name == port)))
            .or(resolved.components.first());
        let (Some(class), Some(component)) = (resolved.class, component) else { continue };
        let scope = Scope::at(instance.syntax());
        let written = params::written_values(instance.field_values(), &scope);
        let params = params::parameters(sema, class, &written, name.syntax().text_range(), sink);
        let ports = component.item.ports.iter().map(|port| stage_port(sema, port)).collect();
        stages.push(Stage {
            instance: name.text(),
            range: name.syntax().text_range(),
            class: class.fqn.clone(),
            kind: component.item.kind,
            bases: sema.type_and_bases(class).iter().skip(1).map(|d| d.fqn.clone()).collect(),
            behavior: behavior(sema, class),
            params,
            ports,
        });
        nodes.push(instance);
    }
    (stages, nodes)
}

fn stage_port(sema: &Semantics, port: &PortItem) -> StagePort {
    let connectors = port
        .connectors
        .iter()
        .map(|c| StageConnector {
            name: c.name.clone(),
            role: c.role,
            interface: sema
                .resolve(&Scope::default(), &c.interface)
                .map_or_else(|| c.interface.clone(), |d| d.fqn.clone()),
            carries: carried(sema, &c.interface),
        })
        .collect();
    StagePort { name: port.name.clone(), is_async: port.is_async, is_buffered: port.is_buffered, connectors }
}

/// The activity diagrams a class's own `process` method calls by `call behavior`, in order.
fn behavior(sema: &Semantics, class: &Definition) -> Vec<BehaviorCall> {
    let Some(process) = sema.member_declaration(class, "process") else { return Vec::new() };
    let method = process.syntax().clone();
    process
        .syntax()
        .descendants()
        .filter_map(ast::CallBehaviorExpr::cast)
        .filter_map(|call| {
            let path = call.behavior()?;
            let def = sema.resolve(&Scope::at(call.syntax()), &path.text())?;
            let statement = call.syntax().parent().filter(|p| p.kind() == SyntaxKind::EXPR_STMT);
            let in_body = statement
                .and_then(|s| s.parent())
                .filter(|block| block.kind() == SyntaxKind::BLOCK)
                .and_then(|block| block.parent())
                .is_some_and(|owner| owner == method);
            let plain = call.arg_list().is_none() && in_body;
            matches!(def.kind, DefKind::Activity(_)).then(|| BehaviorCall { diagram: def.fqn.clone(), plain })
        })
        .collect()
}

/// The type an interface's method passes (its first parameter's) and that type's bases.
fn carried(sema: &Semantics, interface: &str) -> Vec<String> {
    let Some(def) = sema.resolve(&Scope::default(), interface) else { return Vec::new() };
    let DefKind::Type(ty) = &def.kind else { return Vec::new() };
    let passed = ty.methods.iter().find_map(|m| m.params.first()).and_then(|p| p.ty.path.clone());
    let Some(passed) = passed.and_then(|path| sema.resolve(&Scope::of(def), &path)) else { return Vec::new() };
    sema.type_and_bases(passed).iter().map(|d| d.fqn.clone()).collect()
}

/// The bindings whose ends both resolve to stages' connectors of opposite roles.
fn bindings(
    sema: &Semantics,
    diagram: &ast::ComponentInstanceDiagram,
    stages: &[Stage],
    nodes: &[ast::ComponentInstance],
) -> Vec<PlanBinding> {
    let instances = sema.instances(diagram);
    let index: HashMap<&str, usize> = stages.iter().enumerate().map(|(i, s)| (s.instance.as_str(), i)).collect();
    let mut out = Vec::new();
    for (owner, node) in stages.iter().zip(nodes) {
        for binding in node.bindings() {
            let ends: Vec<_> = [binding.source(), binding.target()]
                .into_iter()
                .flatten()
                .filter_map(|path| instances.binding_end(&owner.instance, &path).ok())
                .filter_map(|end| {
                    let stage = *index.get(end.instance.as_str())?;
                    let port = stages[stage].ports.iter().find(|p| p.name == end.port)?;
                    let role = port.connectors.iter().find(|c| c.name == end.connector)?.role;
                    let port_instance = end.port_instance.clone();
                    Some((
                        PlanEnd { stage, port: end.port.clone(), port_instance, connector: end.connector.clone() },
                        role,
                        end,
                    ))
                })
                .collect();
            let [(a, a_role, a_end), (b, b_role, b_end)] = &ends[..] else { continue };
            let ((provider, _), (processor, processor_end)) = match (a_role, b_role) {
                (ConnectorRole::Provider, ConnectorRole::Processor) => ((a, a_end), (b, b_end)),
                (ConnectorRole::Processor, ConnectorRole::Provider) => ((b, b_end), (a, a_end)),
                _ => continue,
            };
            let port = stages[processor.stage].ports.iter().find(|p| p.name == processor.port).expect("found above");
            let buffer_size = nodes[processor.stage]
                .port_instances()
                .find(|pi| pi.name().is_some_and(|n| n.text() == processor_end.port_instance))
                .and_then(|pi| pi.connectors().find(|c| c.role() == Some(ConnectorRole::Processor)))
                .map_or(4, |c| params::buffer_size(sema, &Scope::at(c.syntax()), &c));
            out.push(PlanBinding {
                provider: provider.clone(),
                processor: processor.clone(),
                range: binding.syntax().text_range(),
                is_async: port.is_async,
                is_buffered: port.is_buffered,
                buffer_size,
            });
        }
    }
    out
}

/// A filter or a sink runs when data arrives (Sec. 11.4.1): each processor connector of a
/// filter needs a binding, or it never runs; a sink writes what arrives on each of its inputs
/// apart, so it needs one bound (a bag writer takes raw frames, depth images or clouds). A
/// warning: the diagram is valid GU-DSL, but cannot run. A diagram without any binding only
/// declares instances (Listing 23): not a pipeline yet.
fn unbound_processors(stages: &[Stage], bindings: &[PlanBinding], sink: &mut Diagnostics) {
    if bindings.is_empty() {
        return;
    }
    for (index, stage) in stages.iter().enumerate() {
        if !matches!(stage.kind, ClassKind::Filter | ClassKind::Sink) {
            continue;
        }
        let fed = |port: &str, connector: &str| {
            bindings
                .iter()
                .any(|b| b.processor.stage == index && b.processor.port == port && b.processor.connector == connector)
        };
        let processors = || {
            stage.ports.iter().flat_map(|port| {
                let connectors = port.connectors.iter().filter(|c| c.role == ConnectorRole::Processor);
                connectors.map(move |c| (port, c))
            })
        };
        if stage.kind == ClassKind::Sink && processors().any(|(port, c)| fed(&port.name, &c.name)) {
            continue;
        }
        for (port, connector) in processors() {
            if !fed(&port.name, &connector.name) {
                sink.warn(
                    DiagnosticCode::UnboundProcessor,
                    stage.range,
                    format!(
                        "`{}` receives nothing on `{}.{}`: bind a provider to it (a {} runs when data arrives)",
                        stage.instance,
                        port.name,
                        connector.name,
                        if stage.kind == ClassKind::Sink { "sink" } else { "filter" }
                    ),
                );
            }
        }
    }
}

/// The stages with producers before consumers along unbuffered bindings, declaration order
/// where free; stages on a cycle of unbuffered bindings are reported (E0402) and follow in
/// declaration order.
fn data_order(stages: &[Stage], bindings: &[PlanBinding], sink: &mut Diagnostics) -> Vec<usize> {
    let flowing: Vec<&PlanBinding> = bindings.iter().filter(|b| !b.is_buffered).collect();
    let mut waiting: Vec<usize> = vec![0; stages.len()];
    for b in &flowing {
        waiting[b.processor.stage] += 1;
    }
    let mut order = Vec::with_capacity(stages.len());
    let mut done = vec![false; stages.len()];
    while let Some(next) = (0..stages.len()).find(|&s| !done[s] && waiting[s] == 0) {
        done[next] = true;
        order.push(next);
        for b in flowing.iter().filter(|b| b.provider.stage == next) {
            waiting[b.processor.stage] -= 1;
        }
    }
    if order.len() < stages.len() {
        let cycle = find_cycle(&flowing, &done);
        let names: Vec<String> = cycle.iter().map(|&(s, _)| format!("`{}`", stages[s].instance)).collect();
        let closing = cycle.first().map_or(stages[0].range, |&(_, range)| range);
        sink.error(
            DiagnosticCode::PipelineCycle,
            closing,
            format!(
                "{} → {} form a cycle without a buffered port: data would wait for itself; bind into an \
                 `async buffered` port, which takes the previous frame's data",
                names.join(" → "),
                names.first().cloned().unwrap_or_default()
            ),
        );
        order.extend((0..stages.len()).filter(|&s| !done[s]));
    }
    order
}

/// A cycle among the stages not yet ordered, in the direction data flows: each stage with the
/// range of the binding that brings it data.
fn find_cycle(flowing: &[&PlanBinding], done: &[bool]) -> Vec<(usize, TextRange)> {
    let Some(start) = (0..done.len()).find(|&s| !done[s]) else { return Vec::new() };
    // Walk against the data: every stage left unordered waits for another unordered one.
    let mut path: Vec<(usize, TextRange)> = Vec::new();
    let mut at = start;
    loop {
        if let Some(position) = path.iter().position(|&(s, _)| s == at) {
            let mut cycle = path.split_off(position);
            cycle.reverse();
            return cycle;
        }
        let Some(edge) = flowing.iter().find(|b| b.processor.stage == at && !done[b.provider.stage]) else {
            return Vec::new();
        };
        path.push((at, edge.range));
        at = edge.provider.stage;
    }
}

/// Stages in `order`, binding ends renumbered.
fn reorder(stages: Vec<Stage>, mut bindings: Vec<PlanBinding>, order: &[usize]) -> (Vec<Stage>, Vec<PlanBinding>) {
    let mut position = vec![0; stages.len()];
    for (new, &old) in order.iter().enumerate() {
        position[old] = new;
    }
    let mut slots: Vec<Option<Stage>> = stages.into_iter().map(Some).collect();
    let stages = order.iter().map(|&old| slots[old].take().expect("each stage once")).collect();
    for b in &mut bindings {
        b.provider.stage = position[b.provider.stage];
        b.processor.stage = position[b.processor.stage];
    }
    (stages, bindings)
}
