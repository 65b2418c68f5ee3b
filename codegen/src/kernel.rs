//! One device diagram as one WGSL module: its parameters as bindings (a uniform block for
//! values, storage buffers, textures, work-group memory sized by pipeline constants), its
//! variables as the work-item's private variables, its nodes as the entry point's control flow,
//! the work-group size as pipeline constants; then naga validates the module.

use std::collections::{HashMap, HashSet};

use gudsl_model::{
    ast::{self, AstNode, HasModifiers, HasName},
    hir::{Definition, Semantics, Ty},
    syntax::{SyntaxKind, SyntaxNode},
};

use crate::{
    emitter::{ident, Emitter, GENERATED},
    types::{value_type, ImageType},
    validate, Binding, CodegenError, Kernel, KernelParam, UniformBlock, LOCAL_SIZE_CONSTANTS,
};

pub(crate) fn generate(sema: &Semantics<'_>, def: &Definition) -> Result<Kernel, Vec<CodegenError>> {
    let diagram = sema.declaration(def).and_then(|(node, _)| ast::ActivityDiagram::cast(node));
    let Some(diagram) = diagram else {
        let error = CodegenError { file: def.file, range: Default::default(), message: "no activity diagram".into() };
        return Err(vec![error]);
    };
    let diagram_types = sema.body_types(diagram.syntax());
    let mut errors = Vec::new();
    let owner = sema.activity_owners(def).into_iter().find(|owner| sema.is_gpu_class(owner));
    let memory: HashSet<String> = diagram.params().filter_map(|p| p.name().map(|n| n.text())).collect();
    let atomics = crate::atomics::atomic_memory(sema, owner, diagram.syntax(), &memory);
    let params = parameters(def, &diagram, &diagram_types, &atomics, &mut errors);
    let by_name: HashMap<String, KernelParam> = params.iter().map(|p| (p.name.clone(), p.clone())).collect();
    let mut emitter = Emitter::new(*sema, def.file, by_name);
    emitter.errors = errors;
    emitter.atomics = atomics.clone();
    emitter.owner = owner;

    // The entry point's body first: it tells whether the kernel synchronises.
    let nodes: Vec<ast::ActivityNode> = diagram.all_nodes().collect();
    emitter.types = diagram_types.clone();
    variables(&mut emitter, &diagram);
    emitter.control_flow(&diagram, &nodes);
    let body = emitter.take_output();
    let functions = emitter.functions_wgsl();
    // A buffer a function writes is written by the kernel that binds it.
    let mut params = params;
    for param in &mut params {
        if let Binding::Storage { writable, .. } = &mut param.binding {
            *writable |= emitter.written_memory.contains(&param.name);
        }
    }
    let functions = emitter.compare_exchange_helpers() + &emitter.sampling_helpers() + &functions;

    let entry_point = ident(def.fqn.rsplit('.').next().unwrap_or("main"));
    let wgsl = module(&def.fqn, &entry_point, &params, &atomics, emitter.uses_barriers, &functions, &body);
    if !emitter.errors.is_empty() {
        return Err(emitter.errors);
    }
    let generator_bug = |message: String| {
        let range = diagram.name().map(|n| n.syntax().text_range()).unwrap_or_default();
        let message = format!("the generated WGSL does not validate (a generator bug, please report it): {message}");
        vec![CodegenError { file: def.file, range, message }]
    };
    let module = validate::validate(&wgsl).map_err(generator_bug)?;
    let uniform = layout(&module, &mut params).map_err(generator_bug)?;
    Ok(Kernel { diagram: def.fqn.clone(), entry_point, wgsl, params, uses_barriers: emitter.uses_barriers, uniform })
}

/// How each parameter of the diagram is bound.
fn parameters(
    def: &Definition,
    diagram: &ast::ActivityDiagram,
    types: &gudsl_model::hir::BodyTypes,
    atomics: &HashSet<String>,
    errors: &mut Vec<CodegenError>,
) -> Vec<KernelParam> {
    let mut next_binding = 1;
    let mut binding = || {
        next_binding += 1;
        next_binding - 1
    };
    let mut out = Vec::new();
    for param in diagram.params() {
        let Some(name) = param.name().map(|n| n.text()) else { continue };
        let ty = types.locals.get(&name).cloned().unwrap_or(Ty::Unknown);
        let kind = if param.has_modifier(SyntaxKind::SHARED_KW) {
            Some(Binding::Workgroup { length_constant: format!("{GENERATED}{}_length", ident(&name)), element_size: 0 })
        } else if matches!(ty, Ty::Ref { .. } | Ty::Array(_)) {
            storage_element(&ty).map(|_| Binding::Storage {
                binding: binding(),
                writable: written(diagram.syntax(), &name) || atomics.contains(&name),
            })
        } else {
            match &ty {
                Ty::Gpu(gpu) if gpu.starts_with("image") => ImageType::parse(gpu).map(|image| {
                    let (read, written) = image_use(diagram.syntax(), &name);
                    Binding::Image { binding: binding(), image, read, written }
                }),
                Ty::Gpu(gpu) if gpu.starts_with("buffer") => Some(Binding::Storage {
                    binding: binding(),
                    writable: written(diagram.syntax(), &name) || atomics.contains(&name),
                }),
                _ if value_type(&ty).is_some() => Some(Binding::Uniform { offset: 0 }),
                _ => None,
            }
        };
        match kind {
            Some(binding) => out.push(KernelParam { name, ty, binding }),
            None => errors.push(CodegenError {
                file: def.file,
                range: param.syntax().text_range(),
                message: format!("a `{ty}` parameter cannot be handed to a GPU kernel"),
            }),
        }
    }
    out
}

/// The element of a buffer parameter (`global ref unsigned int` → `u32`, `buffer2D_f4` →
/// `vec4<f32>`).
fn storage_element(ty: &Ty) -> Option<String> {
    match ty {
        Ty::Ref { inner, .. } => storage_element(inner),
        Ty::Array(inner) => storage_element(inner),
        Ty::Gpu(name) => {
            let rest = name.strip_prefix("buffer2D_").or_else(|| name.strip_prefix("buffer3D_"))?;
            let digits = rest.trim_start_matches(|c: char| c.is_ascii_alphabetic());
            let suffix = &rest[..rest.len() - digits.len()];
            let scalar = match suffix {
                "f" => "f32",
                "i" | "c" | "s" => "i32",
                "ui" | "uc" | "us" => "u32",
                _ => return None,
            };
            match digits {
                "" | "1" => Some(scalar.into()),
                "2" | "3" | "4" => Some(format!("vec{digits}<{scalar}>")),
                _ => None,
            }
        }
        Ty::Bool => None,
        other => value_type(other),
    }
}

/// Whether the diagram reads and writes the image `name` (`read_image…`, `write_image…`).
pub(crate) fn image_use(root: &SyntaxNode, name: &str) -> (bool, bool) {
    let (mut read, mut written) = (false, false);
    for call in root.descendants().filter_map(ast::CallExpr::cast) {
        let Some(ast::Expr::NameExpr(callee)) = call.callee() else { continue };
        let callee = callee.name_ref().map(|n| n.text()).unwrap_or_default();
        let first = call.args().next().map(|a| a.syntax().text().to_string());
        if first.as_deref() != Some(name) {
            continue;
        }
        read |= callee.starts_with("read_image");
        written |= callee.starts_with("write_image");
    }
    (read, written)
}

/// Whether the diagram writes into the buffer `name` (`name[i] = …`, `name[i]++`).
pub(crate) fn written(root: &SyntaxNode, name: &str) -> bool {
    let target_is_name = |target: Option<ast::Expr>| {
        let mut target = target;
        while let Some(ast::Expr::IndexExpr(index)) = &target {
            target = index.base();
        }
        matches!(target, Some(ast::Expr::NameExpr(n)) if n.name_ref().is_some_and(|r| r.text() == name))
    };
    root.descendants().filter_map(ast::Expr::cast).any(|expr| match expr {
        ast::Expr::BinExpr(bin) => bin.is_assignment() && target_is_name(bin.lhs()),
        ast::Expr::PostfixExpr(postfix) => target_is_name(postfix.operand()),
        ast::Expr::PrefixExpr(prefix) => {
            prefix.op().is_some_and(|t| matches!(t.kind(), SyntaxKind::PLUS2 | SyntaxKind::MINUS2))
                && target_is_name(prefix.operand())
        }
        _ => false,
    })
}

/// The diagram's variables: private to the work-item, zero unless initialised.
pub(crate) fn variables(emitter: &mut Emitter<'_>, diagram: &ast::ActivityDiagram) {
    for variable in diagram.variables() {
        let Some(name) = variable.name().map(|n| n.text()) else { continue };
        if let Some(declaration) = emitter.declaration("var", &name, variable.initializer(), variable.syntax()) {
            emitter.line(format!("{declaration};"));
        }
    }
    for decl in diagram.var_decls() {
        emitter.var_decl(&decl);
    }
}

/// Where naga laid out the uniform block and the work-group arrays: the offsets of the value
/// parameters and the element sizes of the `shared` ones go into their bindings.
fn layout(module: &naga::Module, params: &mut [KernelParam]) -> Result<UniformBlock, String> {
    let global = |name: &str| module.global_variables.iter().map(|(_, g)| g).find(|g| g.name.as_deref() == Some(name));
    let block = global("params").ok_or("no uniform block `params`")?;
    let naga::TypeInner::Struct { members, span } = &module.types[block.ty].inner else {
        return Err("the uniform block `params` is not a struct".into());
    };
    let offset = |name: &str| {
        members
            .iter()
            .find(|m| m.name.as_deref() == Some(name))
            .map(|m| m.offset)
            .ok_or_else(|| format!("no field `{name}` in the uniform block"))
    };
    for param in params.iter_mut() {
        match &mut param.binding {
            Binding::Uniform { offset: at } => *at = offset(&ident(&param.name))?,
            Binding::Workgroup { element_size, .. } => {
                let name = ident(&param.name);
                let array = global(&name).ok_or_else(|| format!("no work-group array `{name}`"))?;
                let naga::TypeInner::Array { stride, .. } = module.types[array.ty].inner else {
                    return Err(format!("the work-group memory `{name}` is not an array"));
                };
                *element_size = stride;
            }
            _ => {}
        }
    }
    Ok(UniformBlock {
        size: *span,
        global_size_offset: offset(&format!("{GENERATED}global_size"))?,
        work_dim_offset: offset(&format!("{GENERATED}work_dim"))?,
    })
}

/// The whole module around the entry point's body.
fn module(
    fqn: &str,
    entry_point: &str,
    params: &[KernelParam],
    atomics: &HashSet<String>,
    barriers: bool,
    functions: &str,
    body: &str,
) -> String {
    let mut out = format!("// Generated by gudsl from the activity diagram `{fqn}`.\n\n");
    out.push_str("struct Params {\n");
    for param in params.iter().filter(|p| matches!(p.binding, Binding::Uniform { .. })) {
        let ty = match param.ty.dereferenced() {
            Ty::Bool => "u32".to_string(),
            other => value_type(other).unwrap_or_default(),
        };
        out.push_str(&format!("    {}: {ty},\n", ident(&param.name)));
    }
    out.push_str(&format!("    {GENERATED}global_size: vec3<u32>,\n    {GENERATED}work_dim: u32,\n}}\n\n"));
    out.push_str("@group(0) @binding(0) var<uniform> params: Params;\n");
    for param in params {
        let name = ident(&param.name);
        // The elements an atomic function works on are atomic (`atomics.rs`).
        let atomic = |element: String| match atomics.contains(&param.name) {
            true => format!("atomic<{element}>"),
            false => element,
        };
        match &param.binding {
            Binding::Storage { binding, writable } => {
                let access = if *writable { "read_write" } else { "read" };
                let element = atomic(storage_element(&param.ty).unwrap_or_default());
                out.push_str(&format!(
                    "@group(0) @binding({binding}) var<storage, {access}> {name}: array<{element}>;\n"
                ));
            }
            Binding::Image { binding, image, read, written } => {
                let dims = image.dimensions;
                let ty = match (read, written) {
                    (_, false) => format!("texture_{dims}d<{}>", image.texel),
                    (false, true) => format!("texture_storage_{dims}d<{}, write>", image.format),
                    (true, true) => format!("texture_storage_{dims}d<{}, read_write>", image.format),
                };
                out.push_str(&format!("@group(0) @binding({binding}) var {name}: {ty};\n"));
            }
            Binding::Workgroup { length_constant, .. } => {
                let element = atomic(storage_element(&param.ty).unwrap_or_else(|| "i32".into()));
                out.push_str(&format!(
                    "override {length_constant}: u32 = 256u;\nvar<workgroup> {name}: array<{element}, {length_constant}>;\n"
                ));
            }
            Binding::Uniform { .. } => {}
        }
    }
    for (constant, default) in LOCAL_SIZE_CONSTANTS.iter().zip([64, 1, 1]) {
        out.push_str(&format!("override {constant}: u32 = {default}u;\n"));
    }
    out.push('\n');
    let [x, y, z] = LOCAL_SIZE_CONSTANTS;
    // Built-in values a function reads are private variables the entry point sets first.
    let private: Vec<&str> = ["global_id", "local_id", "group_id", "num_groups", "local_size"]
        .into_iter()
        .filter(|name| uses(functions, &format!("{GENERATED}{name}")))
        .collect();
    for name in &private {
        out.push_str(&format!("var<private> {GENERATED}{name}: vec3<u32>;\n"));
    }
    if !private.is_empty() {
        out.push('\n');
    }
    out.push_str(functions);
    // The built-in values the code reads (and the guard below), one per line when several.
    let code = format!("{functions}{body}");
    let builtins: Vec<(&str, &str)> = [
        ("global_invocation_id", "global_id"),
        ("local_invocation_id", "local_id"),
        ("workgroup_id", "group_id"),
        ("num_workgroups", "num_groups"),
    ]
    .into_iter()
    .filter(|(_, name)| uses(&code, &format!("{GENERATED}{name}")) || (*name == "global_id" && !barriers))
    .collect();
    let argument = |name: &str| match private.contains(&name) {
        true => format!("{GENERATED}{name}_in"),
        false => format!("{GENERATED}{name}"),
    };
    let inputs: Vec<String> =
        builtins.iter().map(|(builtin, name)| format!("@builtin({builtin}) {}: vec3<u32>", argument(name))).collect();
    let signature = match &inputs[..] {
        [] => String::new(),
        [one] => one.clone(),
        several => format!("\n    {},\n", several.join(",\n    ")),
    };
    out.push_str(&format!("@compute @workgroup_size({x}, {y}, {z})\nfn {entry_point}({signature}) {{\n"));
    for (_, name) in builtins.iter().filter(|(_, name)| private.contains(name)) {
        out.push_str(&format!("    {GENERATED}{name} = {GENERATED}{name}_in;\n"));
    }
    if private.contains(&"local_size") {
        out.push_str(&format!("    {GENERATED}local_size = vec3<u32>({x}, {y}, {z});\n"));
    } else if uses(body, &format!("{GENERATED}local_size")) {
        out.push_str(&format!("    let {GENERATED}local_size = vec3<u32>({x}, {y}, {z});\n"));
    }
    if !barriers {
        out.push_str(&format!(
            "    // Work-items past the global size (the last work-groups' spare ones) do nothing.\n    if any({GENERATED}global_id >= params.{GENERATED}global_size) {{ return; }}\n"
        ));
    }
    for line in body.lines() {
        out.push_str("    ");
        out.push_str(line);
        out.push('\n');
    }
    out.push_str("}\n");
    out
}

/// Whether `code` names the generated identifier `name` (not one it is a prefix of).
fn uses(code: &str, name: &str) -> bool {
    code.match_indices(name)
        .any(|(at, _)| !code[at + name.len()..].starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_'))
}
