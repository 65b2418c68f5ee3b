//! Expression typing inside method and node bodies: enough to check guards and conditions,
//! assignments and initialisers, and the arity and argument types of calls that resolve to a
//! declared method. Names it cannot type are `Unknown` and never cause a diagnostic of their own.
//!
//! An [`InferenceCtx`] reads the model through [`Semantics`] and reports into a [`Diagnostics`]
//! sink; [`Semantics::type_of_expr`] runs it with a sink nobody reads.

mod calls;
mod locals;
mod operators;
mod places;
mod statements;

pub use locals::{diagram_locals, header_declarations};
pub use places::BodyRole;
use places::CallForm;
use statements::DeclQualifiers;
pub use statements::{implementing_behavior, misplaced_jumps, returns_on_every_path};

use std::collections::{HashMap, HashSet};

use super::{
    definitions::{DefKind, Definition},
    diagnostics::{DiagnosticCode, Diagnostics},
    items::type_signature,
    scope::Scope,
    semantics::Semantics,
    spelling::closest,
    ty::Ty,
};
use crate::{
    ast::{self, AstNode, HasName, LiteralValue},
    syntax::{SyntaxKind, SyntaxNode, TextRange, TextSize},
};

/// Typing context of one body: local names, and the class whose members are in scope.
pub struct InferenceCtx<'a, 'db> {
    sema: Semantics<'db>,
    sink: &'a mut Diagnostics,
    scope: Scope,
    locals: HashMap<String, Ty>,
    /// The locals and parameters declared `const`.
    constants: HashSet<String>,
    /// The image parameters declared `read` or `write` (the keyword's kind).
    access: HashMap<String, SyntaxKind>,
    /// The parameters declared `shared`: work-group memory, indexed like an array.
    shared_memory: HashSet<String>,
    /// Where the body's own `var`s are declared (the name's start) and the statement they are
    /// in scope in (a block, a `for`, the body), by name: a use must come after and within.
    declared_in: HashMap<String, Vec<(TextSize, TextRange)>>,
    /// The method whose body this is and its return type, for `return` statements.
    returns: Option<(String, Ty)>,
    /// The nodes of the activity diagram, by name: what a transition's arguments must fit.
    nodes: Option<&'a HashMap<String, ast::ActivityNode>>,
    owner: Option<&'db Definition>,
    /// What the body is: a `global` method's, a calc node's, another.
    role: BodyRole,
    /// The type of every expression inferred, when asked for ([`Semantics::body_types`]).
    record: Option<HashMap<ExprKey, Ty>>,
}

/// An expression by its syntax kind and range (unique within a file).
type ExprKey = (SyntaxKind, TextRange);

/// The types of the expressions of one body (an activity node's, with its header, guards and
/// transitions; a method's; a diagram's variable section) and of its locals, as the checks saw
/// them: what a code generator reads.
#[derive(Debug, Default, Clone, PartialEq, Eq)]
pub struct BodyTypes {
    exprs: HashMap<ExprKey, Ty>,
    /// Parameters, diagram variables and the body's own `var`s.
    pub locals: HashMap<String, Ty>,
}

impl BodyTypes {
    /// The type of `expr`; `Unknown` for one outside the body.
    pub fn of(&self, expr: &ast::Expr) -> &Ty {
        self.exprs.get(&(expr.syntax().kind(), expr.syntax().text_range())).unwrap_or(&Ty::Unknown)
    }
}

impl<'a, 'db> InferenceCtx<'a, 'db> {
    /// A context for a body in `scope` whose members are those of `owner`.
    pub fn new(
        sema: Semantics<'db>,
        sink: &'a mut Diagnostics,
        scope: Scope,
        owner: Option<&'db Definition>,
    ) -> InferenceCtx<'a, 'db> {
        InferenceCtx {
            sema,
            sink,
            scope,
            locals: HashMap::new(),
            constants: HashSet::new(),
            access: HashMap::new(),
            shared_memory: HashSet::new(),
            declared_in: HashMap::new(),
            returns: None,
            nodes: None,
            owner,
            role: BodyRole::Ordinary,
            record: None,
        }
    }

    /// Declares a local (parameter, variable) from its written type (`const` if its
    /// declaration says so).
    pub fn declare(&mut self, name: String, ty: Option<ast::TypeRef>) {
        let qualifiers = ty.as_ref().map(DeclQualifiers::of).unwrap_or_default();
        if qualifiers.is_const {
            self.constants.insert(name.clone());
        } else {
            self.constants.remove(&name);
        }
        if qualifiers.is_shared {
            self.shared_memory.insert(name.clone());
        } else {
            self.shared_memory.remove(&name);
        }
        match qualifiers.access {
            Some(access) => self.access.insert(name.clone(), access),
            None => self.access.remove(&name),
        };
        let ty = self.ty_of(ty);
        self.locals.insert(name, ty);
    }

    /// A value given where a declaration of type `ty` is initialised (a field's `= value`, an
    /// attribute field's, an enum value's): typed, and it must fit.
    pub fn check_value(&mut self, ty: &Ty, value: &ast::Expr, what: &str) {
        let value_ty = self.infer(value);
        self.expect_assignable(&value_ty, ty, value.syntax(), what);
    }

    /// The type written at `ty`, in this context's scope.
    pub fn written_type(&self, ty: Option<ast::TypeRef>) -> Ty {
        self.ty_of(ty)
    }

    /// The body is a node of a diagram with these nodes (by name): transitions' arguments are checked
    /// against their targets' parameters (and a calc node's work sizes are integers).
    pub fn expect_transitions_to(&mut self, nodes: &'a HashMap<String, ast::ActivityNode>) {
        self.nodes = Some(nodes);
    }

    /// The body is method `name`'s, which returns `ty`: `return` statements are checked.
    pub fn expect_returns(&mut self, name: String, ty: Option<ast::TypeRef>) {
        let ty = self.ty_of(ty);
        self.returns = Some((name, ty));
    }

    fn ty_of(&self, ty: Option<ast::TypeRef>) -> Ty {
        let sig = type_signature(ty);
        if sig.path.as_ref().is_some_and(|p| self.scope.type_params.contains(p)) {
            return Ty::Unknown;
        }
        self.sema.ty(&sig, &self.scope)
    }

    /// Declares the locals a body introduces: its `var` declarations (all of them, so that uses
    /// anywhere in the body see them) and the window variables of `loopwindow2D(u = -r : r, …)`.
    /// `own` are the body's own descendants (`ast::own_descendants(node)`).
    fn declare_body(&mut self, node: &SyntaxNode, own: &[SyntaxNode]) {
        for element in own {
            match element.kind() {
                SyntaxKind::VAR_DECL => {
                    let decl = ast::VarDecl::cast(element.clone()).expect("kind checked");
                    if let Some(name) = decl.name() {
                        let text = name.text();
                        let outer = self.locals.contains_key(&text) && !self.declared_in.contains_key(&text);
                        if !outer {
                            let scope = decl.syntax().ancestors().skip(1).find(|n| {
                                n == node
                                    || matches!(
                                        n.kind(),
                                        SyntaxKind::BLOCK | SyntaxKind::FOR_STMT | SyntaxKind::NODE_BODY
                                    )
                            });
                            let scope = scope.map_or_else(|| node.text_range(), |s| s.text_range());
                            let at = name.syntax().text_range().start();
                            self.declared_in.entry(text.clone()).or_default().push((at, scope));
                        }
                        self.declare(text, decl.type_ref());
                    }
                }
                // `loopwindow2D(u = -r : r, …)` introduces its window variables (integers).
                SyntaxKind::LOOP_WINDOW_DIM => {
                    let dim = ast::LoopWindowDim::cast(element.clone()).expect("kind checked");
                    if let Some(ast::LoopPart::Expr(ast::Expr::BinExpr(assign))) = dim.start() {
                        if let Some(name) = assign.lhs().and_then(|lhs| match lhs {
                            ast::Expr::NameExpr(name) => name.name_ref(),
                            _ => None,
                        }) {
                            self.locals.entry(name.text()).or_insert(Ty::Int);
                        }
                    }
                }
                _ => {}
            }
        }
    }

    /// Checks every statement, guard and transition of `node` (a block or a node body).
    pub fn check(&mut self, node: &SyntaxNode) {
        let own: Vec<SyntaxNode> = ast::own_descendants(node).collect();
        self.declare_body(node, &own);
        for element in own {
            match element.kind() {
                SyntaxKind::VAR_DECL => self.var_decl(&ast::VarDecl::cast(element).expect("kind checked")),
                SyntaxKind::EXPR_STMT => {
                    if let Some(expr) = ast::support::child::<ast::Expr>(&element) {
                        self.infer(&expr);
                    }
                }
                SyntaxKind::RETURN_STMT => self.return_stmt(&element),
                SyntaxKind::LOOP_WINDOW_STMT => {
                    let window = ast::LoopWindowStmt::cast(element).expect("kind checked");
                    let (keyword, wanted) = match window.loopwindow3d_token() {
                        Some(_) => ("loopwindow3D", 3),
                        None => ("loopwindow2D", 2),
                    };
                    let given = window.ranges().count();
                    if given != wanted {
                        self.sink.error(
                            DiagnosticCode::LoopWindowMismatch,
                            window
                                .loopwindow2d_token()
                                .or(window.loopwindow3d_token())
                                .map_or_else(|| window.syntax().text_range(), |t| t.text_range()),
                            format!("`{keyword}` takes {wanted} window ranges (`u = -r : r, …`), {given} given"),
                        );
                    }
                }
                SyntaxKind::GUARD => {
                    if let Some(cond) = ast::Guard::cast(element).and_then(|g| g.condition()) {
                        self.expect_bool(&cond, "a transition guard");
                    }
                }
                SyntaxKind::IF_STMT | SyntaxKind::LOOP_STMT | SyntaxKind::DO_LOOP_STMT => {
                    if let Some(cond) = ast::support::child::<ast::Expr>(&element) {
                        self.expect_bool(&cond, "a condition");
                    }
                }
                // `for (init : step : test)`: the test is boolean, the other parts are typed
                // (a declaration among them is a VAR_DECL, checked above).
                SyntaxKind::FOR_STMT => {
                    let sections = ast::ForStmt::cast(element).expect("kind checked").sections();
                    for (i, part) in sections.iter().enumerate() {
                        match part {
                            ast::LoopPart::Expr(e) if i == 2 => self.expect_bool(e, "a `for` test"),
                            ast::LoopPart::Expr(e) => drop(self.infer(e)),
                            ast::LoopPart::Decl(_) => {}
                        }
                    }
                }
                SyntaxKind::SWITCH_STMT => self.switch(&ast::SwitchStmt::cast(element).expect("kind checked")),
                SyntaxKind::LOOP_WINDOW_DIM => {
                    let dim = ast::LoopWindowDim::cast(element).expect("kind checked");
                    if let Some(ast::LoopPart::Expr(start)) = dim.start() {
                        self.infer(&start);
                    }
                    if let Some(end) = dim.end() {
                        self.infer(&end);
                    }
                }
                SyntaxKind::TRANSITION => self.transition(&ast::Transition::cast(element).expect("kind checked")),
                _ => {}
            }
        }
    }

    fn expect_bool(&mut self, cond: &ast::Expr, what: &str) {
        let ty = self.infer(cond);
        if !Ty::Bool.assignable_to(&ty, &mut |_, _| true) || matches!(ty, Ty::String | Ty::Named(_) | Ty::Vector(..)) {
            self.sink.error(
                DiagnosticCode::NotABoolean,
                cond.syntax().text_range(),
                format!("{what} must be a boolean expression, but this is `{ty}`"),
            );
        }
    }

    fn expect_assignable(&mut self, value: &Ty, target: &Ty, at: &SyntaxNode, what: &str) {
        let sema = self.sema;
        if !value.assignable_to(target, &mut |a, b| sema.is_subtype(a, b)) {
            self.sink.error(
                DiagnosticCode::TypeMismatch,
                at.text_range(),
                format!("{what} has type `{target}`, but the value is `{value}`"),
            );
        }
    }

    /// The type of an expression, checking calls and assignments inside it on the way.
    pub fn infer(&mut self, expr: &ast::Expr) -> Ty {
        let ty = self.infer_expr(expr);
        if let Some(record) = &mut self.record {
            record.insert((expr.syntax().kind(), expr.syntax().text_range()), ty.clone());
        }
        ty
    }

    fn infer_expr(&mut self, expr: &ast::Expr) -> Ty {
        use LiteralValue::Int;
        match expr {
            ast::Expr::Literal(lit) => match lit.token().map(|t| t.kind()) {
                // `3u`, and a literal too large for `int`, is `unsigned int`, as in C.
                Some(SyntaxKind::INT_NUMBER) if matches!(lit.value(), Some(Int { unsigned: true, .. })) => Ty::UInt,
                Some(SyntaxKind::INT_NUMBER | SyntaxKind::CHAR) => Ty::Int,
                Some(SyntaxKind::FLOAT_NUMBER) => Ty::Float,
                Some(SyntaxKind::STRING) => Ty::String,
                Some(SyntaxKind::TRUE_KW | SyntaxKind::FALSE_KW) => Ty::Bool,
                Some(SyntaxKind::NULL_KW) => Ty::Null,
                _ => Ty::Unknown,
            },
            ast::Expr::NameExpr(name) => {
                let Some(name_ref) = name.name_ref() else { return Ty::Unknown };
                self.name_ty(&name_ref.text(), name_ref.syntax())
            }
            ast::Expr::ThisExpr(this) => {
                self.expect_object("this", &[], this.syntax());
                self.owner.map_or(Ty::Unknown, |o| Ty::Named(o.fqn.clone()))
            }
            ast::Expr::ParenExpr(p) => p.expr().map_or(Ty::Unknown, |e| self.infer(&e)),
            ast::Expr::PrefixExpr(p) => self.prefix(p),
            ast::Expr::PostfixExpr(p) => self.postfix(p),
            ast::Expr::BinExpr(bin) => self.binary(bin),
            ast::Expr::TernaryExpr(t) => self.ternary(t),
            ast::Expr::CastExpr(c) => {
                if let Some(e) = c.operand() {
                    self.infer(&e);
                }
                self.ty_of(c.type_ref())
            }
            ast::Expr::AsExpr(a) => {
                if let Some(e) = a.operand() {
                    self.infer(&e);
                }
                self.ty_of(a.type_ref())
            }
            ast::Expr::IndexExpr(i) => self.index(i),
            ast::Expr::MemberExpr(m) => self.member(m),
            ast::Expr::ScopeExpr(s) => self.scope_member(s),
            ast::Expr::NewExpr(n) => self.new_expr(n),
            ast::Expr::CallExpr(call) => self.call(call),
            ast::Expr::CallMethodExpr(call) => {
                let args: Vec<ast::Expr> = call.args().collect();
                let (Some(class), Some(method)) = (call.class(), call.method()) else { return Ty::Unknown };
                match self.sema.resolve(&self.scope, &class.text()) {
                    Some(def) => self.check_call(def, &method.text(), &args, method.syntax(), CallForm::Class),
                    None => Ty::Unknown,
                }
            }
            ast::Expr::CallBehaviorExpr(call) => self.call_behavior(call),
            ast::Expr::CallInterfaceExpr(call) => {
                for arg in call.args() {
                    self.infer(&arg);
                }
                Ty::Unknown
            }
        }
    }

    /// A local, a field of the owner (or its bases), or a type used as a scope; anything else
    /// is reported as unknown.
    fn name_ty(&mut self, name: &str, at: &SyntaxNode) -> Ty {
        if let Some(ty) = self.locals.get(name).cloned() {
            self.expect_declared_before(name, at);
            return ty;
        }
        if let Some(owner) = self.owner {
            if let Some((ty, qualifiers)) = self.member_field(&owner.fqn, name, at) {
                if let Some(qualifiers) = qualifiers {
                    self.expect_object(name, &qualifiers, at);
                }
                return ty;
            }
        }
        match self.sema.resolve(&self.scope, name) {
            Some(def) if matches!(def.kind, DefKind::Type(_)) => Ty::Named(def.fqn.clone()),
            Some(_) => Ty::Unknown,
            None => {
                let hint = match self.owner {
                    Some(owner) => format!(" (nor a field of the owner `{}`)", owner.fqn),
                    None => String::new(),
                };
                let mut known: Vec<String> = self.locals.keys().cloned().collect();
                known.sort();
                if let Some(owner) = self.owner {
                    known.extend(self.sema.member_names(&owner.fqn, true));
                }
                self.sink.error_with_suggestion(
                    DiagnosticCode::UnknownName,
                    at.text_range(),
                    format!("unknown name `{name}`: not a variable, parameter or type in scope{hint}"),
                    closest(name, known.iter().map(String::as_str)),
                );
                Ty::Unknown
            }
        }
    }

    /// A body's own `var` is used after its declaration and inside the block it is declared in
    /// (C's scopes: a use before the declaration, or after the block ended, names nothing).
    fn expect_declared_before(&mut self, name: &str, at: &SyntaxNode) {
        let Some(declarations) = self.declared_in.get(name) else { return };
        let used = at.text_range();
        if declarations.iter().any(|(declared, scope)| *declared <= used.start() && scope.contains_range(used)) {
            return;
        }
        let later = declarations.iter().any(|(declared, scope)| *declared > used.start() && scope.contains_range(used));
        let message = match later {
            true => format!("`{name}` is used before its declaration: declare it (`var … {name}`) before this use"),
            false => format!("`{name}` is declared in another block: it is not in scope here (declare it in a block that holds this use)"),
        };
        self.sink.error(DiagnosticCode::UnknownName, used, message);
    }

    /// A member `name` of `declaring` with `qualifiers`, used here: a `private` one only in the
    /// class that declares it, a `protected` one also in its subclasses (9.1.1, as in C# and
    /// Java); the body's class is its owner (a method's class, a swimlane's or diagram's owner).
    fn expect_visible(&mut self, declaring: &Definition, qualifiers: &[String], name: &str, at: &SyntaxNode) {
        let here = self.owner.map(|o| o.fqn.as_str());
        let (allowed, what) = if qualifiers.iter().any(|q| q == "private") {
            (here == Some(declaring.fqn.as_str()), "private to")
        } else if qualifiers.iter().any(|q| q == "protected") {
            (here.is_some_and(|h| self.sema.is_subtype(h, &declaring.fqn)), "protected in")
        } else {
            return;
        };
        if !allowed {
            let used_in = here.map_or("a body without an owner class".to_string(), |h| format!("`{h}`"));
            self.sink.error(
                DiagnosticCode::InaccessibleMember,
                at.text_range(),
                format!("`{name}` is {what} `{}`: it cannot be used in {used_in}", declaring.fqn),
            );
        }
    }

    /// The field `name` of `fqn` (or of a base; an enum's value), its visibility checked where
    /// it is used: its type, and a declared field's qualifiers; `None` if the type has none of
    /// that name.
    fn member_field(&mut self, fqn: &str, name: &str, at: &SyntaxNode) -> Option<(Ty, Option<Vec<String>>)> {
        let declared = self.sema.find_member(fqn, &|ty| ty.fields.iter().find(|f| f.name == name).cloned());
        let Some((declaring, field)) = declared else { return self.sema.field_ty(fqn, name).map(|ty| (ty, None)) };
        self.expect_visible(declaring, &field.qualifiers, name, at);
        Some((self.sema.ty(&field.ty, &Scope::of(declaring)), Some(field.qualifiers)))
    }

    /// `receiver.member` on a user type: reports a member the type does not have.
    fn field_ty(&mut self, fqn: &str, name: &str, at: &SyntaxNode) -> Ty {
        if let Some((ty, _)) = self.member_field(fqn, name, at) {
            return ty;
        }
        if !self.sema.has_method(fqn, name) && self.sema.definition(fqn).is_some() {
            let fields = self.sema.member_names(fqn, true);
            self.sink.error_with_suggestion(
                DiagnosticCode::UnknownMember,
                at.text_range(),
                format!("`{fqn}` has no field `{name}`"),
                closest(name, fields.iter().map(String::as_str)),
            );
        }
        Ty::Unknown
    }
}

/// How many components the swizzle `name` of a `width`-wide vector selects (OpenCL C 6.1.7:
/// `xyzw`/`rgba` letters, `s` and hex digits, `lo`/`hi`/`even`/`odd`; the dissertation writes
/// `_x`); `None` if it is none, or names a component the vector does not have (`int2._w`).
pub fn swizzle_width(name: &str, width: u8) -> Option<u8> {
    let name = name.strip_prefix('_').unwrap_or(name);
    let count = |n: usize| u8::try_from(n).ok().filter(|n| (1..=16).contains(n));
    let within = |index: Option<usize>| index.is_some_and(|i| i < usize::from(width));
    if matches!(name, "lo" | "hi" | "even" | "odd") {
        return (width >= 2).then_some(width / 2);
    }
    if let Some(digits) = name.strip_prefix(['s', 'S']).filter(|d| !d.is_empty()) {
        if digits.chars().all(|c| within(c.to_digit(16).map(|d| d as usize))) {
            return count(digits.len());
        }
    }
    for letters in ["xyzw", "rgba"] {
        if name.chars().all(|c| within(letters.find(c))) {
            return count(name.len());
        }
    }
    None
}

impl<'db> Semantics<'db> {
    /// The type of an expression in the context it is written in: the locals, parameters and
    /// variables in scope there and the members of the owner class. `Unknown` where it cannot be
    /// known; problems found on the way are not reported (validation reports them).
    pub fn type_of_expr(&self, expr: &ast::Expr) -> Ty {
        let mut sink = Diagnostics::default();
        let (mut ctx, body) = self.context_at(expr.syntax(), &mut sink);
        if let Some(body) = body {
            let own: Vec<SyntaxNode> = ast::own_descendants(&body).collect();
            ctx.declare_body(&body, &own);
        }
        ctx.infer(expr)
    }

    /// The types of the expressions of the body `node` is or is in — an activity node's (its
    /// loop header, statements, guards, transitions and returned value), a method's, or, for an
    /// activity diagram, its variable section — and of the locals it sees.
    pub fn body_types(&self, node: &SyntaxNode) -> BodyTypes {
        let mut sink = Diagnostics::default();
        let (mut ctx, body) = self.context_at(node, &mut sink);
        ctx.record = Some(HashMap::new());
        if let Some(activity_node) = node.ancestors().find_map(ast::ActivityNode::cast) {
            if let Some(header) = activity_node.loop_header() {
                ctx.check_loop_header(&header);
            }
            if let Some(value) = activity_node.return_value() {
                ctx.infer(&value);
            }
        } else if let Some(diagram) = ast::ActivityDiagram::cast(node.clone()) {
            let values = diagram.variables().filter_map(|v| v.initializer());
            for value in values.chain(diagram.var_decls().filter_map(|v| v.initializer())) {
                ctx.infer(&value);
            }
        }
        if let Some(body) = body {
            ctx.check(&body);
        }
        BodyTypes { exprs: ctx.record.take().unwrap_or_default(), locals: ctx.locals.clone() }
    }

    /// A typing context for what is written at `node`: the diagram's locals, the activity node's
    /// header or the method's parameters, the owner; and the body `node` is in.
    fn context_at<'a>(
        &self,
        node: &SyntaxNode,
        sink: &'a mut Diagnostics,
    ) -> (InferenceCtx<'a, 'db>, Option<SyntaxNode>) {
        let mut scope = Scope::at(node);
        if let Some(decl) = node.ancestors().find_map(ast::TypeDecl::cast) {
            let params: Vec<ast::TemplateParam> = match &decl {
                ast::TypeDecl::Class(c) => c.template_params().collect(),
                ast::TypeDecl::Interface(i) => i.template_params().collect(),
                _ => Vec::new(),
            };
            scope.type_params.extend(params.iter().filter_map(|t| t.name()).map(|n| n.text()));
        }
        let mut ctx = InferenceCtx::new(*self, sink, scope, self.owner_at(node));
        let mut body = None;
        if let Some(diagram) = node.ancestors().find_map(ast::ActivityDiagram::cast) {
            for (name, ty) in diagram_locals(&diagram) {
                ctx.declare(name, ty);
            }
        }
        if let Some(activity_node) = node.ancestors().find_map(ast::ActivityNode::cast) {
            for (name, ty) in header_declarations(&activity_node) {
                ctx.declare(name, ty);
            }
            body = activity_node.body().map(|b| b.syntax().clone());
        }
        if let Some(method) = node.ancestors().find_map(ast::Method::cast) {
            for param in method.params() {
                if let Some(name) = param.name() {
                    ctx.declare(name.text(), param.type_ref());
                }
            }
            body = method.body().map(|b| b.syntax().clone());
        }
        (ctx, body)
    }
}
