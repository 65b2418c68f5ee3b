//! `Semantics`: the one read-only API through which everything above the item tree asks what the
//! model means: what a name resolves to, which members a type has (inherited ones too), which
//! class owns a body, what a signature's type is, which components a class is, and where a
//! definition is declared. Validation, editor features, the graph view and code generation all
//! ask here; none of them resolves names on its own.
//!
//! Cross-file answers go through the per-name [`lookup`](super::definitions::lookup) query, so
//! a caller depends on exactly the names it asks about. Expression types are answered in
//! `infer.rs` ([`Semantics::type_of_expr`]), name classification for the editor in
//! `classify.rs`.

use std::collections::{BTreeMap, BTreeSet, HashSet};

use super::{
    components::{component_info, processor_signatures, ComponentInfo},
    definitions::{
        def_map, definitions_named, namespace_definitions, type_names_in_bucket, types_named, DefKind, DefMap,
        Definition, Fqn, TYPE_NAME_BUCKETS,
    },
    items::{ClassKind, MethodSignature, TypeItem, TypeKind, TypeSignature},
    scope::Scope,
    ty::{self, Ty},
};
use crate::{
    ast::{self, AstNode, HasName},
    db::{parse, Db, SourceFile, Workspace},
    library::{is_library, COMPONENT_BASE},
    syntax::{SyntaxNode, TextRange},
};

/// Answers about the workspace's model, for one snapshot of the database.
#[derive(Clone, Copy)]
pub struct Semantics<'db> {
    db: &'db dyn Db,
    workspace: Workspace,
}

impl<'db> Semantics<'db> {
    pub fn new(db: &'db dyn Db, workspace: Workspace) -> Semantics<'db> {
        Semantics { db, workspace }
    }

    pub fn db(&self) -> &'db dyn Db {
        self.db
    }

    pub fn workspace(&self) -> Workspace {
        self.workspace
    }

    // ---- names

    /// Every definition of the workspace, for listings (completion, symbol search, "did you
    /// mean"). Resolving one name goes through [`Semantics::resolve`], which depends on that
    /// name only.
    pub fn def_map(&self) -> &'db DefMap {
        def_map(self.db, self.workspace)
    }

    /// The diagrams `file` declares (nested ones included): what a per-file feature reads
    /// instead of [`Semantics::def_map`], so that it runs again only when this file changes.
    pub fn file_diagrams(&self, file: SourceFile) -> impl Iterator<Item = &'db Definition> + 'db {
        super::definitions::file_diagrams(self.db, file).iter().map(|(_, def)| def)
    }

    /// Every definition of a fully qualified name (several when it is declared twice).
    pub fn lookup(&self, fqn: &str) -> &'db [Definition] {
        definitions_named(self.db, self.workspace, fqn)
    }

    /// Whether `fqn` is declared in more than one file (without a `lookup` memo of its own).
    pub fn declared_in_several_files(&self, fqn: &str) -> bool {
        let (namespace, last) = fqn.rsplit_once('.').unwrap_or(("", fqn));
        let namespace = Fqn::new(self.db, namespace.to_string());
        super::definitions::names_declared_in_several_files(self.db, self.workspace, namespace).contains(last)
    }

    /// What a namespace declares directly, by last name segment (for listings of a namespace).
    pub fn namespace_members(&self, namespace: &str) -> &'db BTreeMap<String, Vec<Definition>> {
        namespace_definitions(self.db, self.workspace, Fqn::new(self.db, namespace.to_string()))
    }

    /// Every simple type name of the workspace with the fully qualified names of its types, in
    /// no particular order (for listings; read bucket by bucket, so a rename elsewhere costs a
    /// listing one bucket, not the whole index).
    pub fn types_by_simple_name(&self) -> impl Iterator<Item = (&'db String, &'db Vec<String>)> + 'db {
        let (db, workspace) = (self.db, self.workspace);
        (0..TYPE_NAME_BUCKETS).flat_map(move |bucket| type_names_in_bucket(db, workspace, bucket))
    }

    /// The (first) definition of a fully qualified name.
    pub fn definition(&self, fqn: &str) -> Option<&'db Definition> {
        self.lookup(fqn).first()
    }

    /// Resolves a (possibly qualified) name from `scope`: enclosing namespaces innermost first,
    /// then imports, then the name as a fully qualified one.
    ///
    /// A simple name that none of these finds names the workspace's only type of that name, if
    /// there is exactly one (the dissertation's listings use other diagrams' types unqualified);
    /// a type of the bundled library counts only if the user's files declare none.
    pub fn resolve(&self, scope: &Scope, path: &str) -> Option<&'db Definition> {
        if let Some(fqn) = scope.candidate(path, |c| !self.lookup(c).is_empty()) {
            return self.definition(&fqn);
        }
        if path.contains('.') {
            return None;
        }
        match self.candidates(path) {
            [only] => self.definition(only),
            [] => None,
            several => {
                // The workspace's own type wins over the bundled library's of the same name.
                let mut own =
                    several.iter().filter_map(|fqn| self.definition(fqn)).filter(|d| !is_library(self.db, d.file));
                match (own.next(), own.next()) {
                    (Some(only), None) => Some(only),
                    _ => None,
                }
            }
        }
    }

    /// What a qualified name means where it is written.
    pub fn resolve_path(&self, path: &ast::Path) -> Option<&'db Definition> {
        self.resolve(&Scope::at(path.syntax()), &path.text())
    }

    /// What a path means up to and including `segment` (`A.B` for `B` in `A.B.C`).
    pub fn resolve_path_segment(&self, path: &ast::Path, segment: &ast::NameRef) -> Option<&'db Definition> {
        let mut prefix = Vec::new();
        for s in path.segments() {
            prefix.push(s.text());
            if s.syntax() == segment.syntax() {
                break;
            }
        }
        self.resolve(&Scope::at(path.syntax()), &prefix.join("."))
    }

    /// The fully qualified names of the types a simple name could mean (all types of that name;
    /// none for a qualified name), for "ambiguous" messages and fixes.
    pub fn candidates(&self, path: &str) -> &'db [String] {
        if path.contains('.') {
            return &[];
        }
        types_named(self.db, self.workspace, Fqn::new(self.db, path.to_string()))
    }

    /// The type a signature denotes, its names resolved from `scope`.
    pub fn ty(&self, signature: &TypeSignature, scope: &Scope) -> Ty {
        ty::from_signature(signature, &mut |path| self.resolve(scope, path).map(|d| d.fqn.clone()))
    }

    // ---- types and members

    /// The types `def` extends or implements, resolved where it is declared; a component class
    /// also implements the library's [`COMPONENT_BASE`] (its `init`, `process`, `cleanup`).
    pub fn bases(&self, def: &'db Definition) -> Vec<&'db Definition> {
        let DefKind::Type(ty) = &def.kind else { return Vec::new() };
        let scope = Scope::of(def);
        let mut bases: Vec<&'db Definition> = ty
            .extends
            .iter()
            .chain(&ty.implements)
            .filter_map(|b| b.path.as_deref())
            .filter_map(|base| self.resolve(&scope, base))
            .collect();
        if matches!(ty.kind, TypeKind::Class(ClassKind::Source | ClassKind::Filter | ClassKind::Sink)) {
            bases.extend(self.definition(COMPONENT_BASE));
        }
        bases
    }

    /// Whether type `sub` is `sup` or derives from it (`extends`/`implements`, transitively).
    pub fn is_subtype(&self, sub: &str, sup: &str) -> bool {
        let mut seen = HashSet::new();
        let mut stack = vec![sub.to_string()];
        while let Some(fqn) = stack.pop() {
            if fqn == sup {
                return true;
            }
            if !seen.insert(fqn.clone()) {
                continue;
            }
            if let Some(def) = self.definition(&fqn) {
                stack.extend(self.bases(def).into_iter().map(|b| b.fqn.clone()));
            }
        }
        false
    }

    /// Finds, in type `fqn` or its bases (depth first, in declaration order), the first member
    /// `pick` returns, with the type that declares it.
    pub fn find_member<T>(&self, fqn: &str, pick: &dyn Fn(&TypeItem) -> Option<T>) -> Option<(&'db Definition, T)> {
        self.find_member_in(fqn, &mut HashSet::new(), pick)
    }

    fn find_member_in<T>(
        &self,
        fqn: &str,
        seen: &mut HashSet<String>,
        pick: &dyn Fn(&TypeItem) -> Option<T>,
    ) -> Option<(&'db Definition, T)> {
        if !seen.insert(fqn.to_string()) {
            return None;
        }
        let def = self.definition(fqn)?;
        let DefKind::Type(ty) = &def.kind else { return None };
        if let Some(found) = pick(ty) {
            return Some((def, found));
        }
        self.bases(def).into_iter().find_map(|base| self.find_member_in(&base.fqn, seen, pick))
    }

    /// The type of field `name` of type `fqn` (or its bases), resolved where it is declared; an
    /// enum's values are of the enum. `None` if the type has no such member.
    pub fn field_ty(&self, fqn: &str, name: &str) -> Option<Ty> {
        let found = self.find_member(fqn, &|ty| ty.fields.iter().find(|f| f.name == name).map(|f| f.ty.clone()));
        let Some((declaring, field)) = found else {
            return match self.definition(fqn).map(|d| &d.kind) {
                Some(DefKind::Type(ty)) if ty.kind == TypeKind::Enum && ty.enum_values.iter().any(|v| v == name) => {
                    Some(Ty::Named(fqn.to_string()))
                }
                _ => None,
            };
        };
        Some(self.ty(&field, &Scope::of(declaring)))
    }

    /// The number of the constant `member` of the enum `fqn`, as C numbers it: the value written
    /// (`A = 4`, `B = -1`), else one more than the constant before (the first is 0). `None` if
    /// `fqn` is no enum with that constant.
    pub fn enum_value(&self, fqn: &str, member: &str) -> Option<i64> {
        let (node, _) = self.declaration(self.definition(fqn)?)?;
        let ast::TypeDecl::Enum(decl) = ast::TypeDecl::cast(node)? else { return None };
        let mut next = 0i64;
        for constant in decl.values() {
            let value = constant.value().and_then(|value| constant_number(&value)).unwrap_or(next);
            if constant.name().is_some_and(|name| name.text() == member) {
                return Some(value);
            }
            next = value.wrapping_add(1);
        }
        None
    }

    /// The type declaring field `name` of `fqn` (or of a base), if that field is `const`.
    pub fn const_field(&self, fqn: &str, name: &str) -> Option<&'db str> {
        let found =
            self.find_member(fqn, &|ty| ty.fields.iter().find(|f| f.name == name).map(|f| f.qualifiers.clone()));
        let (declaring, qualifiers) = found?;
        qualifiers.iter().any(|q| q == "const").then_some(declaring.fqn.as_str())
    }

    /// The names of the fields (`fields`) or methods of type `fqn` and its bases, and an
    /// enum's values with its fields, for "did you mean".
    pub fn member_names(&self, fqn: &str, fields: bool) -> Vec<String> {
        let Some(def) = self.definition(fqn) else { return Vec::new() };
        let mut names = Vec::new();
        for def in self.type_and_bases(def) {
            let DefKind::Type(ty) = &def.kind else { continue };
            if fields {
                names.extend(ty.fields.iter().map(|f| f.name.clone()));
                names.extend(ty.enum_values.iter().cloned());
            } else {
                names.extend(ty.methods.iter().map(|m| m.name.clone()));
            }
        }
        names
    }

    /// Whether type `fqn` (or a base) declares a method `name`.
    pub fn has_method(&self, fqn: &str, name: &str) -> bool {
        self.find_member(fqn, &|ty| ty.methods.iter().any(|m| m.name == name).then_some(())).is_some()
    }

    /// Every overload of `name` in `def` and its bases, with the type that declares it.
    pub fn methods(&self, def: &'db Definition, name: &str) -> Vec<(&'db Definition, MethodSignature)> {
        let mut out = Vec::new();
        self.collect_methods(def, name, &mut HashSet::new(), &mut out);
        out
    }

    /// The declarations of the methods `name` with `arity` parameters of `def` and its bases,
    /// with the type that declares each (what a call `name(…)` in a body of `def` may reach).
    pub fn method_declarations(
        &self,
        def: &'db Definition,
        name: &str,
        arity: usize,
    ) -> Vec<(&'db Definition, ast::Method)> {
        let mut classes: Vec<&'db Definition> = Vec::new();
        for (class, signature) in self.methods(def, name) {
            if signature.params.len() == arity && !classes.iter().any(|c| c.fqn == class.fqn) {
                classes.push(class);
            }
        }
        let mut out = Vec::new();
        for class in classes {
            let Some(decl) = self.declaration(class).and_then(|(node, _)| ast::TypeDecl::cast(node)) else { continue };
            for member in decl.members() {
                if let ast::Member::Method(method) = member {
                    if method.name().is_some_and(|n| n.text() == name) && method.params().count() == arity {
                        out.push((class, method));
                    }
                }
            }
        }
        out
    }

    fn collect_methods(
        &self,
        def: &'db Definition,
        name: &str,
        seen: &mut HashSet<String>,
        out: &mut Vec<(&'db Definition, MethodSignature)>,
    ) {
        if !seen.insert(def.fqn.clone()) {
            return;
        }
        let DefKind::Type(ty) = &def.kind else { return };
        out.extend(ty.methods.iter().filter(|m| m.name == name).map(|m| (def, m.clone())));
        for base in self.bases(def) {
            self.collect_methods(base, name, seen, out);
        }
    }

    /// `def` and every type it derives from, each once.
    pub fn type_and_bases(&self, def: &'db Definition) -> Vec<&'db Definition> {
        let mut seen = HashSet::new();
        let mut stack = vec![def];
        let mut out = Vec::new();
        while let Some(def) = stack.pop() {
            if seen.insert(def.fqn.clone()) {
                out.push(def);
                stack.extend(self.bases(def));
            }
        }
        out
    }

    /// Whether a type implements (directly or through its bases) the `OpenCL` interface: its
    /// methods and activity diagrams are device code (chapter 10.3.2.3).
    pub fn implements_opencl(&self, scope: &Scope, bases: impl Iterator<Item = ast::TypeRef>) -> bool {
        let mut seen = HashSet::new();
        bases
            .filter_map(|t| t.path())
            .any(|p| self.resolve(scope, &p.text()).is_some_and(|d| self.reaches_opencl(d, &mut seen)))
    }

    /// Whether a class is a GPU class: it implements `OpenCL`, directly or through its bases.
    pub fn is_gpu_class(&self, def: &'db Definition) -> bool {
        self.reaches_opencl(def, &mut HashSet::new())
    }

    fn reaches_opencl(&self, def: &'db Definition, seen: &mut HashSet<String>) -> bool {
        if def.fqn.rsplit('.').next() == Some("OpenCL") {
            return true;
        }
        if !matches!(def.kind, DefKind::Type(_)) || !seen.insert(def.fqn.clone()) {
            return false;
        }
        self.bases(def).into_iter().any(|base| self.reaches_opencl(base, seen))
    }

    // ---- activity diagrams

    /// The class whose members a body at `node` sees: its swimlane's owner, else its activity
    /// diagram's owner, else the class the body belongs to.
    pub fn owner_at(&self, node: &SyntaxNode) -> Option<&'db Definition> {
        let scope = Scope::at(node);
        if let Some(diagram) = node.ancestors().find_map(ast::ActivityDiagram::cast) {
            let lane = node.ancestors().find_map(ast::Swimlane::cast);
            return self.activity_owner(&scope, &diagram, lane.as_ref());
        }
        let class = node.ancestors().find_map(ast::TypeDecl::cast)?;
        self.definition(&scope.qualify(&class.name()?.text())).filter(|d| matches!(d.kind, DefKind::Type(_)))
    }

    /// The class whose members the nodes of `lane` (or, without one, the diagram's own nodes)
    /// see: the swimlane's owner, else the diagram's. A checker asks once per swimlane, not per
    /// node: finding an absent owner reads every child of the diagram.
    pub fn activity_owner(
        &self,
        scope: &Scope,
        diagram: &ast::ActivityDiagram,
        lane: Option<&ast::Swimlane>,
    ) -> Option<&'db Definition> {
        let resolve_owner = |path: Option<ast::Path>| path.and_then(|p| self.resolve(scope, &p.text()));
        lane.and_then(|lane| resolve_owner(lane.owner()))
            .or_else(|| resolve_owner(diagram.owner()))
            .filter(|d| matches!(d.kind, DefKind::Type(_)))
    }

    /// The classes that own the activity diagram `def` or one of its swimlanes, as its
    /// signature names them; empty for other definitions.
    pub fn activity_owners(&self, def: &Definition) -> Vec<&'db Definition> {
        let DefKind::Activity(signature) = &def.kind else { return Vec::new() };
        let scope = Scope::of(def);
        let owners = signature.owner.iter().chain(signature.swimlanes.iter().filter_map(|lane| lane.owner.as_ref()));
        owners.filter_map(|owner| self.resolve(&scope, owner)).collect()
    }

    // ---- components

    /// The components built on the class `class` (a fully qualified name); empty if none.
    pub fn components(&self, class: &str) -> &'db [ComponentInfo] {
        component_info(self.db, self.workspace, Fqn::new(self.db, class.to_string()))
    }

    /// The connections each component diagram declares, by diagram.
    pub fn diagram_connections(&self) -> &'db BTreeMap<String, BTreeSet<(String, String)>> {
        super::components::diagram_connections(self.db, self.workspace)
    }

    /// The `process…` signatures of every processor interface, as `signature_key`s.
    pub fn processor_signatures(&self) -> &'db BTreeSet<String> {
        processor_signatures(self.db, self.workspace)
    }

    // ---- sources

    /// The declaration node of a definition and the range of its name, found by walking its
    /// file's tree along the fully qualified name.
    pub fn declaration(&self, def: &Definition) -> Option<(SyntaxNode, TextRange)> {
        let root = parse(self.db, def.file).syntax_node();
        let mut candidates: Vec<SyntaxNode> = vec![root];
        let mut found: Option<(SyntaxNode, TextRange)> = None;
        for segment in def.fqn.split('.') {
            let mut next = Vec::new();
            for parent in &candidates {
                for child in parent.children() {
                    let name = match ast::Diagram::cast(child.clone()) {
                        Some(d) => d.name(),
                        None => ast::TypeDecl::cast(child.clone()).and_then(|t| t.name()),
                    };
                    if let Some(name) = name.filter(|n| n.text() == segment) {
                        found = Some((child.clone(), name.syntax().text_range()));
                        next.push(child);
                    }
                }
            }
            if next.is_empty() {
                return None;
            }
            candidates = next;
        }
        found
    }

    /// The declaration of member `name` (field, method or association) of the type `owner`.
    pub fn member_declaration(&self, owner: &Definition, name: &str) -> Option<ast::Member> {
        let (node, _) = self.declaration(owner)?;
        ast::TypeDecl::cast(node)?.members().find(|m| m.name().is_some_and(|n| n.text() == name))
    }
}

/// An enum constant's written value: an integer literal, negated or not.
fn constant_number(value: &ast::Expr) -> Option<i64> {
    match value {
        ast::Expr::Literal(literal) => match literal.value()? {
            ast::LiteralValue::Int { value, .. } => i64::try_from(value).ok(),
            _ => None,
        },
        ast::Expr::PrefixExpr(prefix) if prefix.op()?.kind() == crate::syntax::SyntaxKind::MINUS => {
            constant_number(&prefix.operand()?).map(i64::wrapping_neg)
        }
        ast::Expr::ParenExpr(inner) => constant_number(&inner.expr()?),
        _ => None,
    }
}

/// How a definition reads in a message: "a class", "an activity diagram".
pub fn describe(kind: &DefKind) -> &'static str {
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
