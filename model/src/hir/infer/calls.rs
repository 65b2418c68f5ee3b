//! Calls in bodies: a method of the owner, of a receiver's type or of a class (`C::m`), checked
//! for arity and argument types against the overloads, choosing among overloads by argument
//! type.

use super::{places::CallForm, InferenceCtx};
use crate::{
    ast::{self, AstNode, HasName},
    db::{Db, Workspace},
    hir::{
        definitions::{DefKind, Definition, Fqn},
        diagnostics::{arguments, DiagnosticCode},
        items::{MethodSignature, ParamSignature},
        scope::Scope,
        semantics::Semantics,
        spelling::closest,
        ty::Ty,
    },
    library::OPENCL_INTERFACE,
    syntax::{SyntaxKind, SyntaxNode},
};

impl<'db> InferenceCtx<'_, 'db> {
    pub(super) fn call(&mut self, call: &ast::CallExpr) -> Ty {
        let args: Vec<ast::Expr> = call.args().collect();
        match call.callee() {
            Some(ast::Expr::NameExpr(name)) => {
                let Some(method) = name.name_ref() else { return Ty::Unknown };
                match self.owner {
                    Some(owner) => self.check_call(owner, &method.text(), &args, method.syntax(), CallForm::Owner),
                    None => {
                        self.sink.error(
                            DiagnosticCode::UnknownName,
                            method.syntax().text_range(),
                            match self.opencl_builtin(&method.text()) {
                                true => format!(
                                    "`{}` is an OpenCL built-in: it is called in a body whose owner class implements `OpenCL` (give the swimlane or diagram such an owner)",
                                    method.text()
                                ),
                                false => format!(
                                    "unknown function `{}`: without an owner class, call methods as `Class::{0}(…)`",
                                    method.text()
                                ),
                            },
                        );
                        self.infer_all(&args)
                    }
                }
            }
            Some(ast::Expr::MemberExpr(member)) => {
                let receiver = member.receiver().map_or(Ty::Unknown, |r| self.infer(&r));
                self.call_on(receiver, member.member(), &args, CallForm::Object)
            }
            Some(ast::Expr::ScopeExpr(scoped)) => {
                let form = match scoped.scope() {
                    Some(scope) if self.names_a_type(&scope) => CallForm::Class,
                    _ => CallForm::Object,
                };
                let scope = scoped.scope().map_or(Ty::Unknown, |r| self.infer(&r));
                self.call_on(scope, scoped.member(), &args, form)
            }
            _ => self.infer_all(&args),
        }
    }

    /// `receiver.method(args)` and `Type::method(args)`: a method of the receiver's type.
    fn call_on(&mut self, receiver: Ty, method: Option<ast::NameRef>, args: &[ast::Expr], form: CallForm) -> Ty {
        match (receiver.dereferenced(), method) {
            (Ty::Named(fqn), Some(method)) => match self.sema.definition(fqn) {
                Some(def) => self.check_call(def, &method.text(), args, method.syntax(), form),
                None => self.infer_all(args),
            },
            _ => self.infer_all(args),
        }
    }

    fn infer_all(&mut self, args: &[ast::Expr]) -> Ty {
        for arg in args {
            self.infer(arg);
        }
        Ty::Unknown
    }

    /// Whether `expr`, written before `::`, names a type (not a variable of one).
    fn names_a_type(&self, expr: &ast::Expr) -> bool {
        let text: String = expr.syntax().text().to_string().split_whitespace().collect();
        !self.locals.contains_key(&text)
            && self.owner.is_none_or(|o| self.sema.field_ty(&o.fqn, &text).is_none())
            && self.sema.resolve(&self.scope, &text).is_some_and(|d| matches!(d.kind, DefKind::Type(_)))
    }

    /// Checks a call of `method` on type `def` (with its bases), written in `form`: arity
    /// against the overloads, then argument types against the overload of that arity, then
    /// whether it may be called here. Returns the result type.
    pub(super) fn check_call(
        &mut self,
        def: &'db Definition,
        method: &str,
        args: &[ast::Expr],
        at: &SyntaxNode,
        form: CallForm,
    ) -> Ty {
        // `call Class::m(…)` of a method the class lacks is validation's (E0214).
        let report_missing = at.parent().is_none_or(|p| p.kind() != SyntaxKind::CALL_METHOD_EXPR);
        let arg_tys: Vec<Ty> = args.iter().map(|a| self.infer(a)).collect();
        self.image_access(method, args);
        self.texel_kind(method, args, &arg_tys);
        let overloads: Vec<(&'db Definition, MethodSignature)> = self.sema.methods(def, method);
        if overloads.is_empty() {
            if !report_missing {
                return Ty::Unknown;
            }
            let message = match self.opencl_builtin(method) {
                true => format!(
                    "`{method}` is an OpenCL built-in, and `{}` does not implement `OpenCL`: add `implements OpenCL` (with `import OpenCL.GPU.*;`) to call it",
                    def.fqn
                ),
                false => format!("`{}` has no method `{method}`", def.fqn),
            };
            let methods = self.sema.member_names(&def.fqn, false);
            let suggestion = closest(method, methods.iter().map(String::as_str));
            self.sink.error_with_suggestion(DiagnosticCode::UnknownMember, at.text_range(), message, suggestion);
            return Ty::Unknown;
        }
        if let Some((declaring, hidden)) = overloads.first().filter(|_| overloads.iter().all(|(_, m)| !is_public(m))) {
            self.expect_visible(declaring, &hidden.qualifiers, method, at);
        }
        let same_arity: Vec<&(&'db Definition, MethodSignature)> =
            overloads.iter().filter(|(_, m)| m.params.len() == args.len()).collect();
        if same_arity.is_empty() {
            let mut arities: Vec<usize> = overloads.iter().map(|(_, m)| m.params.len()).collect();
            arities.sort_unstable();
            arities.dedup();
            let expected = match arities.as_slice() {
                [one] => arguments(*one),
                _ => format!("{} arguments", arities.iter().map(|a| a.to_string()).collect::<Vec<_>>().join(" or ")),
            };
            self.sink.error(
                DiagnosticCode::CallArity,
                at.text_range(),
                format!("`{method}` takes {expected}, {} given", args.len()),
            );
            return Ty::Unknown;
        }
        let sema = self.sema;
        let param_tys = |(declaring, signature): &(&'db Definition, MethodSignature)| -> Vec<Ty> {
            let scope = Scope::of(declaring);
            signature.params.iter().map(|p| sema.ty(&p.ty, &scope)).collect()
        };
        let return_ty = |(declaring, signature): &(&'db Definition, MethodSignature)| {
            sema.ty(&signature.ret, &Scope::of(declaring))
        };
        if let [only] = same_arity.as_slice() {
            for (i, ((arg, arg_ty), param_ty)) in args.iter().zip(&arg_tys).zip(param_tys(only)).enumerate() {
                self.expect_argument(method, i, &only.1.params[i].name, &param_ty, arg, arg_ty);
                self.expect_passed_access(method, &only.1.params[i], arg);
            }
            self.expect_callable_here(form, only.0, &only.1, at);
            return return_ty(only);
        }
        // Overloads (`exp(float)`, `exp(float4)`, …): the one that takes these arguments, the
        // one with the most arguments of exactly its parameter types if several do, the first
        // declared of those.
        let mut best: Option<(usize, &(&'db Definition, MethodSignature))> = None;
        for &overload in &same_arity {
            let params = param_tys(overload);
            if !arg_tys.iter().zip(&params).all(|(a, p)| a.assignable_to(p, &mut |x, y| sema.is_subtype(x, y))) {
                continue;
            }
            let exact = arg_tys.iter().zip(&params).filter(|(a, p)| a.dereferenced() == p.dereferenced()).count();
            if best.is_none_or(|(score, _)| exact > score) {
                best = Some((exact, overload));
            }
        }
        if let Some((_, chosen)) = best {
            self.expect_callable_here(form, chosen.0, &chosen.1, at);
            return return_ty(chosen);
        }
        let given: Vec<String> = arg_tys.iter().map(|t| format!("`{t}`")).collect();
        let mut offered: Vec<String> = same_arity
            .iter()
            .map(|o| format!("({})", param_tys(o).iter().map(|t| t.to_string()).collect::<Vec<_>>().join(", ")))
            .collect();
        if offered.len() > 6 {
            let more = offered.len() - 5;
            offered.truncate(5);
            offered.push(format!("{more} more"));
        }
        let range = match (args.first(), args.last()) {
            (Some(first), Some(last)) => first.syntax().text_range().cover(last.syntax().text_range()),
            _ => at.text_range(),
        };
        self.sink.error(
            DiagnosticCode::ArgumentType,
            range,
            format!("no overload of `{method}` takes ({}): it takes {}", given.join(", "), offered.join(", ")),
        );
        Ty::Unknown
    }

    /// Whether `name` is one of the OpenCL built-ins of the bundled library.
    fn opencl_builtin(&self, name: &str) -> bool {
        self.sema.definition(OPENCL_INTERFACE).is_some_and(|opencl| !self.sema.methods(opencl, name).is_empty())
    }

    /// `call behavior Ad(args)`: each argument fits the activity diagram's parameter (the
    /// number of arguments is validation's, E0210).
    pub(super) fn call_behavior(&mut self, call: &ast::CallBehaviorExpr) -> Ty {
        let args: Vec<ast::Expr> = call.args().collect();
        let arg_tys: Vec<Ty> = args.iter().map(|a| self.infer(a)).collect();
        // What is no behavior is validation's (E0211), and so is the number of arguments (E0210).
        let Some(path) = call.behavior() else { return Ty::Unknown };
        let sema = self.sema;
        let Some(def) = sema.resolve(&self.scope, &path.text()) else { return Ty::Unknown };
        let DefKind::Activity(signature) = &def.kind else { return Ty::Unknown };
        if signature.params.len() == args.len() {
            let scope = Scope::of(def);
            for (i, ((arg, arg_ty), param)) in args.iter().zip(&arg_tys).zip(&signature.params).enumerate() {
                let param_ty = sema.ty(&param.ty, &scope);
                self.expect_argument(&def.fqn, i, &param.name, &param_ty, arg, arg_ty);
                self.expect_passed_access(&def.fqn, param, arg);
            }
        }
        behavior_result(sema.db(), sema.workspace(), Fqn::new(sema.db(), def.fqn.clone())).clone()
    }

    /// What `call behavior X(…)` yields, without checking its arguments again.
    pub(super) fn behavior_result(&self, call: &ast::CallBehaviorExpr) -> Ty {
        let sema = self.sema;
        let def = call.behavior().and_then(|path| sema.resolve(&self.scope, &path.text()));
        match def {
            Some(def) if matches!(def.kind, DefKind::Activity(_)) => {
                behavior_result(sema.db(), sema.workspace(), Fqn::new(sema.db(), def.fqn.clone())).clone()
            }
            _ => Ty::Unknown,
        }
    }

    /// `new T(args)` and `new T[size]`: no object of an interface or an abstract class (E0243),
    /// and a vector built from as many components as it has (OpenCL C 6.1.6: scalars and
    /// vectors whose widths add up, or one scalar for every component; 10.2.1.5).
    pub(super) fn new_expr(&mut self, new: &ast::NewExpr) -> Ty {
        let args: Vec<ast::Expr> = new.arg_list().into_iter().flat_map(|l| l.args().collect::<Vec<_>>()).collect();
        let arg_tys: Vec<Ty> = args.iter().map(|arg| self.infer(arg)).collect();
        let ty = self.ty_of(new.type_ref());
        if let Some(size) = new.array_size() {
            self.infer(&size);
            return Ty::Array(Box::new(ty));
        }
        let at = new.type_ref().map_or_else(|| new.syntax().clone(), |t| t.syntax().clone());
        match &ty {
            Ty::Named(fqn) => {
                let item = self.sema.definition(fqn).and_then(|d| match &d.kind {
                    DefKind::Type(item) => Some(item),
                    _ => None,
                });
                if let Some(why) = item.and_then(|item| item.why_not_instantiable()) {
                    self.sink.error(DiagnosticCode::AbstractInstance, at.text_range(), format!("`{fqn}` is {why}"));
                }
            }
            Ty::Vector(_, width) => self.vector_components(&ty, *width, &args, &arg_tys, &at),
            _ => {}
        }
        ty
    }

    fn vector_components(&mut self, ty: &Ty, width: u8, args: &[ast::Expr], arg_tys: &[Ty], at: &SyntaxNode) {
        let mut given = 0usize;
        for (arg, arg_ty) in args.iter().zip(arg_tys) {
            given += match arg_ty {
                Ty::Vector(_, w) => usize::from(*w),
                Ty::Unknown => return,
                t if t.is_numeric() => 1,
                other => {
                    self.sink.error(
                        DiagnosticCode::ArgumentType,
                        arg.syntax().text_range(),
                        format!("a component of `{ty}` is a number or a vector, not `{other}`"),
                    );
                    return;
                }
            };
        }
        let scalar_for_all = args.len() == 1 && given == 1;
        if given != usize::from(width) && !scalar_for_all && !args.is_empty() {
            self.sink.error(
                DiagnosticCode::CallArity,
                at.text_range(),
                format!("`{ty}` is built from {width} components (or one number for all of them), {given} given"),
            );
        }
    }

    /// `=> node(args)`: the work sizes of a calc node (3) or the ranges of a calcRange node
    /// (2, 4 or 6) are integers, the other arguments fit the node's parameters (the number of
    /// arguments is validation's, E0210).
    pub(super) fn transition(&mut self, transition: &ast::Transition) {
        let args: Vec<ast::Expr> = transition.args().collect();
        let arg_tys: Vec<Ty> = args.iter().map(|a| self.infer(a)).collect();
        let Some(target) = transition.target().map(|t| t.text()) else { return };
        let Some(node) = self.nodes.and_then(|nodes| nodes.get(&target)).cloned() else { return };
        let params: Vec<(String, Ty)> = node
            .params()
            .map(|p| (p.name().map(|n| n.text()).unwrap_or_default(), self.written_type(p.type_ref())))
            .collect();
        let leading = match node.kind() {
            ast::NodeKind::Calc => 3,
            ast::NodeKind::CalcRange => args.len().saturating_sub(params.len()),
            _ => 0,
        };
        if args.len() != leading + params.len() {
            return;
        }
        for (i, (arg, arg_ty)) in args.iter().zip(&arg_tys).enumerate() {
            match i.checked_sub(leading) {
                None if !matches!(arg_ty.dereferenced(), Ty::Int | Ty::UInt | Ty::Unknown) => self.sink.error(
                    DiagnosticCode::ArgumentType,
                    arg.syntax().text_range(),
                    format!(
                        "argument {} of `{target}` is a work size or range: an integer, but this is `{arg_ty}`",
                        i + 1
                    ),
                ),
                None => {}
                Some(p) => {
                    let (name, param_ty) = &params[p];
                    self.expect_argument(&target, i, name, param_ty, arg, arg_ty);
                }
            }
        }
    }

    /// Argument `index` (from 0) of `callee`, of type `arg_ty`, fits parameter `param`.
    fn expect_argument(
        &mut self,
        callee: &str,
        index: usize,
        param: &str,
        param_ty: &Ty,
        arg: &ast::Expr,
        arg_ty: &Ty,
    ) {
        let sema = self.sema;
        if !arg_ty.assignable_to(param_ty, &mut |a, b| sema.is_subtype(a, b)) {
            self.sink.error(
                DiagnosticCode::ArgumentType,
                arg.syntax().text_range(),
                format!(
                    "argument {} of `{callee}` (`{param}`) expects `{param_ty}`, but this is `{arg_ty}`",
                    index + 1
                ),
            );
        }
    }

    /// A `read` image passed to a parameter that writes it (`write` or `read write`), or a
    /// `write` one to a parameter that reads it (Sec. 10.2.1.5): the callee would do what the
    /// image may not.
    fn expect_passed_access(&mut self, callee: &str, param: &ParamSignature, arg: &ast::Expr) {
        let ast::Expr::NameExpr(image) = arg else { return };
        let Some(name) = image.name_ref().map(|n| n.text()) else { return };
        let (has, needs) = match self.access.get(&name) {
            Some(SyntaxKind::READ_KW) => ("read", "write"),
            Some(SyntaxKind::WRITE_KW) => ("write", "read"),
            _ => return,
        };
        if param.qualifiers.iter().any(|q| q == needs) {
            let declared = match param.qualifiers.iter().any(|q| q == has) {
                true => "read write",
                false => needs,
            };
            let does = if needs == "write" { "writes" } else { "reads" };
            self.sink.error(
                DiagnosticCode::ImageAccess,
                image.syntax().text_range(),
                format!(
                    "`{name}` is a `{has}` image, and `{callee}` {does} it (its parameter `{}` is `{declared}`): declare `{name}` `read write` to pass it",
                    param.name
                ),
            );
        }
    }

    /// `read_image…` of a `write` image or `write_image…` of a `read` one (Sec. 10.2.1.5).
    fn image_access(&mut self, method: &str, args: &[ast::Expr]) {
        let (forbidden, what) = if method.starts_with("read_image") {
            (SyntaxKind::WRITE_KW, "write")
        } else if method.starts_with("write_image") {
            (SyntaxKind::READ_KW, "read")
        } else {
            return;
        };
        let Some(ast::Expr::NameExpr(image)) = args.first() else { return };
        let Some(name) = image.name_ref().map(|n| n.text()) else { return };
        if self.access.get(&name) == Some(&forbidden) && self.opencl_builtin(method) {
            let verb = if what == "write" { "read" } else { "written" };
            self.sink.error(
                DiagnosticCode::ImageAccess,
                image.syntax().text_range(),
                format!("`{name}` is a `{what}` image: it cannot be {verb} (declare it `read write` to do both)"),
            );
        }
    }
}

impl InferenceCtx<'_, '_> {
    /// `read_imagef`/`write_imagef` on a float image, `…i`/`…ui` on an integer one: the
    /// function's texel kind is the image's (OpenCL 1.2, 6.12.14.2: other pairs are undefined).
    /// An integer image's texels are read and written as `int` or `unsigned int` alike (Listing
    /// 15 reads an `image2D_uc` with `read_imagei`), converted as the texel's bits allow.
    fn texel_kind(&mut self, method: &str, args: &[ast::Expr], arg_tys: &[Ty]) {
        let Some(suffix) = method.strip_prefix("read_image").or_else(|| method.strip_prefix("write_image")) else {
            return;
        };
        let (Some(image), Some(Ty::Gpu(image_ty))) = (args.first(), arg_tys.first().map(Ty::dereferenced)) else {
            return;
        };
        let Some(texel) = image_ty.strip_prefix("image2D_").or_else(|| image_ty.strip_prefix("image3D_")) else {
            return;
        };
        let float_image = matches!(texel, "f" | "d");
        let float_function = suffix == "f";
        if texel == "t" || float_image == float_function || !self.opencl_builtin(method) {
            return;
        }
        let verb = &method[..method.len() - suffix.len()];
        let (holds, other, use_instead) = match float_image {
            true => ("float", "integer", format!("`{verb}f`")),
            false => ("integer", "float", format!("`{verb}i` or `{verb}ui`")),
        };
        let name = image.syntax().text();
        self.sink.error(
            DiagnosticCode::TexelKind,
            image.syntax().text_range(),
            format!("`{name}` is an `{image_ty}`, which holds {holds} texels, and `{method}` is for {other} ones: use {use_instead}"),
        );
    }
}

/// What `call behavior` of a diagram yields: the value its final nodes return (the first one's
/// type; validation checks that they agree), `void` if they return none. A value that is itself
/// the result of a behavior is not followed (`Unknown`): no chain of diagrams, no cycle.
/// A query, so that a caller is re-checked when the result changes, not on every edit of the
/// diagram's file.
#[salsa::tracked(returns(ref))]
pub(crate) fn behavior_result<'db>(db: &'db dyn Db, workspace: Workspace, diagram: Fqn<'db>) -> Ty {
    let sema = Semantics::new(db, workspace);
    let Some(def) = sema.definition(diagram.text(db)) else { return Ty::Unknown };
    let Some(diagram) = sema.declaration(def).and_then(|(node, _)| ast::ActivityDiagram::cast(node)) else {
        return Ty::Unknown;
    };
    let finals = diagram.all_nodes();
    let Some(value) = finals.filter(|n| n.kind() == ast::NodeKind::Final).find_map(|n| n.return_value()) else {
        return Ty::Void;
    };
    if value.syntax().descendants().any(|n| n.kind() == SyntaxKind::CALL_BEHAVIOR_EXPR) {
        return Ty::Unknown;
    }
    sema.type_of_expr(&value)
}

/// Whether a method is visible everywhere: declared neither `private` nor `protected`.
fn is_public(method: &MethodSignature) -> bool {
    !method.qualifiers.iter().any(|q| q == "private" || q == "protected")
}
