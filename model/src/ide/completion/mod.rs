//! Completion that knows where the cursor is: node names after `=>`, qualified names after a
//! `.`, types in type positions, the owner class's members and the locals inside bodies,
//! interfaces after `:` in ports, fields in `instantiates X (`, and keyword snippets for the
//! constructs valid at that level.

use std::collections::{BTreeSet, HashSet};

use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    hir::{
        items::{ImportItem, InterfaceRole, TypeKind},
        DefKind, Definition, Scope, Semantics,
    },
    syntax::{SyntaxKind::*, SyntaxNode, SyntaxToken, TextSize},
};

/// What a completion item is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum CompletionKind {
    Keyword,
    Snippet,
    Type,
    Namespace,
    Node,
    Field,
    Method,
    Variable,
    Interface,
    EnumValue,
}

/// One proposal.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct CompletionItem {
    pub label: String,
    pub kind: CompletionKind,
    pub detail: Option<String>,
    /// Text to insert in LSP snippet syntax (`$1`, `${1:name}`), when it differs from the label.
    pub snippet: Option<String>,
    /// Declared outside what the cursor's scope sees (a type of another diagram that resolves
    /// by its unique simple name): listed after the names in scope.
    pub far: bool,
}

/// The proposals at a position; `incomplete` when a long list was cut to what is typed so far
/// (the editor asks again as the user types on).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Completions {
    pub items: Vec<CompletionItem>,
    pub incomplete: bool,
}

/// At most this many types of other diagrams are proposed; the names in scope always are.
const FAR_TYPES: usize = 100;

fn item(label: impl Into<String>, kind: CompletionKind, detail: Option<String>) -> CompletionItem {
    CompletionItem { label: label.into(), kind, detail, snippet: None, far: false }
}

fn snippet(label: &str, body: &str, detail: &str) -> CompletionItem {
    CompletionItem {
        label: label.to_string(),
        kind: CompletionKind::Snippet,
        detail: Some(detail.to_string()),
        snippet: Some(body.to_string()),
        far: false,
    }
}

const BUILTIN_TYPES: &[&str] = &[
    "bool",
    "byte",
    "char",
    "short",
    "int",
    "long",
    "float",
    "double",
    "real",
    "string",
    "void",
    "unsigned",
    "int2",
    "int4",
    "float2",
    "float3",
    "float4",
    "uchar4",
    "image2D_uc",
    "image2D_f",
    "image3D_f",
    "buffer2D_f4",
    "sampler_t",
];

/// The proposals at `offset`.
pub fn completions(db: &dyn Db, workspace: Workspace, file: SourceFile, offset: TextSize) -> Completions {
    let root = parse(db, file).syntax_node();
    let sema = Semantics::new(db, workspace);
    let previous = previous_token(&root, offset);
    let at = previous.as_ref().and_then(|t| t.parent()).unwrap_or_else(|| root.clone());
    // The identifier being typed, if the cursor is right after one.
    let typing_ident = previous.as_ref().filter(|t| t.kind() == IDENT && t.text_range().end() == offset);
    let before = match typing_ident {
        Some(ident) => ident.prev_token().and_then(|t| skip_trivia_back(&t)),
        None => previous.clone(),
    };
    let before_kind = before.as_ref().map(|t| t.kind());
    let typed = typing_ident.map_or("", |t| t.text());

    let mut items = Vec::new();
    // `=> |`: the nodes of this activity diagram.
    if before_kind == Some(FAT_ARROW) {
        if let Some(diagram) = at.ancestors().find_map(ast::ActivityDiagram::cast) {
            for node in diagram.syntax().descendants().filter_map(ast::ActivityNode::cast) {
                if let Some(name) = node.name() {
                    let detail = format!("{:?}", node.kind()).to_lowercase();
                    items.push(item(name.text(), CompletionKind::Node, Some(detail)));
                }
            }
        }
        return finish(items);
    }
    // Bindings and connections: port instances, ports and connectors.
    if let Some(link) = at.ancestors().find(|a| matches!(a.kind(), BINDING | CONNECTION)) {
        if matches!(before_kind, Some(SOURCE_KW | TARGET_KW | DOT)) {
            let prefix = if before_kind == Some(DOT) { before.as_ref().and_then(path_before_dot) } else { None };
            connector_candidates(&link, prefix.as_deref(), &mut items);
            return finish(items);
        }
    }
    // `receiver.|` in an expression: the fields and methods of the receiver's declared type.
    if before_kind == Some(DOT) && before.as_ref().and_then(|d| d.parent()).is_some_and(|p| p.kind() == MEMBER_EXPR) {
        let receiver = before.as_ref().and_then(|d| d.prev_token()).and_then(|t| skip_trivia_back(&t));
        if let Some(receiver) = receiver.filter(|r| r.kind() == IDENT) {
            if let Some(resolved) =
                super::navigation::type_of_name_at(db, workspace, file, receiver.text_range().start())
            {
                if let Some(def) = resolved.qualified.as_deref().and_then(|fqn| sema.definition(fqn)) {
                    type_members(&sema, def, &mut items);
                }
            }
        }
        if !items.is_empty() {
            return finish(items);
        }
        // Not a typed receiver: `Enum.Value`, `Diagram.Type` are qualified names (below).
    }
    // `A.B.|` in a qualified name: what the namespace contains.
    if before_kind == Some(DOT) {
        if let Some(prefix) = before.as_ref().and_then(path_before_dot) {
            let namespace = sema.resolve(&Scope::at(&at), &prefix).map(|d| d.fqn.clone()).unwrap_or(prefix.clone());
            let children: BTreeSet<(String, bool)> = sema
                .namespace_members(&namespace)
                .iter()
                .map(|(name, defs)| (name.clone(), matches!(defs[0].kind, DefKind::Type(_))))
                .collect();
            for (name, is_type) in children {
                let kind = if is_type { CompletionKind::Type } else { CompletionKind::Namespace };
                items.push(item(name, kind, Some(namespace.clone())));
            }
            // An enum's values.
            if let Some(DefKind::Type(ty)) = sema.definition(&namespace).map(|d| &d.kind) {
                for value in &ty.enum_values {
                    items.push(item(value.clone(), CompletionKind::EnumValue, Some(namespace.clone())));
                }
            }
            return finish(items);
        }
    }
    // `provider name : |` in a port: interfaces of that role.
    if before_kind == Some(COLON) && at.ancestors().any(|a| a.kind() == CONNECTOR || a.kind() == PORT) {
        let role = at.ancestors().find_map(ast::Connector::cast).and_then(|c| c.role());
        for defs in sema.def_map().definitions.values() {
            let def = &defs[0];
            if let DefKind::Type(ty) = &def.kind {
                let fits = matches!(
                    (ty.kind, role),
                    (TypeKind::Interface(InterfaceRole::Provider), Some(ast::ConnectorRole::Provider))
                        | (TypeKind::Interface(InterfaceRole::Processor), Some(ast::ConnectorRole::Processor))
                        | (TypeKind::Interface(_), None)
                );
                if fits {
                    items.push(item(def.fqn.clone(), CompletionKind::Interface, None));
                }
            }
        }
        return finish(items);
    }
    // `X instantiates T (|`: the component class's fields.
    if let Some(instance) = at.ancestors().find_map(ast::ComponentInstance::cast) {
        let in_args = at.ancestors().any(|a| a.kind() == NAMED_ARG_LIST);
        if in_args && matches!(before_kind, Some(L_PAREN | COMMA)) {
            if let Some(def) = instance.component().and_then(|p| sema.resolve(&Scope::at(&at), &p.text())) {
                if let DefKind::Type(ty) = &def.kind {
                    for field in &ty.fields {
                        let mut it = item(field.name.clone(), CompletionKind::Field, Some(def.fqn.clone()));
                        it.snippet = Some(format!("{} = $1", field.name));
                        items.push(it);
                    }
                }
            }
            return finish(items);
        }
    }
    // Type positions: after a visibility/qualifier, in a parameter list, after `var`, `new`, `as`,
    // `extends`, `implements`, `owner`, `instantiates`, `:` of an association.
    let type_position = matches!(
        before_kind,
        Some(
            PUBLIC_KW
                | PROTECTED_KW
                | PRIVATE_KW
                | VAR_KW
                | CONST_KW
                | REF_KW
                | NEW_KW
                | AS_KW
                | EXTENDS_KW
                | IMPLEMENTS_KW
                | UNSIGNED_KW
                | OWNER_KW
                | INSTANTIATES_KW
                | L_ANGLE
        )
    ) || (matches!(before_kind, Some(L_PAREN | COMMA))
        && at.ancestors().any(|a| a.kind() == PARAM_LIST))
        || at.ancestors().any(|a| a.kind() == TYPE_REF);
    if type_position {
        return with_types(&sema, &at, typed, items);
    }
    // Inside a node or method body: statements, locals, the owner's members.
    if let Some(body) = at.ancestors().find(|a| matches!(a.kind(), NODE_BODY | BLOCK)) {
        for keyword in ["var", "const", "if", "for", "loop", "do", "switch", "return", "call behavior", "new"] {
            items.push(item(keyword, CompletionKind::Keyword, None));
        }
        if body.kind() == NODE_BODY || body.ancestors().any(|a| a.kind() == NODE_BODY) {
            items.push(snippet("=> transition", "=> ${1:target};", "transition to a node"));
            items.push(snippet("[guard] => transition", "[${1:condition}] => ${2:target};", "guarded transition"));
        }
        locals_in_scope(&body, &mut items);
        if let Some(owner) = sema.owner_at(&at) {
            type_members(&sema, owner, &mut items);
        }
        return finish(items);
    }
    // Declaration levels: keyword snippets.
    let level = at.ancestors().find(|a| {
        matches!(
            a.kind(),
            CLASS_DIAGRAM | ACTIVITY_DIAGRAM | SWIMLANE | COMPONENT_DIAGRAM | COMPONENT_INSTANCE_DIAGRAM | MEMBER_LIST
        )
    });
    match level.as_ref().map(|l| l.kind()) {
        Some(CLASS_DIAGRAM) => {
            items.push(snippet("class", "public class ${1:Name}\n{\n\t$0\n}", "class declaration"));
            items.push(snippet("interface", "public interface ${1:Name}\n{\n\t$0\n}", "interface declaration"));
            items.push(snippet("provider interface", "public interface provider ${1:Name}\n{\n\tpublic void provide${2:Data}(${3});\n}", "output interface of a component"));
            items.push(snippet("processor interface", "public interface processor ${1:Name}\n{\n\tpublic void process${2:Data}(${3});\n}", "input interface of a component"));
            items.push(snippet("enum", "public enum ${1:Name} { ${2:A}, ${3:B} }", "enumeration"));
            items.push(snippet("attribute", "public attribute ${1:Name}\n{\n\tpublic ${2:string} ${3:value};\n}", "generator attribute"));
            for kind in ["source", "filter", "sink"] {
                items.push(snippet(kind, &format!("public {kind} ${{1:Name}}\n{{\n\tpublic bool process(ConstIObjectParametersPtr parameters);\n}}"), "component class"));
            }
            items.push(item("import", CompletionKind::Keyword, None));
        }
        Some(ACTIVITY_DIAGRAM) | Some(SWIMLANE) => {
            if level.as_ref().is_some_and(|l| l.kind() == ACTIVITY_DIAGRAM) {
                items.push(snippet("swimlane", "swimlane ${1:Lane}, owner ${2:Class}\n{\n\tstart S\n\t{\n\t\t=> ${3:first};\n\t}\n\t$0\n\tfinal done;\n}", "swimlane with start and final nodes"));
            }
            for (kind, body) in [
                ("start", "start ${1:S}\n{\n\t=> ${2:first};\n}"),
                ("action", "action ${1:name}(${2})\n{\n\t$0\n\t=> ${3:next};\n}"),
                ("decision", "decision ${1:name}\n{\n\t[${2:condition}] => ${3:yes};\n\t[] => ${4:no};\n}"),
                ("calc", "calc ${1:name}(${2})\n{\n\tcall ${3:Class}::${4:kernel}($5);\n\t=> ${6:next};\n}"),
                ("calcRange", "calcRange ${1:name}(${2})\n{\n\tcall ${3:Class}::${4:kernel}($5);\n\t=> ${6:next};\n}"),
                ("loop", "loop ${1:name}(var int ${2:i} = 0; $2 < ${3:n}; $2 = $2 + 1)\n{\n\t$0\n\t=> ${4:next};\n}"),
                ("loopWindow", "loopWindow ${1:name}(var int u = -${2:r}, var int v = -$2; u <= $2, v <= $2; u = u + 1, v = v + 1)\n{\n\t$0\n\t=> ${3:next};\n}"),
                ("fork", "fork ${1:name}\n{\n\t=> ${2:a};\n\t=> ${3:b};\n}"),
                ("join", "join ${1:name}\n{\n\t=> ${2:next};\n}"),
                ("final", "final ${1:done};"),
            ] {
                items.push(snippet(kind, body, &format!("{kind} node")));
            }
        }
        Some(MEMBER_LIST) => {
            for keyword in ["public", "protected", "private", "const", "ref", "global", "self"] {
                items.push(item(keyword, CompletionKind::Keyword, None));
            }
            return with_types(&sema, &at, typed, items);
        }
        Some(COMPONENT_DIAGRAM) => {
            for kind in ["source", "filter", "sink", "class"] {
                items.push(snippet(kind, &format!("{kind} ${{1:Class}}\n{{\n\tport ${{2:Port}} ( provider ${{3:out}} : ${{4:Interface}} );\n}}"), "component"));
            }
        }
        Some(COMPONENT_INSTANCE_DIAGRAM) => {
            items.push(snippet("instantiates", "${1:Name} instantiates ${2:Component} ( )\n{\n\t$0\n}", "component instance"));
        }
        _ => {
            for (kind, body) in [
                ("ClassDiagram", "ClassDiagram ${1:Name}\n{\n\t$0\n}"),
                ("ActivityDiagram", "ActivityDiagram ${1:Name}(${2})\n{\n\tswimlane ${3:Lane}\n\t{\n\t\tstart S\n\t\t{\n\t\t\t=> done;\n\t\t}\n\t\t$0\n\t\tfinal done;\n\t}\n}"),
                ("ComponentDiagram", "ComponentDiagram ${1:Name}\n{\n\t$0\n}"),
                ("ComponentInstanceDiagram", "ComponentInstanceDiagram ${1:Name}\n{\n\t$0\n}"),
            ] {
                items.push(snippet(kind, body, "diagram"));
            }
        }
    }
    finish(items)
}

fn finish(mut items: Vec<CompletionItem>) -> Completions {
    items.sort();
    items.dedup_by(|a, b| a.label == b.label && a.kind == b.kind);
    Completions { items, incomplete: false }
}

fn previous_token(root: &SyntaxNode, offset: TextSize) -> Option<SyntaxToken> {
    let token = root.token_at_offset(offset).left_biased()?;
    skip_trivia_back(&token)
}

fn skip_trivia_back(token: &SyntaxToken) -> Option<SyntaxToken> {
    let mut t = Some(token.clone());
    while let Some(current) = t {
        if !current.kind().is_trivia() {
            return Some(current);
        }
        t = current.prev_token();
    }
    None
}

/// What may follow in a connection (`port.connector`) or binding
/// (`portInstance.connector`, `instance.portInstance.connector`) after `prefix`.
fn connector_candidates(link: &SyntaxNode, prefix: Option<&str>, items: &mut Vec<CompletionItem>) {
    let segments: Vec<&str> = prefix.map(|p| p.split('.').collect()).unwrap_or_default();
    if link.kind() == CONNECTION {
        let Some(diagram) = link.ancestors().find_map(ast::ComponentDiagram::cast) else { return };
        for port in diagram.syntax().descendants().filter_map(ast::Port::cast) {
            let Some(name) = port.name().map(|n| n.text()) else { continue };
            match segments.as_slice() {
                [] => items.push(item(name, CompletionKind::Interface, Some("port".into()))),
                [p] if *p == name => {
                    for c in port.connectors().filter_map(|c| c.name()) {
                        items.push(item(c.text(), CompletionKind::Field, Some(format!("connector of {name}"))));
                    }
                }
                _ => {}
            }
        }
        return;
    }
    let Some(diagram) = link.ancestors().find_map(ast::ComponentInstanceDiagram::cast) else { return };
    let own = link.ancestors().find_map(ast::ComponentInstance::cast);
    let port_instances =
        |instance: &ast::ComponentInstance| -> Vec<ast::PortInstance> { instance.port_instances().collect() };
    let connectors_of = |pi: &ast::PortInstance, items: &mut Vec<CompletionItem>| {
        for c in pi.connectors().filter_map(|c| c.name()) {
            items.push(item(c.text(), CompletionKind::Field, Some("connector".into())));
        }
    };
    match segments.as_slice() {
        [] => {
            if let Some(own) = &own {
                for pi in port_instances(own).iter().filter_map(|p| p.name()) {
                    items.push(item(pi.text(), CompletionKind::Interface, Some("port instance".into())));
                }
            }
            for instance in diagram.instances().filter_map(|i| i.name()) {
                items.push(item(instance.text(), CompletionKind::Variable, Some("instance".into())));
            }
        }
        [first] => {
            if let Some(pi) = own.iter().flat_map(port_instances).find(|p| p.name().is_some_and(|n| n.text() == *first))
            {
                connectors_of(&pi, items);
            }
            if let Some(instance) = diagram.instances().find(|i| i.name().is_some_and(|n| n.text() == *first)) {
                for pi in port_instances(&instance).iter().filter_map(|p| p.name()) {
                    items.push(item(pi.text(), CompletionKind::Interface, Some("port instance".into())));
                }
            }
        }
        [instance, port_instance] => {
            if let Some(instance) = diagram.instances().find(|i| i.name().is_some_and(|n| n.text() == *instance)) {
                if let Some(pi) =
                    instance.port_instances().find(|p| p.name().is_some_and(|n| n.text() == *port_instance))
                {
                    connectors_of(&pi, items);
                }
            }
        }
        _ => {}
    }
}

/// `A.B` for the `.` after `B` in `A.B.`.
fn path_before_dot(dot: &SyntaxToken) -> Option<String> {
    let mut segments = Vec::new();
    let mut t = dot.prev_token().and_then(|t| skip_trivia_back(&t));
    while let Some(ident) = t.filter(|t| t.kind() == IDENT) {
        segments.push(ident.text().to_string());
        let before = ident.prev_token().and_then(|t| skip_trivia_back(&t));
        match before {
            Some(d) if d.kind() == DOT => t = d.prev_token().and_then(|t| skip_trivia_back(&t)),
            _ => break,
        }
    }
    segments.reverse();
    (!segments.is_empty()).then(|| segments.join("."))
}

/// `items` and every type that fits where a type is written at `at`: the built-in ones, then
/// those of [`types_in_scope`].
fn with_types(sema: &Semantics, at: &SyntaxNode, typed: &str, mut items: Vec<CompletionItem>) -> Completions {
    for ty in BUILTIN_TYPES {
        items.push(item(*ty, CompletionKind::Keyword, Some("built-in type".into())));
    }
    let incomplete = types_in_scope(sema, &Scope::at(at), typed, &mut items);
    Completions { incomplete, ..finish(items) }
}

/// The types for a type position: every type the cursor's scope sees by its simple name (its
/// diagrams' and its imports'), then the workspace's other types whose name matches what is
/// typed (`typed` in order, any case), at most [`FAR_TYPES`] of them. Whether some were left out.
fn types_in_scope(sema: &Semantics, scope: &Scope, typed: &str, items: &mut Vec<CompletionItem>) -> bool {
    let mut seen: HashSet<String> = HashSet::new();
    let mut near = |name: &str, def: &Definition, items: &mut Vec<CompletionItem>| {
        if matches!(def.kind, DefKind::Type(_)) && seen.insert(def.fqn.clone()) {
            items.push(item(name, CompletionKind::Type, Some(def.fqn.clone())));
        }
    };
    let wildcards = scope.imports.iter().filter_map(|i| match i {
        ImportItem::Wildcard(prefix) => Some(prefix.as_str()),
        _ => None,
    });
    for namespace in scope.namespaces.iter().map(String::as_str).chain(wildcards) {
        for (name, defs) in sema.namespace_members(namespace) {
            near(name, &defs[0], items);
        }
    }
    for import in &scope.imports {
        if let ImportItem::Name(fqn) = import {
            if let Some(def) = sema.definition(fqn) {
                near(fqn.rsplit('.').next().unwrap_or(fqn), def, items);
            }
        }
    }
    // Names that start with what is typed first, then the others that contain its letters.
    let mut matching: Vec<(bool, &String, &Vec<String>)> = sema
        .types_by_simple_name()
        .filter(|(simple, _)| typed_in(typed, simple))
        .map(|(simple, fqns)| (!starts_with_ignoring_case(simple, typed), simple, fqns))
        .collect();
    // Only the first ones are proposed: each name has a type, and at most `seen.len()` of those
    // are already listed, so the first `FAR_TYPES + seen.len()` names hold every proposal.
    let proposed = FAR_TYPES + seen.len();
    let cut = matching.len() > proposed;
    if cut {
        matching.select_nth_unstable(proposed);
        matching.truncate(proposed);
    }
    matching.sort_unstable();
    let mut far = 0;
    for (_, simple, fqns) in matching {
        for fqn in fqns.iter().filter(|fqn| !seen.contains(*fqn)) {
            if far == FAR_TYPES {
                return true;
            }
            let label = if fqns.len() == 1 { simple.clone() } else { fqn.clone() };
            items.push(CompletionItem { far: true, ..item(label, CompletionKind::Type, Some(fqn.clone())) });
            far += 1;
        }
    }
    cut
}

fn starts_with_ignoring_case(name: &str, typed: &str) -> bool {
    name.get(..typed.len()).is_some_and(|head| head.eq_ignore_ascii_case(typed))
}

/// Whether the characters of `typed` appear in `name` in order, ignoring case (as editors
/// filter completions).
fn typed_in(typed: &str, name: &str) -> bool {
    let mut name = name.chars().flat_map(char::to_lowercase);
    typed.chars().flat_map(char::to_lowercase).all(|t| name.any(|n| n == t))
}

fn locals_in_scope(body: &SyntaxNode, items: &mut Vec<CompletionItem>) {
    for ancestor in body.ancestors() {
        for decl in ancestor.children().filter(|c| matches!(c.kind(), VAR_DECL | VARIABLE)) {
            if let Some(name) = decl.children().find(|c| c.kind() == NAME) {
                items.push(item(name.text().to_string(), CompletionKind::Variable, None));
            }
        }
        for param in ancestor.children().filter(|c| c.kind() == PARAM_LIST).flat_map(|l| l.children()) {
            if let Some(name) = ast::Param::cast(param).and_then(|p| p.name()) {
                items.push(item(name.text(), CompletionKind::Variable, Some("parameter".into())));
            }
        }
    }
}

/// The fields and methods of a type and its bases.
fn type_members(sema: &Semantics, def: &crate::hir::Definition, items: &mut Vec<CompletionItem>) {
    for def in sema.type_and_bases(def) {
        let DefKind::Type(ty) = &def.kind else { continue };
        for field in &ty.fields {
            items.push(item(field.name.clone(), CompletionKind::Field, Some(def.fqn.clone())));
        }
        for method in &ty.methods {
            let params: Vec<String> =
                method.params.iter().enumerate().map(|(i, p)| format!("${{{}:{}}}", i + 1, p.name)).collect();
            let mut it = item(method.name.clone(), CompletionKind::Method, Some(def.fqn.clone()));
            it.snippet = Some(format!("{}({})", method.name, params.join(", ")));
            items.push(it);
        }
    }
}

#[cfg(test)]
mod tests;
