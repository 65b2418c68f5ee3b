//! Methods of the owner as WGSL functions: a device diagram's call of a method of its OpenCL
//! class (or a base) that has a body becomes a call of a function generated once per module,
//! with the method's value parameters and return type; methods it calls follow. What WGSL
//! cannot take is an error at its place: recursion, pointer or image parameters, fields of the
//! class, overloads of the same arity, a method without a body.

use gudsl_model::{
    ast::{self, AstNode, HasName},
    hir::{Definition, Scope, Ty},
    syntax::{SyntaxNode, TextRange},
};

use crate::{
    emitter::{bare, ident, Emitter},
    types::value_type,
};

/// One method generated as a function.
#[derive(Clone)]
pub(crate) struct Function<'db> {
    class: &'db Definition,
    method: ast::Method,
    /// Its name in the module: `Class_method`.
    name: String,
    params: Vec<(String, Ty)>,
    returns: Ty,
}

/// A call of a generated function: by whom (`None`: the kernel), of which, and where.
pub(crate) struct Call {
    caller: Option<usize>,
    callee: usize,
    place: (gudsl_model::db::SourceFile, TextRange),
}

impl<'db> Emitter<'db> {
    /// `name(args)` where `name` is no OpenCL built-in: a method of the diagram's owner.
    pub fn method_call(&mut self, call: &ast::CallExpr, name: &str) -> String {
        let args: Vec<ast::Expr> = call.args().collect();
        let Some(owner) = self.owner else {
            return self.unsupported(
                call.syntax(),
                format!("`{name}` is no OpenCL built-in, and the diagram has no OpenCL owner whose method it could be"),
            );
        };
        let found = declared_methods(self, owner, name, args.len());
        let (class, method) = match &found[..] {
            [(class, method)] => (*class, method.clone()),
            [] => {
                return self.unsupported(
                    call.syntax(),
                    format!(
                        "`{name}` is neither an OpenCL built-in nor a method of `{}` with {} parameter(s)",
                        owner.fqn,
                        args.len()
                    ),
                )
            }
            _ => {
                return self.unsupported(
                    call.syntax(),
                    format!("`{name}` has several overloads of {} parameter(s): WGSL has no overloads", args.len()),
                )
            }
        };
        if method.body().is_none() {
            return self.unsupported(
                call.syntax(),
                format!(
                    "`{}::{name}` has no body to generate: give it one, or model it as a device diagram",
                    class.fqn
                ),
            );
        }
        let Some(callee) = self.function_index(class, &method) else {
            return self.unsupported(call.syntax(), format!("`{name}` cannot be generated (see its declaration)"));
        };
        let caller = self.current_function.as_ref().map(|(index, _)| *index);
        self.calls.push(Call { caller, callee, place: (self.file, call.syntax().text_range()) });
        let params: Vec<Ty> = self.functions[callee].params.iter().map(|(_, ty)| ty.clone()).collect();
        let args: Vec<String> = args.iter().zip(&params).map(|(arg, ty)| bare(self.expr_as(arg, ty))).collect();
        format!("{}({})", self.functions[callee].name, args.join(", "))
    }

    /// The index of `method` among the functions, added (its signature checked) when first
    /// called; `None` when its signature has no WGSL form (reported at the declaration).
    fn function_index(&mut self, class: &'db Definition, method: &ast::Method) -> Option<usize> {
        if let Some(index) = self.functions.iter().position(|f| f.method == *method) {
            return Some(index);
        }
        let name = method.name().map(|n| n.text()).unwrap_or_default();
        let types = self.sema.body_types(method.syntax());
        let file = self.file;
        self.file = class.file;
        let mut params = Vec::new();
        let mut fine = true;
        for param in method.params() {
            let Some(param_name) = param.name().map(|n| n.text()) else { continue };
            let ty = types.locals.get(&param_name).cloned().unwrap_or(Ty::Unknown);
            if value_type(&ty).is_none() || matches!(ty, Ty::Ref { .. } | Ty::Array(_)) {
                self.unsupported(
                    param.syntax(),
                    format!("`{param_name}` is a `{ty}`: generated functions take numbers and vectors only"),
                );
                fine = false;
            }
            params.push((param_name, ty));
        }
        let returns = self
            .sema
            .methods(class, &name)
            .into_iter()
            .find(|(declared, signature)| declared.fqn == class.fqn && signature.params.len() == params.len())
            .map(|(_, signature)| self.sema.ty(&signature.ret, &Scope::of(class)))
            .unwrap_or(Ty::Unknown);
        if returns != Ty::Void && value_type(&returns).is_none() {
            let at = method.name().map(|n| n.syntax().clone()).unwrap_or_else(|| method.syntax().clone());
            self.unsupported(&at, format!("`{name}` returns a `{returns}`, which has no WGSL value type"));
            fine = false;
        }
        self.file = file;
        if !fine {
            return None;
        }
        let class_name = class.fqn.rsplit('.').next().unwrap_or_default();
        let function =
            Function { class, method: method.clone(), name: ident(&format!("{class_name}_{name}")), params, returns };
        self.functions.push(function);
        Some(self.functions.len() - 1)
    }

    /// The functions called so far (and those they call), as WGSL; then every recursion is an
    /// error at the call that closes it. Written after the kernel's body was taken.
    pub fn functions_wgsl(&mut self) -> String {
        let kernel_types = std::mem::take(&mut self.types);
        let kernel_file = self.file;
        let mut index = 0;
        while index < self.functions.len() {
            let function = self.functions[index].clone();
            self.types = self.sema.body_types(function.method.syntax());
            self.file = function.class.file;
            self.current_function = Some((index, function.returns.clone()));
            let params: Vec<String> = function
                .params
                .iter()
                .map(|(name, ty)| format!("{}: {}", ident(name), value_type(ty).unwrap_or_default()))
                .collect();
            let returns = value_type(&function.returns).map(|ty| format!(" -> {ty}")).unwrap_or_default();
            self.line(format!(
                "// {}::{}",
                function.class.fqn,
                function.method.name().map(|n| n.text()).unwrap_or_default()
            ));
            let statements: Vec<ast::Stmt> =
                function.method.body().map(|b| b.statements().collect()).unwrap_or_default();
            self.block(format!("fn {}({}){returns} {{", function.name, params.join(", ")), |e| {
                for stmt in &statements {
                    e.statement(stmt);
                }
                // The model checked that every path returns (E0235); WGSL also asks for a value
                // after a last statement that returns on each of its branches.
                let ends_in_return = matches!(statements.last(), Some(ast::Stmt::ReturnStmt(_)));
                if let Some(ty) = value_type(&function.returns).filter(|_| !ends_in_return) {
                    e.line(format!("return {ty}();"));
                }
            });
            self.line("");
            index += 1;
        }
        self.current_function = None;
        self.types = kernel_types;
        self.file = kernel_file;
        self.report_recursion();
        self.take_output()
    }

    /// Every call that closes a cycle of calls between the functions.
    fn report_recursion(&mut self) {
        let count = self.functions.len();
        let mut closing = Vec::new();
        for (at, call) in self.calls.iter().enumerate() {
            // A call from `caller` to `callee` closes a cycle when `callee` reaches `caller`.
            let Some(caller) = call.caller else { continue };
            let mut seen = vec![false; count];
            let mut stack = vec![call.callee];
            while let Some(f) = stack.pop() {
                if f == caller {
                    closing.push(at);
                    break;
                }
                if std::mem::replace(&mut seen[f], true) {
                    continue;
                }
                stack.extend(self.calls.iter().filter(|c| c.caller == Some(f)).map(|c| c.callee));
            }
        }
        for at in closing {
            let call = &self.calls[at];
            let (file, range) = call.place;
            let name = self.functions[call.callee].name.clone();
            self.errors.push(crate::CodegenError {
                file,
                range,
                message: format!("`{name}` is called recursively: WGSL has no recursion"),
            });
        }
    }

    /// Inside a generated function, a name that is neither a parameter nor a local: a field of
    /// the class, which the GPU does not have.
    pub fn field_in_function(&mut self, name: &str, at: &SyntaxNode) -> Option<String> {
        let in_function = self.current_function.is_some() && !self.types.locals.contains_key(name);
        in_function.then(|| {
            self.unsupported(
                at,
                format!("`{name}`: fields of the class are not generated for the GPU; pass it as a parameter"),
            )
        })
    }
}

/// The methods `name` of `owner` and its bases with `arity` parameters, with the class that
/// declares each.
fn declared_methods<'db>(
    emitter: &Emitter<'db>,
    owner: &'db Definition,
    name: &str,
    arity: usize,
) -> Vec<(&'db Definition, ast::Method)> {
    let mut classes: Vec<&'db Definition> = Vec::new();
    for (class, signature) in emitter.sema.methods(owner, name) {
        if signature.params.len() == arity && !classes.iter().any(|c| c.fqn == class.fqn) {
            classes.push(class);
        }
    }
    let mut out = Vec::new();
    for class in classes {
        let Some(decl) = emitter.sema.declaration(class).and_then(|(node, _)| ast::TypeDecl::cast(node)) else {
            continue;
        };
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
