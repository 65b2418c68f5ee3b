//! Component-instance diagrams (chapter 11.3.4): instances of components with field values of
//! the fields' types, port instances of the component's ports, and bindings that a connection of
//! the component diagram allows.

use super::{names, Ctx, DiagnosticCode, Scope};
use crate::{
    ast::{self, AstNode, HasEnds, HasName},
    hir::{
        definitions::{DefKind, Definition},
        infer::InferenceCtx,
        instances::{BindingEnd, UnresolvedEnd},
        items::PortItem,
        spelling::closest,
    },
};

pub(super) fn check(ctx: &mut Ctx, scope: &Scope, diagram: &ast::ComponentInstanceDiagram) {
    names::duplicates(ctx, diagram.instances().filter_map(|i| i.name()), "instance");
    for instance in diagram.instances() {
        if instance.name().is_none() {
            continue;
        }
        if let Some(path) = instance.component() {
            instance_component(ctx, scope, &instance, &path);
        }
        names::duplicates(ctx, instance.port_instances().filter_map(|p| p.name()), "port instance");
        let components = ctx.sema.instance(&instance).components;
        for port_instance in instance.port_instances() {
            let (Some(_), Some(port)) = (port_instance.name(), port_instance.port()) else { continue };
            let Some(first) = components.first() else { continue };
            match components.iter().flat_map(|info| &info.item.ports).find(|p| p.name == port.text()) {
                Some(declared) => connector_instances(ctx, scope, &port_instance, declared),
                None => ctx.sink.error(
                    DiagnosticCode::UnresolvedConnector,
                    port.syntax().text_range(),
                    format!("component `{}` has no port `{}`", first.item.class, port.text()),
                ),
            }
        }
    }
    // Bindings: `[source portInstance.connector ==> target instance.portInstance.connector]`,
    // allowed only where the component diagram connects the two ports' connectors.
    let instances = ctx.sema.instances(diagram);
    for instance in diagram.instances() {
        let Some(owner) = instance.name().map(|n| n.text()) else { continue };
        for binding in instance.bindings() {
            let ends: Vec<Option<BindingEnd>> = [binding.source(), binding.target()]
                .into_iter()
                .flatten()
                .map(|end| match instances.binding_end(&owner, &end) {
                    Ok(found) => Some(found),
                    Err(error) => {
                        let message = match error {
                            UnresolvedEnd::Malformed => {
                                "a binding end is `portInstance.connector` or `instance.portInstance.connector`"
                                    .to_string()
                            }
                            UnresolvedEnd::NoInstance(name) => format!("no instance `{name}` in this diagram"),
                            UnresolvedEnd::NoPortInstance { instance, port_instance } => {
                                format!("instance `{instance}` has no port instance `{port_instance}`")
                            }
                            UnresolvedEnd::NoConnector { port_instance, connector, known } => {
                                let segment = end
                                    .segments()
                                    .last()
                                    .map_or(end.syntax().text_range(), |s| s.syntax().text_range());
                                ctx.sink.error_with_suggestion(
                                    DiagnosticCode::UnresolvedConnector,
                                    segment,
                                    format!(
                                        "port instance `{port_instance}` has no connector `{connector}` (it has {})",
                                        known.join(", ")
                                    ),
                                    closest(&connector, known.iter().map(String::as_str)),
                                );
                                return None;
                            }
                        };
                        ctx.sink.error(DiagnosticCode::UnresolvedConnector, end.syntax().text_range(), message);
                        None
                    }
                })
                .collect();
            if let [Some(source), Some(target)] = ends.as_slice() {
                if !instances.connects(source, target) {
                    ctx.sink.error(
                        DiagnosticCode::BindingNotAllowed,
                        binding.syntax().text_range(),
                        format!(
                            "no connection in the component diagram joins `{}.{}` and `{}.{}`",
                            source.port, source.connector, target.port, target.connector
                        ),
                    );
                }
            }
        }
    }
}

/// The connectors of a port instance instantiate the port's (Sec. 11.3.4; their names are the
/// instance's own): each matches a connector of the port by role word and interface, and gives
/// values only to the interface's fields.
fn connector_instances(ctx: &mut Ctx, scope: &Scope, port_instance: &ast::PortInstance, port: &PortItem) {
    let simple = |path: &str| path.rsplit('.').next().unwrap_or(path).to_string();
    let offered: Vec<String> =
        port.connectors.iter().map(|c| format!("{} {} : {}", c.role.keyword(), c.name, c.interface)).collect();
    for connector in port_instance.connectors() {
        let (Some(name), Some(role), Some(interface)) = (connector.name(), connector.role(), connector.interface())
        else {
            continue;
        };
        let same_interface: Vec<_> =
            port.connectors.iter().filter(|c| simple(&c.interface) == simple(&interface.text())).collect();
        if same_interface.is_empty() {
            ctx.sink.error(
                DiagnosticCode::InvalidConnectorInterface,
                interface.syntax().text_range(),
                format!(
                    "port `{}` has no connector of interface `{}` (it has {})",
                    port.name,
                    interface.text(),
                    offered.join(", ")
                ),
            );
            continue;
        }
        if !same_interface.iter().any(|c| c.role == role) {
            let role_word = connector.provider_token().or_else(|| connector.processor_token());
            ctx.sink.error_with_replacement(
                DiagnosticCode::InvalidConnectorInterface,
                role_word.map_or_else(|| name.syntax().text_range(), |t| t.text_range()),
                format!(
                    "port `{}` connects `{}` as a {}, not a {}: write `{} {} = …`",
                    port.name,
                    interface.text(),
                    same_interface[0].role.keyword(),
                    role.keyword(),
                    same_interface[0].role.keyword(),
                    name.text()
                ),
                same_interface[0].role.keyword(),
            );
        }
        let Some(def) = ctx.sema.resolve(scope, &interface.text()) else { continue };
        field_values(ctx, scope, def, connector.field_values(), "interface");
    }
}

/// The component an instance instantiates exists, is a component, and its field values are
/// fields of the class (inherited ones too) of matching types.
fn instance_component(ctx: &mut Ctx, scope: &Scope, instance: &ast::ComponentInstance, path: &ast::Path) {
    let text = path.text();
    let range = path.syntax().text_range();
    let Some(def) = ctx.sema.resolve(scope, &text) else {
        let suggestion = super::types::misspelt_type(ctx, scope, &text);
        let message = format!("unknown component `{text}`");
        ctx.sink.error_with_suggestion(DiagnosticCode::InvalidComponent, range, message, suggestion.as_deref());
        return;
    };
    if ctx.sema.components(&def.fqn).is_empty() {
        ctx.sink.error(
            DiagnosticCode::InvalidComponent,
            range,
            format!("`{}` is not a component of any component diagram", def.fqn),
        );
        return;
    }
    let DefKind::Type(item) = &def.kind else { return };
    if let Some(why) = item.why_not_instantiable() {
        ctx.sink.error(DiagnosticCode::AbstractInstance, range, format!("`{}` is {why}", def.fqn));
    }
    field_values(ctx, scope, def, instance.field_values(), "component class");
}

/// Values given to the fields of `def` — a component's class (`Camera1 instantiates
/// Camera(width = 640)`) or a connector's interface (`provider P = I(bufferSize = 4)`) — each
/// once (E0205), to a field it has, inherited ones too (E0220), not `const` (E0233), of a value
/// that fits the field (E0225). `what` names `def`'s kind.
fn field_values(
    ctx: &mut Ctx,
    scope: &Scope,
    def: &Definition,
    values: impl Iterator<Item = ast::NamedArg>,
    what: &str,
) {
    let values: Vec<ast::NamedArg> = values.collect();
    let given: Vec<String> = values.iter().filter_map(|v| v.name()).map(|n| n.text()).collect();
    let mut seen = std::collections::HashSet::new();
    for value in values {
        let Some(field) = value.name() else { continue };
        let name = field.text();
        let range = field.syntax().text_range();
        if !seen.insert(name.clone()) {
            let message = format!("field `{name}` is given a value more than once");
            ctx.sink.error(DiagnosticCode::DuplicateName, range, message);
            continue;
        }
        // The field may be inherited; its type is resolved where it is declared.
        let found = ctx.sema.find_member(&def.fqn, &|ty| ty.fields.iter().find(|f| f.name == name).cloned());
        let Some((declaring, declared)) = found else {
            // "Did you mean" names a field not given a value already.
            let fields = ctx.sema.member_names(&def.fqn, true);
            let free = fields.iter().filter(|f| !given.contains(f)).map(String::as_str);
            ctx.sink.error_with_suggestion(
                DiagnosticCode::UnknownInstanceField,
                range,
                format!("{what} `{}` has no field `{name}`", def.fqn),
                closest(&name, free),
            );
            continue;
        };
        if declared.qualifiers.iter().any(|q| q == "const") {
            let message = format!("field `{name}` of `{}` is `const`: an instance cannot give it a value", def.fqn);
            ctx.sink.error(DiagnosticCode::AssignToConst, range, message);
            continue;
        }
        let Some(expr) = value.value() else { continue };
        let field_ty = ctx.sema.ty(&declared.ty, &Scope::of(declaring));
        let sema = ctx.sema;
        let value_ty = InferenceCtx::new(sema, &mut ctx.sink, scope.clone(), None).infer(&expr);
        if !value_ty.assignable_to(&field_ty, &mut |a, b| sema.is_subtype(a, b)) {
            ctx.sink.error(
                DiagnosticCode::TypeMismatch,
                expr.syntax().text_range(),
                format!("field `{name}` of `{}` has type `{field_ty}`, but the value is `{value_ty}`", def.fqn),
            );
        }
    }
}
