//! Methods of the owner and called diagrams as WGSL functions: a device diagram's call of a
//! method of its OpenCL class (or a base) that has a body, and its `call behavior` of another
//! activity diagram, become calls of a function generated once per module, with the method's or
//! diagram's value parameters and return type (a diagram's: what its `final … return` gives);
//! what those call follows. A method whose body ends with `call behavior X(…)` is implemented
//! by `X` (Listing 36) and returns its value. What WGSL cannot take is an error at its place:
//! recursion, pointer or image parameters, fields of the class, overloads of the same arity, a
//! method without a body, `out` parameters of a diagram.

use gudsl_model::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{infer::implementing_behavior, BodyTypes, DefKind, Definition, Scope, Ty},
    syntax::{SyntaxKind, SyntaxNode},
};

use std::collections::HashMap;

use crate::{
    emitter::{bare, ident, Body, Call, Emitter, Function},
    types::value_type,
    Binding, KernelParam,
};

impl<'db> Emitter<'db> {
    /// Leaves the entry point, or the function being written (with its type's zero where it
    /// returns a value: a diagram that ends without `final … return`).
    pub fn leave(&mut self) {
        match self.current_function.as_ref().and_then(|(_, ty)| value_type(ty)) {
            Some(ty) => self.line(format!("return {ty}();")),
            None => self.line("return;"),
        }
    }

    /// `name(args)` where `name` is no OpenCL built-in: a method of the diagram's owner.
    pub fn method_call(&mut self, call: &ast::CallExpr, name: &str) -> String {
        let args: Vec<ast::Expr> = call.args().collect();
        let Some(owner) = self.owner else {
            return self.unsupported(
                call.syntax(),
                format!("`{name}` is no OpenCL built-in, and the diagram has no OpenCL owner whose method it could be"),
            );
        };
        let found = self.sema.method_declarations(owner, name, args.len());
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
        let Some(callee) = self.function_index(class, &method, &args) else {
            return self.unsupported(call.syntax(), format!("`{name}` cannot be generated (see its declaration)"));
        };
        self.function_call(callee, &args, call.syntax())
    }

    /// `call behavior X(args)`: a call of the function generated from the diagram `X`.
    pub fn behavior_call(&mut self, call: &ast::CallBehaviorExpr) -> String {
        let args: Vec<ast::Expr> = call.args().collect();
        let Some(path) = call.behavior() else { return self.unsupported(call.syntax(), "an incomplete call") };
        let def = self.sema.resolve(&Scope::at(call.syntax()), &path.text());
        let Some(def) = def.filter(|def| matches!(def.kind, DefKind::Activity(_))) else {
            // What `X` is, is validation's (E0211).
            return self.unsupported(call.syntax(), format!("`{}` is no activity diagram", path.text()));
        };
        let diagram = self.sema.declaration(def).and_then(|(node, _)| ast::ActivityDiagram::cast(node));
        let Some(diagram) = diagram.filter(|d| d.params().count() == args.len()) else {
            return self.unsupported(call.syntax(), format!("`{}` takes other arguments", def.fqn));
        };
        let Some(callee) = self.diagram_index(def, diagram, call) else {
            return self.unsupported(call.syntax(), format!("`{}` cannot be generated (see its declaration)", def.fqn));
        };
        self.function_call(callee, &args, call.syntax())
    }

    /// `name(args)` of function `callee`, its value arguments converted to its parameters'
    /// types (the buffers are its specialisation's); the call recorded (for recursion).
    fn function_call(&mut self, callee: usize, args: &[ast::Expr], at: &SyntaxNode) -> String {
        let caller = self.current_function.as_ref().map(|(index, _)| *index);
        self.calls.push(Call { caller, callee, place: (self.file, at.text_range()) });
        let function = &self.functions[callee];
        let params: Vec<(String, Ty)> = function.params.clone();
        let out_params = function.out_params.clone();
        let passed: Vec<&ast::Expr> = args.iter().zip(&function.passed).filter(|(_, p)| **p).map(|(a, _)| a).collect();
        let name = function.name.clone();
        let args: Vec<String> = passed
            .into_iter()
            .zip(&params)
            .map(|(arg, (param, ty))| match out_params.contains(param) {
                // The caller's own `out` parameter is already the pointer.
                true => self.out_param_named(arg).unwrap_or_else(|| format!("&{}", self.expr(arg))),
                false => bare(self.expr_as(arg, ty)),
            })
            .collect();
        format!("{name}({})", args.join(", "))
    }

    /// The index of the diagram `def` among the functions, added (its parameters checked)
    /// when first called; `None` when it cannot be a function (reported at the declaration).
    fn diagram_index(
        &mut self,
        def: &'db Definition,
        diagram: ast::ActivityDiagram,
        call: &ast::CallBehaviorExpr,
    ) -> Option<usize> {
        let body = Body::Diagram(def, diagram.clone());
        let args: Vec<ast::Expr> = call.args().collect();
        let types = self.sema.body_types(diagram.syntax());
        let Parameters { values: params, passed, bound, out_params, mut fine } =
            self.parameters(diagram.params(), &types, &args, def);
        if let Some(index) = self.functions.iter().position(|f| f.body == body && f.bound == bound) {
            return Some(index);
        }
        let returns = self.ty(&ast::Expr::CallBehaviorExpr(call.clone()));
        let at = call.syntax();
        if returns == Ty::Unknown {
            self.unsupported(
                at,
                format!(
                    "what `{}` returns has no known type (a `final … return` value that calls a diagram is not \
                     typed): return a variable of a declared type instead",
                    def.fqn
                ),
            );
            fine = false;
        } else if returns != Ty::Void && value_type(&returns).is_none() {
            self.unsupported(at, format!("`{}` returns a `{returns}`, which has no WGSL value type", def.fqn));
            fine = false;
        }
        if !fine {
            return None;
        }
        let name = specialised(def.fqn.rsplit('.').next().unwrap_or_default(), &bound);
        self.functions.push(Function { body, name, params, passed, bound, out_params, returns });
        Some(self.functions.len() - 1)
    }

    /// A function's parameters at a call with `args`: its value parameters (numbers and
    /// vectors), and its buffer, image and `shared` parameters bound to the kernel parameters
    /// the call passes; whether WGSL can take them all (each other one is an error at its place,
    /// in the file of `declared`).
    fn parameters(
        &mut self,
        params: impl Iterator<Item = ast::Param>,
        types: &BodyTypes,
        args: &[ast::Expr],
        declared: &Definition,
    ) -> Parameters {
        let mut out = Parameters {
            values: Vec::new(),
            passed: Vec::new(),
            bound: Vec::new(),
            out_params: Vec::new(),
            fine: true,
        };
        for (index, param) in params.enumerate() {
            let Some(name) = param.name().map(|n| n.text()) else { continue };
            let ty = types.locals.get(&name).cloned().unwrap_or(Ty::Unknown);
            if is_memory(&param, &ty) {
                match args.get(index).and_then(|arg| self.passed_memory(arg)) {
                    Some(global) => out.bound.push((name, global)),
                    None => {
                        let at = args.get(index).map_or_else(|| param.syntax().clone(), |a| a.syntax().clone());
                        self.unsupported(
                            &at,
                            format!(
                                "`{name}` takes a buffer, image or `shared` memory: pass a parameter of the kernel (or of \
                                 the function calling) that is one, by its name — a generated function is specialised \
                                 for the memory each call passes"
                            ),
                        );
                        out.fine = false;
                    }
                }
                out.passed.push(false);
                continue;
            }
            let is_out = param.has_modifier(SyntaxKind::OUT_KW);
            if is_out && !args.get(index).is_some_and(|arg| self.is_variable(arg)) {
                let at = args.get(index).map_or_else(|| param.syntax().clone(), |a| a.syntax().clone());
                self.unsupported(&at, format!("`{name}` is `out`: pass a variable by its name, which the call sets"));
                out.fine = false;
            }
            let value = match &ty {
                Ty::Ref { inner, .. } if is_out => inner.as_ref().clone(),
                _ => ty.clone(),
            };
            let problem = if value_type(&value).is_none() || matches!(value, Ty::Ref { .. } | Ty::Array(_)) {
                Some(format!("`{name}` is a `{ty}`: generated functions take numbers, vectors, buffers and images"))
            } else {
                None
            };
            if let Some(problem) = problem {
                let file = std::mem::replace(&mut self.file, declared.file);
                self.unsupported(param.syntax(), problem);
                self.file = file;
                out.fine = false;
            }
            if is_out {
                out.out_params.push(name.clone());
            }
            out.values.push((name, value));
            out.passed.push(true);
        }
        out
    }

    /// Whether `arg` names a variable of the body being written (a local, a diagram variable or
    /// an `out` parameter of its own): what an `out` parameter points to.
    fn is_variable(&self, arg: &ast::Expr) -> bool {
        let ast::Expr::NameExpr(name) = arg else { return false };
        let Some(name) = name.name_ref().map(|n| n.text()) else { return false };
        self.binding(&name).is_none() && self.types.locals.contains_key(&name) && !self.is_value_param(&name)
    }

    /// `arg` as the pointer it is when it names an `out` parameter of the function being written.
    fn out_param_named(&self, arg: &ast::Expr) -> Option<String> {
        let ast::Expr::NameExpr(name) = arg else { return None };
        let name = name.name_ref()?.text();
        self.is_out_param(&name).then(|| ident(&name))
    }

    /// Whether `name` is a value parameter (not `out`) of the function being written: WGSL
    /// function parameters are not variables.
    fn is_value_param(&self, name: &str) -> bool {
        let is_param = self.function_written().is_some_and(|f| f.params.iter().any(|(p, _)| p == name));
        is_param && !self.is_out_param(name)
    }

    /// The kernel parameter `arg` passes when it names a buffer, image or `shared` parameter of
    /// the kernel, or one the function being written is bound to.
    fn passed_memory(&self, arg: &ast::Expr) -> Option<String> {
        let ast::Expr::NameExpr(name) = arg else { return None };
        let name = name.name_ref()?.text();
        match self.binding(&name)? {
            Binding::Storage { .. } | Binding::Image { .. } | Binding::Workgroup { .. } => {
                Some(self.global_name(&name))
            }
            Binding::Uniform { .. } => None,
        }
    }

    /// The index of `method` among the functions, added (its signature checked) when first
    /// called; `None` when its signature has no WGSL form (reported at the declaration).
    fn function_index(&mut self, class: &'db Definition, method: &ast::Method, args: &[ast::Expr]) -> Option<usize> {
        let body = Body::Method(class, method.clone());
        let types = self.sema.body_types(method.syntax());
        let Parameters { values: params, passed, bound, out_params, mut fine } =
            self.parameters(method.params(), &types, args, class);
        if let Some(index) = self.functions.iter().position(|f| f.body == body && f.bound == bound) {
            return Some(index);
        }
        let name = method.name().map(|n| n.text()).unwrap_or_default();
        let file = self.file;
        self.file = class.file;
        let returns = self
            .sema
            .methods(class, &name)
            .into_iter()
            .find(|(declared, signature)| declared.fqn == class.fqn && signature.params.len() == passed.len())
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
        let name = specialised(&format!("{class_name}_{name}"), &bound);
        self.functions.push(Function { body, name, params, passed, bound, out_params, returns });
        Some(self.functions.len() - 1)
    }

    /// The functions called so far (and those they call), as WGSL; then every recursion is an
    /// error at the call that closes it. Written after the kernel's body was taken.
    pub fn functions_wgsl(&mut self) -> String {
        let kernel_types = std::mem::take(&mut self.types);
        let kernel_file = self.file;
        let kernel_params = std::mem::take(&mut self.params);
        let mut index = 0;
        while index < self.functions.len() {
            let function = self.functions[index].clone();
            self.types = self.sema.body_types(function.body.syntax());
            self.file = function.body.definition().file;
            self.current_function = Some((index, function.returns.clone()));
            // Its names are its own: the kernel's parameters are in scope only as the memory
            // its specialisation is bound to.
            self.params = function
                .bound
                .iter()
                .filter_map(|(name, global)| Some((name.clone(), kernel_params.get(global)?.clone())))
                .collect();
            self.check_bound_use(&function, &kernel_params);
            let params: Vec<String> = function
                .params
                .iter()
                .map(|(name, ty)| {
                    let ty = value_type(ty).unwrap_or_default();
                    match function.out_params.contains(name) {
                        true => format!("{}: ptr<function, {ty}>", ident(name)),
                        false => format!("{}: {ty}", ident(name)),
                    }
                })
                .collect();
            let returns = value_type(&function.returns).map(|ty| format!(" -> {ty}")).unwrap_or_default();
            let header = format!("fn {}({}){returns} {{", function.name, params.join(", "));
            match &function.body {
                Body::Method(class, method) => {
                    self.line(format!("// {}::{}", class.fqn, method.name().map(|n| n.text()).unwrap_or_default()));
                    let mut statements: Vec<ast::Stmt> =
                        method.body().map(|b| b.statements().collect()).unwrap_or_default();
                    // A body that ends with `call behavior X(…)` is implemented by `X`: its value
                    // is the method's (the model checked that it fits, E0234/E0235).
                    let implementing = method
                        .body()
                        .and_then(|b| implementing_behavior(&b))
                        .filter(|_| value_type(&function.returns).is_some());
                    if implementing.is_some() {
                        statements.pop();
                    }
                    self.block(header, |e| {
                        for stmt in &statements {
                            e.statement(stmt);
                        }
                        if let Some(call) = &implementing {
                            let value = bare(e.expr_as(&ast::Expr::CallBehaviorExpr(call.clone()), &function.returns));
                            e.line(format!("return {value};"));
                            return;
                        }
                        // The model checked that every path returns (E0235); WGSL also asks for
                        // a value after a last statement that returns on each of its branches.
                        let ends_in_return = matches!(statements.last(), Some(ast::Stmt::ReturnStmt(_)));
                        if let Some(ty) = value_type(&function.returns).filter(|_| !ends_in_return) {
                            e.line(format!("return {ty}();"));
                        }
                    });
                }
                Body::Diagram(def, diagram) => {
                    self.line(format!("// activity diagram {}", def.fqn));
                    self.block(header, |e| {
                        crate::kernel::variables(e, diagram);
                        e.control_flow(diagram, &diagram.all_nodes().collect::<Vec<_>>());
                        // A diagram that ends without `final … return` gives its type's zero.
                        if let Some(ty) = value_type(&function.returns).filter(|_| !e.ends_in_return()) {
                            e.line(format!("return {ty}();"));
                        }
                    });
                }
            }
            self.line("");
            index += 1;
        }
        self.params = kernel_params;
        self.current_function = None;
        self.types = kernel_types;
        self.file = kernel_file;
        self.report_recursion();
        self.take_output()
    }

    /// What a function does with the memory it is bound to, against how the kernel binds it: a
    /// buffer it writes is written by the kernel; an image it reads or writes the kernel must
    /// read or write the same way (a read image is a texture, a written one a storage texture).
    fn check_bound_use(&mut self, function: &Function<'db>, kernel_params: &HashMap<String, KernelParam>) {
        let body = function.body.syntax().clone();
        for (name, global) in &function.bound {
            match kernel_params.get(global).map(|p| &p.binding) {
                Some(Binding::Storage { .. }) if crate::kernel::written(&body, name) => {
                    self.written_memory.insert(global.clone());
                }
                Some(Binding::Image { read, written, .. }) => {
                    let (reads, writes) = crate::kernel::image_use(&body, name);
                    if (reads && !read) || (writes && !written) {
                        let how = if writes { "writes" } else { "reads" };
                        let at = function
                            .body
                            .params()
                            .find(|p| p.name().is_some_and(|n| n.text() == *name))
                            .map_or_else(|| body.clone(), |p| p.syntax().clone());
                        self.unsupported(
                            &at,
                            format!(
                                "`{}` {how} the image `{name}`, which the kernel binds as `{global}` and does not \
                                 itself {}: an image is a texture or a storage texture for the whole kernel",
                                function.name,
                                how.trim_end_matches('s')
                            ),
                        );
                    }
                }
                _ => {}
            }
        }
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

/// What a function's parameters are at one call (`Emitter::parameters`).
struct Parameters {
    values: Vec<(String, Ty)>,
    passed: Vec<bool>,
    bound: Vec<(String, String)>,
    out_params: Vec<String>,
    fine: bool,
}

/// Whether a parameter is memory a kernel binds (a buffer, an image, `shared` memory) rather
/// than a value.
fn is_memory(param: &ast::Param, ty: &Ty) -> bool {
    let global_ref = matches!(ty, Ty::Ref { .. }) && param.has_modifier(SyntaxKind::GLOBAL_KW);
    let gpu = matches!(ty, Ty::Gpu(name) if name.starts_with("image") || name.starts_with("buffer"));
    param.has_modifier(SyntaxKind::SHARED_KW) || global_ref || gpu || matches!(ty, Ty::Array(_))
}

/// The name of a function's specialisation for the kernel memory it is bound to: `base`
/// itself when it takes none, else `base_data_scratch`.
fn specialised(base: &str, bound: &[(String, String)]) -> String {
    let mut name = base.to_string();
    for (_, global) in bound {
        name.push('_');
        name.push_str(global);
    }
    ident(&name)
}
