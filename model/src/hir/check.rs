//! Validation of one file: resolves every reference through the workspace and checks the
//! rules of each diagram kind. Runs on the syntax tree (for ranges) and reaches other files
//! only through [`lookup`], so its result depends on exactly the names it uses.

use std::collections::{HashMap, HashSet, VecDeque};

use super::{
    components::{component_info, processor_signatures, resolve_path, signature_key, ComponentInfo},
    definitions::{join, lookup, types_named, DefKind, Definition, Fqn},
    diagnostics::{Diagnostic, DiagnosticCode, Severity},
    infer::{header_declarations, Body},
    items::{type_signature, ConnectorRole, ImportItem, InterfaceRole, TypeKind, TypeSignature},
    ty,
};
use crate::{
    ast::{self, AstNode, HasModifiers, HasName},
    db::{parse, Db, SourceFile, Workspace},
    syntax::{SyntaxKind, TextRange},
};

/// The semantic diagnostics of one file.
#[salsa::tracked(returns(ref))]
pub fn check_file(db: &dyn Db, workspace: Workspace, file: SourceFile) -> Vec<Diagnostic> {
    let mut checker = Checker { db, workspace, current_file: file, diagnostics: Vec::new() };
    let source = parse(db, file).source_file();
    let root = Scope::default();
    checker.duplicates(source.diagrams().filter_map(|d| d.name()), "diagram");
    for diagram in source.diagrams() {
        checker.diagram(&root, &diagram);
    }
    checker.diagnostics
}

impl<'db> Checker<'db> {
    /// A checker used only to resolve names (editor features), reporting nothing.
    pub(crate) fn resolver(db: &'db dyn Db, workspace: Workspace, file: SourceFile) -> Checker<'db> {
        Checker { db, workspace, current_file: file, diagnostics: Vec::new() }
    }
}

/// The scope at a syntax node: the enclosing diagrams (namespaces) and their imports.
pub(crate) fn scope_at(node: &crate::SyntaxNode) -> Scope {
    let mut diagrams: Vec<ast::Diagram> = node.ancestors().filter_map(ast::Diagram::cast).collect();
    diagrams.reverse();
    let mut scope = Scope::default();
    for diagram in diagrams {
        let Some(name) = diagram.name().map(|n| n.text()) else { break };
        scope.namespaces.push(join(scope.namespaces.last().map_or("", |s| s.as_str()), &name));
        for import in diagram.syntax().children().filter_map(ast::Import::cast) {
            match import.target() {
                Some(ast::ImportTarget::Name(p)) => scope.imports.push(ImportItem::Name(p.text())),
                Some(ast::ImportTarget::Wildcard(p)) => scope.imports.push(ImportItem::Wildcard(p.text())),
                _ => {}
            }
        }
    }
    scope
}

/// Where names are looked up: the enclosing diagrams (innermost last), their imports and the
/// template parameters in scope.
#[derive(Clone, Default)]
pub(crate) struct Scope {
    pub(crate) namespaces: Vec<String>,
    pub(crate) imports: Vec<ImportItem>,
    pub(crate) type_params: Vec<String>,
}

pub(crate) struct Checker<'db> {
    db: &'db dyn Db,
    workspace: Workspace,
    current_file: SourceFile,
    diagnostics: Vec<Diagnostic>,
}

impl<'db> Checker<'db> {
    pub(crate) fn error(&mut self, code: DiagnosticCode, range: TextRange, message: String) {
        self.report(code, range, message);
    }

    /// The one definition of a fully qualified name, if any.
    pub(crate) fn lookup_one(&self, fqn: &str) -> Option<&'db Definition> {
        self.lookup(fqn).first()
    }

    /// The class whose members a body at `node` sees: its swimlane's owner, else its activity
    /// diagram's owner, else the class the body belongs to.
    pub(crate) fn owner_at(&self, node: &crate::SyntaxNode) -> Option<&'db Definition> {
        let scope = scope_at(node);
        let resolve_owner = |path: Option<ast::Path>| path.and_then(|p| self.resolve(&scope, &p.text()));
        let lane = node.ancestors().find_map(ast::Swimlane::cast).and_then(|lane| resolve_owner(lane.owner()));
        let diagram = || node.ancestors().find_map(ast::ActivityDiagram::cast).and_then(|d| resolve_owner(d.owner()));
        let class = || {
            let class = node.ancestors().find_map(ast::TypeDecl::cast)?;
            self.lookup_one(&join(scope.namespaces.last().map_or("", |s| s.as_str()), &class.name()?.text()))
        };
        lane.or_else(diagram).or_else(class).filter(|d| matches!(d.kind, DefKind::Type(_)))
    }

    /// Whether type `sub` is `sup` or derives from it (`extends`/`implements`, transitively).
    pub(crate) fn is_subtype(&self, sub: &str, sup: &str) -> bool {
        let mut seen = HashSet::new();
        let mut stack = vec![sub.to_string()];
        while let Some(fqn) = stack.pop() {
            if fqn == sup {
                return true;
            }
            if !seen.insert(fqn.clone()) {
                continue;
            }
            let Some(def) = self.lookup_one(&fqn) else { continue };
            let DefKind::Type(ty) = &def.kind else { continue };
            let scope = self.scope_of(def);
            for base in ty.extends.iter().chain(&ty.implements).filter_map(|b| b.path.as_deref()) {
                if let Some(base_def) = self.resolve(&scope, base) {
                    stack.push(base_def.fqn.clone());
                }
            }
        }
        false
    }

    /// Finds, in type `fqn` or its bases, the first member `pick` returns.
    pub(crate) fn find_member<T>(
        &self,
        fqn: &str,
        seen: &mut HashSet<String>,
        pick: &dyn Fn(&super::items::TypeItem) -> Option<T>,
    ) -> Option<(&'db Definition, T)> {
        if !seen.insert(fqn.to_string()) {
            return None;
        }
        let def = self.lookup_one(fqn)?;
        let DefKind::Type(ty) = &def.kind else { return None };
        if let Some(found) = pick(ty) {
            return Some((def, found));
        }
        let scope = self.scope_of(def);
        for base in ty.extends.iter().chain(&ty.implements).filter_map(|b| b.path.as_deref()) {
            if let Some(base_def) = self.resolve(&scope, base) {
                if let Some(found) = self.find_member(&base_def.fqn, seen, pick) {
                    return Some(found);
                }
            }
        }
        None
    }

    /// Every overload of `name` in `def` and its bases, with the type that declares it.
    pub(crate) fn collect_methods(
        &self,
        def: &'db Definition,
        name: &str,
        seen: &mut HashSet<String>,
        out: &mut Vec<(&'db Definition, super::items::MethodSignature)>,
    ) {
        if !seen.insert(def.fqn.clone()) {
            return;
        }
        let DefKind::Type(ty) = &def.kind else { return };
        out.extend(ty.methods.iter().filter(|m| m.name == name).map(|m| (def, m.clone())));
        let scope = self.scope_of(def);
        for base in ty.extends.iter().chain(&ty.implements).filter_map(|b| b.path.as_deref()) {
            if let Some(base_def) = self.resolve(&scope, base) {
                self.collect_methods(base_def, name, seen, out);
            }
        }
    }

    fn report(&mut self, code: DiagnosticCode, range: TextRange, message: String) {
        self.diagnostics.push(Diagnostic { code, severity: Severity::Error, range, message });
    }

    fn warn(&mut self, code: DiagnosticCode, range: TextRange, message: String) {
        self.diagnostics.push(Diagnostic { code, severity: Severity::Warning, range, message });
    }

    fn lookup(&self, fqn: &str) -> &'db [Definition] {
        lookup(self.db, self.workspace, Fqn::new(self.db, fqn.to_string()))
    }

    /// Resolves a (possibly qualified) name from `scope`: enclosing namespaces innermost first,
    /// then imports, then the name as a fully qualified one.
    ///
    /// A simple name that none of these finds names the workspace's only type of that name, if
    /// there is exactly one (the dissertation's listings use other diagrams' types unqualified).
    pub(crate) fn resolve(&self, scope: &Scope, path: &str) -> Option<&'db Definition> {
        if let Some(fqn) = resolve_path(&scope.namespaces, &scope.imports, path, |c| !self.lookup(c).is_empty()) {
            return self.lookup(&fqn).first();
        }
        if path.contains('.') {
            return None;
        }
        match types_named(self.db, self.workspace, Fqn::new(self.db, path.to_string())).as_slice() {
            [only] => self.lookup(only).first(),
            _ => None,
        }
    }

    /// The types a simple name could mean, for an "ambiguous" message.
    fn candidates(&self, path: &str) -> &'db [String] {
        if path.contains('.') {
            return &[];
        }
        types_named(self.db, self.workspace, Fqn::new(self.db, path.to_string()))
    }

    /// Reports `name` (declared with fully qualified name `fqn`) if another file declares it too.
    fn unique_across_files(&mut self, fqn: &str, name: &ast::Name, what: &str) {
        let definitions = self.lookup(fqn);
        let here = self.current_file;
        let elsewhere: Vec<&str> =
            definitions.iter().filter(|d| d.file != here).map(|d| d.file.path(self.db).as_str()).collect();
        if let Some(other) = elsewhere.first() {
            self.report(
                DiagnosticCode::DuplicateName,
                name.syntax().text_range(),
                format!("{what} `{fqn}` is also declared in {other}"),
            );
        }
    }

    fn duplicates(&mut self, names: impl Iterator<Item = ast::Name>, what: &str) {
        let mut seen: HashMap<String, TextRange> = HashMap::new();
        for name in names {
            let text = name.text();
            let range = name.syntax().text_range();
            if let Some(first) = seen.get(&text) {
                let _ = first;
                self.report(
                    DiagnosticCode::DuplicateName,
                    range,
                    format!("{what} `{text}` is declared more than once in this scope"),
                );
            } else {
                seen.insert(text, range);
            }
        }
    }

    fn diagram(&mut self, outer: &Scope, diagram: &ast::Diagram) {
        let Some(name) = diagram.name().map(|n| n.text()) else { return };
        let mut scope = outer.clone();
        scope.namespaces.push(join(scope.namespaces.last().map_or("", |s| s.as_str()), &name));
        for import in diagram.syntax().children().filter_map(ast::Import::cast) {
            self.import(&mut scope, &import);
        }
        let nested: Vec<ast::Diagram> = diagram.syntax().children().filter_map(ast::Diagram::cast).collect();
        // Class diagrams are namespaces and merge across files; other diagrams must be unique.
        if !matches!(diagram, ast::Diagram::ClassDiagram(_)) {
            if let Some(name) = diagram.name() {
                self.unique_across_files(scope.namespaces.last().map_or("", |s| s.as_str()), &name, "diagram");
            }
        }
        match diagram {
            ast::Diagram::ClassDiagram(d) => {
                let names = d.type_decls().filter_map(|t| t.name()).chain(nested.iter().filter_map(|d| d.name()));
                self.duplicates(names, "declaration");
                for decl in d.type_decls() {
                    if let Some(name) = decl.name() {
                        let fqn = join(scope.namespaces.last().map_or("", |s| s.as_str()), &name.text());
                        self.unique_across_files(&fqn, &name, "type");
                    }
                    self.type_decl(&scope, &decl);
                }
            }
            ast::Diagram::ActivityDiagram(d) => self.activity(&scope, d),
            ast::Diagram::ComponentDiagram(d) => {
                self.duplicates(nested.iter().filter_map(|d| d.name()), "diagram");
                self.component_diagram(&scope, d);
            }
            ast::Diagram::ComponentInstanceDiagram(d) => {
                self.duplicates(nested.iter().filter_map(|d| d.name()), "diagram");
                self.instance_diagram(&scope, d);
            }
        }
        for nested in &nested {
            self.diagram(&scope, nested);
        }
    }

    fn import(&mut self, scope: &mut Scope, import: &ast::Import) {
        let Some(target) = import.target() else { return };
        let (path, item) = match target {
            ast::ImportTarget::Name(p) => (p.clone(), ImportItem::Name(p.text())),
            ast::ImportTarget::Wildcard(p) => (p.clone(), ImportItem::Wildcard(p.text())),
            ast::ImportTarget::Header(_) => return,
        };
        if self.lookup(&path.text()).is_empty() {
            self.report(
                DiagnosticCode::UnresolvedImport,
                path.syntax().text_range(),
                format!("cannot import `{}`: no diagram or type has this fully qualified name", path.text()),
            );
        }
        scope.imports.push(item);
    }

    // ---- class diagrams

    fn type_decl(&mut self, outer: &Scope, decl: &ast::TypeDecl) {
        let mut scope = outer.clone();
        if let ast::TypeDecl::Class(c) = decl {
            scope.type_params.extend(c.template_params().filter_map(|t| t.name()).map(|n| n.text()));
            for ty in c.extends().chain(c.implements()) {
                self.type_ref(&scope, &ty);
            }
        }
        if let ast::TypeDecl::Interface(i) = decl {
            scope.type_params.extend(i.template_params().filter_map(|t| t.name()).map(|n| n.text()));
            for ty in i.extends() {
                self.type_ref(&scope, &ty);
            }
            if i.role() == InterfaceRole::Provider {
                self.provider_methods(i);
            }
        }
        self.attribute_uses(&scope, decl.syntax());
        let gpu_class = self.is_gpu_class(&scope, decl);
        let members: Vec<ast::Member> = decl.members().collect();
        let field_names = members.iter().filter_map(|m| match m {
            ast::Member::Field(f) => f.name(),
            ast::Member::Association(a) => a.name(),
            ast::Member::Method(_) => None,
        });
        self.duplicates(field_names, "field");
        for member in &members {
            match member {
                ast::Member::Field(f) => {
                    if let Some(ty) = f.type_ref() {
                        self.type_ref(&scope, &ty);
                    }
                    if let Some(init) = f.initializer() {
                        self.expressions(&scope, init.syntax());
                    }
                }
                ast::Member::Association(a) => {
                    if let Some(ty) = a.target() {
                        self.type_ref(&scope, &ty);
                    }
                }
                ast::Member::Method(m) => {
                    if let Some(ty) = m.return_type() {
                        self.type_ref(&scope, &ty);
                    }
                    self.params(&scope, m.param_list());
                    if !gpu_class {
                        self.shared_params(m);
                    }
                    if let Some(body) = m.body() {
                        self.expressions(&scope, body.syntax());
                        let owner = self.owner_at(body.syntax());
                        let mut typing = Body { checker: self, scope: scope.clone(), locals: HashMap::new(), owner };
                        for param in m.params() {
                            if let Some(name) = param.name() {
                                typing.declare(name.text(), param.type_ref());
                            }
                        }
                        typing.check(body.syntax());
                    }
                }
            }
        }
    }

    fn params(&mut self, scope: &Scope, list: Option<ast::ParamList>) {
        let Some(list) = list else { return };
        self.duplicates(list.params().filter_map(|p| p.name()), "parameter");
        for param in list.params() {
            if let Some(ty) = param.type_ref() {
                self.type_ref(scope, &ty);
            }
        }
    }

    /// Checks that a type names something (a built-in, a GPU type, a template parameter or a
    /// declared type), and its type arguments likewise.
    fn type_ref(&mut self, scope: &Scope, ty: &ast::TypeRef) {
        for arg in ty.type_args() {
            self.type_ref(scope, &arg);
        }
        let Some(path) = ty.path() else { return };
        let text = path.text();
        if text.is_empty() || is_builtin_type_name(&text) || scope.type_params.contains(&text) {
            return;
        }
        match self.resolve(scope, &text) {
            Some(def) if matches!(def.kind, DefKind::Type(_)) => {}
            Some(def) => self.report(
                DiagnosticCode::UnresolvedType,
                path.syntax().text_range(),
                format!("`{text}` names {} `{}`, not a type", describe(&def.kind), def.fqn),
            ),
            None => {
                let candidates = self.candidates(&text);
                let message = if candidates.len() > 1 {
                    format!("ambiguous type `{text}`: qualify it or import one of {}", candidates.join(", "))
                } else {
                    format!("unknown type `{text}`: declare it in a class diagram or import the diagram that does")
                };
                self.report(DiagnosticCode::UnresolvedType, path.syntax().text_range(), message);
            }
        }
    }

    /// Types and behaviors named inside statements and expressions (`var T x`, `new T(…)`,
    /// `x as T`, `call behavior X`).
    fn expressions(&mut self, scope: &Scope, node: &crate::SyntaxNode) {
        for descendant in node.descendants() {
            match descendant.kind() {
                SyntaxKind::TYPE_REF if descendant.parent().is_some_and(|p| p.kind() != SyntaxKind::TYPE_ARGS) => {
                    if let Some(ty) = ast::TypeRef::cast(descendant) {
                        self.type_ref(scope, &ty);
                    }
                }
                SyntaxKind::CALL_BEHAVIOR_EXPR => {
                    if let Some(call) = ast::CallBehaviorExpr::cast(descendant) {
                        self.call_behavior(scope, &call);
                    }
                }
                SyntaxKind::CALL_METHOD_EXPR => {
                    if let Some(call) = ast::CallMethodExpr::cast(descendant) {
                        self.call_method(scope, &call);
                    }
                }
                _ => {}
            }
        }
    }

    fn call_behavior(&mut self, scope: &Scope, call: &ast::CallBehaviorExpr) {
        let Some(path) = call.behavior() else { return };
        let text = path.text();
        let range = path.syntax().text_range();
        match self.resolve(scope, &text).map(|d| &d.kind) {
            Some(DefKind::Activity(signature)) => {
                let given = call.args().count();
                let expected = signature.params.len();
                // Without an argument list the diagram's parameters are taken from the caller.
                if call.syntax().children().any(|n| n.kind() == SyntaxKind::ARG_LIST) && given != expected {
                    self.report(
                        DiagnosticCode::TransitionArity,
                        range,
                        format!("activity diagram `{text}` takes {}, {given} given", arguments(expected)),
                    );
                }
            }
            Some(other) => self.report(
                DiagnosticCode::UnresolvedBehavior,
                range,
                format!("`call behavior` needs an activity diagram, but `{text}` is {}", describe(other)),
            ),
            None => {
                self.report(DiagnosticCode::UnresolvedBehavior, range, format!("unknown activity diagram `{text}`"))
            }
        }
    }

    /// `call Class::method(…)`: the class exists and has (or inherits) the method.
    fn call_method(&mut self, scope: &Scope, call: &ast::CallMethodExpr) {
        let (Some(class), Some(method)) = (call.class(), call.method()) else { return };
        let class_text = class.text();
        let Some(def) = self.resolve(scope, &class_text) else {
            let candidates = self.candidates(&class_text);
            let message = if candidates.len() > 1 {
                format!("ambiguous class `{class_text}`: qualify it or import one of {}", candidates.join(", "))
            } else {
                format!("unknown class `{class_text}`")
            };
            self.report(DiagnosticCode::UnresolvedType, class.syntax().text_range(), message);
            return;
        };
        let DefKind::Type(_) = &def.kind else {
            self.report(
                DiagnosticCode::UnresolvedType,
                class.syntax().text_range(),
                format!("`{class_text}` is {}, not a class", describe(&def.kind)),
            );
            return;
        };
        let name = method.text();
        let declares = |ty: &super::items::TypeItem| ty.methods.iter().any(|m| m.name == name).then_some(());
        if self.find_member(&def.fqn, &mut HashSet::new(), &declares).is_none() {
            self.report(
                DiagnosticCode::UnresolvedMethod,
                method.syntax().text_range(),
                format!("`{}` has no method `{name}`", def.fqn),
            );
        }
    }

    /// The scope a definition was declared in: its enclosing namespaces and their imports.
    pub(crate) fn scope_of(&self, def: &Definition) -> Scope {
        let mut namespaces = Vec::new();
        let mut prefix = String::new();
        let segments: Vec<&str> = def.fqn.split('.').collect();
        for segment in &segments[..segments.len().saturating_sub(1)] {
            prefix = join(&prefix, segment);
            namespaces.push(prefix.clone());
        }
        Scope { namespaces, imports: def.imports.to_vec(), ..Scope::default() }
    }

    /// A provider interface's `provideX(…)` methods need a processor interface with the
    /// corresponding `processX(…)` signature (chapter 11.3.1).
    fn provider_methods(&mut self, interface: &ast::Interface) {
        let processors = processor_signatures(self.db, self.workspace);
        for member in interface.members() {
            let ast::Member::Method(method) = member else { continue };
            let Some(name) = method.name() else { continue };
            let text = name.text();
            let Some(suffix) = text.strip_prefix("provide") else { continue };
            let params: Vec<TypeSignature> = method.params().map(|p| type_signature(p.type_ref())).collect();
            let key = signature_key(suffix, &params);
            if !processors.contains(&key) {
                self.report(
                    DiagnosticCode::MissingProcessorSignature,
                    name.syntax().text_range(),
                    format!("provider method `{text}` has no processor counterpart: declare `process{key}` in a processor interface"),
                );
            }
        }
    }

    /// `[A.B(field = value)]`: the attribute exists and declares each field.
    fn attribute_uses(&mut self, scope: &Scope, node: &crate::SyntaxNode) {
        for list in node.children().filter_map(ast::AttributeList::cast) {
            for use_ in list.uses() {
                let Some(path) = use_.path() else { continue };
                let text = path.text();
                let def = self.resolve(scope, &text);
                let attribute = match def.map(|d| &d.kind) {
                    Some(DefKind::Type(ty)) if ty.kind == TypeKind::Attribute => ty.clone(),
                    Some(other) => {
                        self.report(
                            DiagnosticCode::InvalidAttributeUse,
                            path.syntax().text_range(),
                            format!("`{text}` is {}, not an attribute", describe(other)),
                        );
                        continue;
                    }
                    None => {
                        self.report(
                            DiagnosticCode::InvalidAttributeUse,
                            path.syntax().text_range(),
                            format!("unknown attribute `{text}`"),
                        );
                        continue;
                    }
                };
                for arg in use_.args() {
                    let Some(field) = arg.name() else { continue };
                    if !attribute.fields.iter().any(|f| f.name == field.text()) {
                        self.report(
                            DiagnosticCode::InvalidAttributeUse,
                            field.syntax().text_range(),
                            format!("attribute `{text}` has no field `{}`", field.text()),
                        );
                    }
                }
            }
        }
    }

    /// A class that implements (directly or through its bases) the `OpenCL` interface is
    /// generated as OpenCL code (chapter 10.3.2.3); only there may parameters be `shared`.
    fn is_gpu_class(&self, scope: &Scope, decl: &ast::TypeDecl) -> bool {
        let ast::TypeDecl::Class(class) = decl else { return false };
        let mut seen = HashSet::new();
        class
            .extends()
            .chain(class.implements())
            .filter_map(|t| t.path())
            .any(|p| self.resolve(scope, &p.text()).is_some_and(|d| self.reaches_opencl(d, &mut seen)))
    }

    fn reaches_opencl(&self, def: &Definition, seen: &mut HashSet<String>) -> bool {
        if def.fqn.rsplit('.').next() == Some("OpenCL") {
            return true;
        }
        let DefKind::Type(ty) = &def.kind else { return false };
        if !seen.insert(def.fqn.clone()) {
            return false;
        }
        let scope = self.scope_of(def);
        ty.extends
            .iter()
            .chain(&ty.implements)
            .filter_map(|b| b.path.as_deref())
            .any(|base| self.resolve(&scope, base).is_some_and(|d| self.reaches_opencl(d, seen)))
    }

    fn shared_params(&mut self, method: &ast::Method) {
        for param in method.params() {
            if param.has_modifier(SyntaxKind::SHARED_KW) {
                let range = param.name().map_or_else(|| param.syntax().text_range(), |n| n.syntax().text_range());
                self.report(
                    DiagnosticCode::SharedOutsideGpuClass,
                    range,
                    "`shared` memory parameters are only allowed in classes that implement the `OpenCL` interface"
                        .to_string(),
                );
            }
        }
    }

    // ---- component diagrams

    fn component_diagram(&mut self, scope: &Scope, diagram: &ast::ComponentDiagram) {
        let mut components = Vec::new();
        let mut stack: Vec<ast::Component> = diagram.components().collect();
        while let Some(component) = stack.pop() {
            stack.extend(component.components());
            components.push(component);
        }
        // Every port.connector of the diagram, for connection ends.
        let mut connectors: HashMap<String, ConnectorRole> = HashMap::new();
        for component in &components {
            if let Some(class) = component.class() {
                let text = class.text();
                match self.resolve(scope, &text).map(|d| &d.kind) {
                    Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Class(_)) => {}
                    Some(other) => self.report(
                        DiagnosticCode::InvalidComponent,
                        class.syntax().text_range(),
                        format!("a component is built on a class, but `{text}` is {}", describe(other)),
                    ),
                    None => self.report(
                        DiagnosticCode::InvalidComponent,
                        class.syntax().text_range(),
                        format!("unknown component class `{text}`"),
                    ),
                }
            }
            self.duplicates(component.ports().filter_map(|p| p.name()), "port");
            for port in component.ports() {
                let Some(port_name) = port.name().map(|n| n.text()) else { continue };
                for connector in port.connectors() {
                    let (Some(role), Some(name), Some(interface)) =
                        (connector.role(), connector.name(), connector.interface())
                    else {
                        continue;
                    };
                    connectors.insert(format!("{port_name}.{}", name.text()), role);
                    self.connector_interface(scope, role, &interface);
                }
            }
        }
        for component in &components {
            for connection in component.connections() {
                use ast::HasEnds;
                let mut roles = Vec::new();
                for end in [connection.source(), connection.target()].into_iter().flatten() {
                    match connectors.get(&end.text()) {
                        Some(&role) => roles.push(role),
                        None => self.report(
                            DiagnosticCode::UnresolvedConnector,
                            end.syntax().text_range(),
                            format!("no connector `{}` (`port.connector`) in this component diagram", end.text()),
                        ),
                    }
                }
                if let [source, target] = roles[..] {
                    if source == target {
                        let range = connection.syntax().text_range();
                        self.report(
                            DiagnosticCode::InvalidConnection,
                            range,
                            format!("a connection joins a provider and a processor, not two {}s", role_name(source)),
                        );
                    }
                }
            }
        }
    }

    /// A connector's interface is an interface of the connector's role.
    fn connector_interface(&mut self, scope: &Scope, role: ConnectorRole, interface: &ast::Path) {
        let text = interface.text();
        let range = interface.syntax().text_range();
        let expected = match role {
            ConnectorRole::Provider => InterfaceRole::Provider,
            ConnectorRole::Processor => InterfaceRole::Processor,
        };
        match self.resolve(scope, &text).map(|d| &d.kind) {
            Some(DefKind::Type(ty)) if ty.kind == TypeKind::Interface(expected) => {}
            Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Interface(_)) => self.report(
                DiagnosticCode::InvalidConnectorInterface,
                range,
                format!("a {0} connector needs a `{0}` interface; `{text}` is not one", role_name(role)),
            ),
            Some(other) => self.report(
                DiagnosticCode::InvalidConnectorInterface,
                range,
                format!("`{text}` is {}, not an interface", describe(other)),
            ),
            None => {
                self.report(DiagnosticCode::InvalidConnectorInterface, range, format!("unknown interface `{text}`"))
            }
        }
    }

    // ---- component-instance diagrams

    fn instance_diagram(&mut self, scope: &Scope, diagram: &ast::ComponentInstanceDiagram) {
        use ast::HasEnds;
        self.duplicates(diagram.instances().filter_map(|i| i.name()), "instance");
        // instance name -> (components, port instance name -> (port name, connector instance
        // name -> the port's connector it instantiates))
        type PortInstances = HashMap<String, (String, HashMap<String, String>)>;
        let mut instances: HashMap<String, (&'db [ComponentInfo], PortInstances)> = HashMap::new();
        for instance in diagram.instances() {
            let Some(name) = instance.name().map(|n| n.text()) else { continue };
            let infos = instance.component().map_or(&[][..], |path| self.instance_component(scope, &instance, &path));
            let mut ports = HashMap::new();
            self.duplicates(instance.port_instances().filter_map(|p| p.name()), "port instance");
            for port_instance in instance.port_instances() {
                let (Some(pi_name), Some(port)) = (port_instance.name(), port_instance.port()) else { continue };
                if let Some(first) = infos.first() {
                    if !infos.iter().any(|info| info.item.ports.iter().any(|p| p.name == port.text())) {
                        self.report(
                            DiagnosticCode::UnresolvedConnector,
                            port.syntax().text_range(),
                            format!("component `{}` has no port `{}`", first.item.class, port.text()),
                        );
                    }
                }
                // A connector instance (`provider name = Interface()`, a new name, Listing 24)
                // instantiates the port's connector with the same interface.
                let port_connectors: Vec<&super::items::ConnectorItem> = infos
                    .iter()
                    .flat_map(|info| info.item.ports.iter())
                    .filter(|p| p.name == port.text())
                    .flat_map(|p| p.connectors.iter())
                    .collect();
                let mut connectors = HashMap::new();
                for cid in port_instance.connectors() {
                    let (Some(cid_name), Some(interface)) = (cid.name(), cid.interface()) else { continue };
                    let simple = interface.last_segment().map(|s| s.text()).unwrap_or_default();
                    let matched = port_connectors
                        .iter()
                        .find(|c| c.interface.rsplit('.').next() == Some(simple.as_str()))
                        .map_or_else(|| cid_name.text(), |c| c.name.clone());
                    connectors.insert(cid_name.text(), matched);
                }
                ports.insert(pi_name.text(), (port.text(), connectors));
            }
            instances.insert(name, (infos, ports));
        }
        // Bindings: `[source portInstance.connector ==> target instance.portInstance.connector]`,
        // allowed only where the component diagram connects the two ports' connectors.
        for instance in diagram.instances() {
            let Some(owner) = instance.name().map(|n| n.text()) else { continue };
            for binding in instance.bindings().chain(Vec::new()) {
                let ends: Vec<Option<(String, String)>> = [binding.source(), binding.target()]
                    .into_iter()
                    .flatten()
                    .map(|end| {
                        let segments: Vec<String> = end.segments().map(|s| s.text()).collect();
                        let (inst, pi, connector) = match segments.as_slice() {
                            [pi, c] => (owner.clone(), pi.clone(), c.clone()),
                            [inst, pi, c] => (inst.clone(), pi.clone(), c.clone()),
                            _ => {
                                self.report(
                                    DiagnosticCode::UnresolvedConnector,
                                    end.syntax().text_range(),
                                    "a binding end is `portInstance.connector` or `instance.portInstance.connector`"
                                        .to_string(),
                                );
                                return None;
                            }
                        };
                        let Some((_, ports)) = instances.get(&inst) else {
                            self.report(
                                DiagnosticCode::UnresolvedConnector,
                                end.syntax().text_range(),
                                format!("no instance `{inst}` in this diagram"),
                            );
                            return None;
                        };
                        let Some((port, connectors)) = ports.get(&pi) else {
                            self.report(
                                DiagnosticCode::UnresolvedConnector,
                                end.syntax().text_range(),
                                format!("instance `{inst}` has no port instance `{pi}`"),
                            );
                            return None;
                        };
                        let connector = connectors.get(&connector).cloned().unwrap_or(connector);
                        Some((port.clone(), connector))
                    })
                    .collect();
                if let [Some((sp, sc)), Some((tp, tc))] = ends.as_slice() {
                    let allowed = instances.values().flat_map(|(infos, _)| infos.iter()).any(|info| {
                        info.item.connections.iter().any(|c| {
                            let forward = c.source == format!("{sp}.{sc}") && c.target == format!("{tp}.{tc}");
                            let backward = c.source == format!("{tp}.{tc}") && c.target == format!("{sp}.{sc}");
                            forward || backward
                        })
                    });
                    if !allowed {
                        self.report(
                            DiagnosticCode::BindingNotAllowed,
                            binding.syntax().text_range(),
                            format!("no connection in the component diagram joins `{sp}.{sc}` and `{tp}.{tc}`"),
                        );
                    }
                }
            }
        }
    }

    /// The component an instance instantiates; checks its field values on the way.
    fn instance_component(
        &mut self,
        scope: &Scope,
        instance: &ast::ComponentInstance,
        path: &ast::Path,
    ) -> &'db [ComponentInfo] {
        let text = path.text();
        let range = path.syntax().text_range();
        let Some(def) = self.resolve(scope, &text) else {
            self.report(DiagnosticCode::InvalidComponent, range, format!("unknown component `{text}`"));
            return &[];
        };
        let infos = component_info(self.db, self.workspace, Fqn::new(self.db, def.fqn.clone())).as_slice();
        if infos.is_empty() {
            self.report(
                DiagnosticCode::InvalidComponent,
                range,
                format!("`{}` is not a component of any component diagram", def.fqn),
            );
            return infos;
        }
        if matches!(def.kind, DefKind::Type(_)) {
            for value in instance.field_values() {
                let Some(field) = value.name() else { continue };
                let name = field.text();
                // The field may be inherited; its type is resolved where it is declared.
                let found = self.find_member(&def.fqn, &mut HashSet::new(), &|ty| {
                    ty.fields.iter().find(|f| f.name == name).map(|f| f.ty.clone())
                });
                let Some((declaring, field_sig)) = found else {
                    self.report(
                        DiagnosticCode::UnknownInstanceField,
                        field.syntax().text_range(),
                        format!("component class `{}` has no field `{name}`", def.fqn),
                    );
                    continue;
                };
                let Some(expr) = value.value() else { continue };
                let declaring_scope = self.scope_of(declaring);
                let field_ty = ty::from_signature(&field_sig, &mut |path| {
                    self.resolve(&declaring_scope, path).map(|d| d.fqn.clone())
                });
                let mut typing = Body { checker: self, scope: scope.clone(), locals: HashMap::new(), owner: None };
                let value_ty = typing.infer(&expr);
                if !value_ty.assignable_to(&field_ty, &mut |a, b| self.is_subtype(a, b)) {
                    self.report(
                        DiagnosticCode::TypeMismatch,
                        expr.syntax().text_range(),
                        format!("field `{name}` of `{}` has type `{field_ty}`, but the value is `{value_ty}`", def.fqn),
                    );
                }
            }
        }
        infos
    }

    fn loop_window_sections(&mut self, node: &ast::ActivityNode) {
        let Some(header) = node.loop_header() else { return };
        let counts: Vec<usize> = header.sections().map(|s| s.parts().count()).collect();
        if counts.len() != 3 || counts.windows(2).any(|w| w[0] != w[1]) {
            self.report(
                DiagnosticCode::LoopWindowMismatch,
                header.syntax().text_range(),
                format!(
                    "a loopWindow needs as many tests and increments as setups (setup; test; increment), found {}",
                    counts.iter().map(|c| c.to_string()).collect::<Vec<_>>().join("; ")
                ),
            );
        }
    }

    // ---- activity diagrams

    fn owner(&mut self, scope: &Scope, path: &ast::Path) {
        let text = path.text();
        let range = path.syntax().text_range();
        match self.resolve(scope, &text).map(|d| &d.kind) {
            Some(DefKind::Type(ty)) if matches!(ty.kind, TypeKind::Class(_)) => {}
            Some(other) => self.report(
                DiagnosticCode::OwnerNotAClass,
                range,
                format!("the owner `{text}` is {}; an owner must be a class", describe(other)),
            ),
            None => self.report(DiagnosticCode::UnresolvedOwner, range, format!("unknown owner class `{text}`")),
        }
    }

    fn activity(&mut self, scope: &Scope, diagram: &ast::ActivityDiagram) {
        self.params(scope, diagram.param_list());
        if let Some(owner) = diagram.owner() {
            self.owner(scope, &owner);
        }
        let variable_names =
            diagram.variables().filter_map(|v| v.name()).chain(diagram.var_decls().filter_map(|v| v.name()));
        self.duplicates(variable_names, "variable");
        for variable in diagram.variables() {
            if let Some(ty) = variable.type_ref() {
                self.type_ref(scope, &ty);
            }
            if let Some(init) = variable.initializer() {
                self.expressions(scope, init.syntax());
            }
        }
        for decl in diagram.var_decls() {
            self.expressions(scope, decl.syntax());
        }
        let mut nodes: Vec<ast::ActivityNode> = Vec::new();
        self.duplicates(diagram.swimlanes().filter_map(|s| s.name()), "swimlane");
        for lane in diagram.swimlanes() {
            if let Some(owner) = lane.owner() {
                self.owner(scope, &owner);
            }
            nodes.extend(lane.nodes());
        }
        nodes.extend(diagram.nodes());
        self.duplicates(nodes.iter().filter_map(|n| n.name()), "node");
        // Locals every node sees: the diagram's parameters and variables.
        let mut diagram_locals: Vec<(String, Option<ast::TypeRef>)> =
            diagram.params().filter_map(|p| Some((p.name()?.text(), p.type_ref()))).collect();
        diagram_locals.extend(diagram.variables().filter_map(|v| Some((v.name()?.text(), v.type_ref()))));
        diagram_locals.extend(diagram.var_decls().filter_map(|v| Some((v.name()?.text(), v.type_ref()))));
        for node in &nodes {
            if node.kind() == ast::NodeKind::LoopWindow {
                self.loop_window_sections(node);
            }
            self.params(scope, node.param_list());
            if let Some(body) = node.body() {
                self.expressions(scope, body.syntax());
                let owner = self.owner_at(body.syntax());
                let mut typing = Body { checker: self, scope: scope.clone(), locals: HashMap::new(), owner };
                for (name, ty) in diagram_locals.iter().cloned().chain(header_declarations(node)) {
                    typing.declare(name, ty);
                }
                typing.check(body.syntax());
            }
        }
        self.flow(diagram, &nodes);
    }

    /// Start nodes, transition targets and arities, reachability and paths to a final node.
    fn flow(&mut self, diagram: &ast::ActivityDiagram, nodes: &[ast::ActivityNode]) {
        let by_name: HashMap<String, &ast::ActivityNode> =
            nodes.iter().filter_map(|n| Some((n.name()?.text(), n))).rev().collect();
        let starts: Vec<&ast::ActivityNode> = nodes.iter().filter(|n| n.kind() == ast::NodeKind::Start).collect();
        let diagram_name = diagram.name().map(|n| n.text()).unwrap_or_default();
        let header_range = diagram.name().map_or_else(|| diagram.syntax().text_range(), |n| n.syntax().text_range());
        if starts.is_empty() && !nodes.is_empty() {
            self.report(
                DiagnosticCode::MissingStartNode,
                header_range,
                format!("activity diagram `{diagram_name}` has no start node: add `start S {{ => first; }}`"),
            );
        }
        for extra in starts.iter().skip(1) {
            let range = extra.name().map_or_else(|| extra.syntax().text_range(), |n| n.syntax().text_range());
            self.report(
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
                    self.report(
                        DiagnosticCode::UnresolvedTransitionTarget,
                        target.syntax().text_range(),
                        format!("no node `{target_name}` in activity diagram `{diagram_name}`"),
                    );
                    continue;
                };
                edges.entry(source.clone()).or_default().push(target_name.clone());
                self.transition_arity(&transition, &target, target_node);
            }
        }
        // Reachability from the start node(s).
        let reachable = reach(starts.iter().filter_map(|s| s.name().map(|n| n.text())), &edges);
        if !starts.is_empty() {
            for node in nodes {
                let Some(name) = node.name() else { continue };
                if !reachable.contains(&name.text()) {
                    self.warn(
                        DiagnosticCode::UnreachableNode,
                        name.syntax().text_range(),
                        format!("node `{}` is never reached from the start node", name.text()),
                    );
                }
            }
        }
        // A final node must be reachable from every reachable node.
        let finals: Vec<String> = nodes
            .iter()
            .filter(|n| n.kind() == ast::NodeKind::Final)
            .filter_map(|n| n.name().map(|n| n.text()))
            .collect();
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
                self.warn(
                    DiagnosticCode::NoPathToFinal,
                    name.syntax().text_range(),
                    format!("no path leads from node `{}` to a final node", name.text()),
                );
            }
        }
    }

    /// A transition passes the target's parameters, after the work size of a calc node
    /// (3 dimensions) or the ranges of a calcRange node (global then local range: 2, 4 or 6
    /// values for 1, 2 or 3 dimensions; Listing 32 passes 4).
    fn transition_arity(&mut self, transition: &ast::Transition, target: &ast::NameRef, node: &ast::ActivityNode) {
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
            self.report(
                DiagnosticCode::TransitionArity,
                range,
                format!("node `{}` takes {}{what}, {given} given", target.text(), arguments(expected)),
            );
        }
    }
}

/// `1 argument`, `3 arguments`.
pub(crate) fn arguments(n: usize) -> String {
    format!("{n} argument{}", if n == 1 { "" } else { "s" })
}

/// The message-ready name of a connector role.
fn role_name(role: ConnectorRole) -> &'static str {
    match role {
        ConnectorRole::Provider => "provider",
        ConnectorRole::Processor => "processor",
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

fn describe(kind: &DefKind) -> &'static str {
    match kind {
        DefKind::ClassDiagram => "a class diagram",
        DefKind::ComponentDiagram => "a component diagram",
        DefKind::ComponentInstanceDiagram => "a component-instance diagram",
        DefKind::Activity(_) => "an activity diagram",
        DefKind::Type(ty) => match ty.kind {
            TypeKind::Class(_) => "a class",
            TypeKind::Interface(_) => "an interface",
            TypeKind::Enum => "an enum",
            TypeKind::Attribute => "an attribute",
        },
    }
}

/// GPU and OpenCL built-in type names of chapter 10 that are written as identifiers:
/// `(u)char|short|int|long|float|double` with n ∈ {2,3,4,8,16} (and the scalar `uchar`…),
/// `image2D_t`, `image3D_t`, `buffer2D_tn`, `buffer3D_tn`, `sampler_t`.
pub fn is_builtin_type_name(name: &str) -> bool {
    const SCALARS: [&str; 6] = ["char", "short", "int", "long", "float", "double"];
    const SUFFIXES: [&str; 10] = ["c", "uc", "s", "us", "i", "ui", "l", "ul", "f", "d"];
    const WIDTHS: [&str; 5] = ["2", "3", "4", "8", "16"];
    if name == "sampler_t" {
        return true;
    }
    let vector =
        |rest: &str| SCALARS.iter().any(|s| rest.strip_prefix(s).is_some_and(|n| n.is_empty() || WIDTHS.contains(&n)));
    if vector(name) || name.strip_prefix('u').is_some_and(|r| r.starts_with(['c', 's', 'i', 'l']) && vector(r)) {
        return true;
    }
    for prefix in ["image2D_", "image3D_"] {
        if name.strip_prefix(prefix).is_some_and(|t| SUFFIXES.contains(&t)) {
            return true;
        }
    }
    for prefix in ["buffer2D_", "buffer3D_"] {
        if let Some(rest) = name.strip_prefix(prefix) {
            if SUFFIXES.iter().any(|s| rest.strip_prefix(s).is_some_and(|n| WIDTHS.contains(&n))) {
                return true;
            }
        }
    }
    false
}

#[cfg(test)]
mod tests {
    #[test]
    fn gpu_type_names() {
        for yes in [
            "float4",
            "uchar16",
            "int2",
            "uint",
            "double8",
            "image2D_uc",
            "image3D_f",
            "buffer2D_ui4",
            "buffer3D_d16",
            "sampler_t",
        ] {
            assert!(super::is_builtin_type_name(yes), "{yes}");
        }
        for no in ["float5", "image2D_x", "buffer2D_f", "Image", "uchar5", "ufloat4"] {
            assert!(!super::is_builtin_type_name(no), "{no}");
        }
    }
}
