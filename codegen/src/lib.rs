//! gudsl-codegen: the GPGPU extension's device code (chapter 10) as WGSL. Every activity diagram
//! owned by a class that implements `OpenCL` becomes one compute entry point whose parameters
//! are bindings (`Kernel::params` says how the host binds each), its variables and node bodies
//! private code, its control flow a state loop over its nodes; every module is validated with
//! naga before it is handed out. What cannot be generated is a [`CodegenError`] with the range
//! of the construct, for the editor and the CLI.

mod atomics;
mod builtins;
mod emitter;
mod expr;
mod flow;
mod functions;
mod images;
mod kernel;
pub mod queries;
mod stmt;
mod structured;
mod types;
mod validate;

use gudsl_model::{
    ast::{self, AstNode},
    db::SourceFile,
    hir::{DefKind, Definition, Semantics, Ty},
    syntax::TextRange,
};

pub use types::ImageType;

/// A generated compute shader and how the host binds it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Kernel {
    /// The activity diagram's fully qualified name.
    pub diagram: String,
    /// The entry point's name in [`Kernel::wgsl`].
    pub entry_point: String,
    pub wgsl: String,
    /// The diagram's parameters, in order, with their bindings.
    pub params: Vec<KernelParam>,
    /// Whether the kernel synchronises its work-group (`barrier`): then every work-item of a
    /// group must run it, so the global size must be a multiple of the work-group size (as in
    /// OpenCL); otherwise work-items past the global size return at once.
    pub uses_barriers: bool,
    /// The uniform block at `@group(0) @binding(0)`.
    pub uniform: UniformBlock,
}

/// The pipeline constants (`override`) that give every kernel its work-group size, x, y and z;
/// the host sets them at each launch.
pub const LOCAL_SIZE_CONSTANTS: [&str; 3] = ["gudsl_local_size_x", "gudsl_local_size_y", "gudsl_local_size_z"];

/// The layout of the uniform block `params` (WGSL's uniform layout rules, as naga computes them):
/// each value parameter's offset is in its [`Binding::Uniform`]; the host also fills the global
/// size (`vec3<u32>`) and the number of work dimensions (`u32`).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct UniformBlock {
    /// Bytes, padded as WGSL requires.
    pub size: u32,
    pub global_size_offset: u32,
    pub work_dim_offset: u32,
}

/// One parameter of a kernel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KernelParam {
    pub name: String,
    pub ty: Ty,
    pub binding: Binding,
}

/// How the host hands a parameter to the kernel.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Binding {
    /// A field of the uniform block `params` at `@group(0) @binding(0)`, `offset` bytes into it
    /// (scalars and vectors of 32-bit components; `bool` as `u32`).
    Uniform { offset: u32 },
    /// A storage buffer (`global ref T`, `buffer2D_*`): `array<T>` at this binding.
    Storage { binding: u32, writable: bool },
    /// A typed image: a texture when only read, a storage texture when written.
    Image { binding: u32, image: ImageType, read: bool, written: bool },
    /// `shared` work-group memory of elements of `element_size` bytes, sized by the pipeline
    /// constant `length_constant` (elements). The host passes bytes, as OpenCL's
    /// `clSetKernelArg(…, size, NULL)` does.
    Workgroup { length_constant: String, element_size: u32 },
}

/// Something the generator cannot turn into WGSL, where it is written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CodegenError {
    pub file: SourceFile,
    pub range: TextRange,
    pub message: String,
}

/// The kernels: the activity diagrams that are device code — owned (the diagram or one of its
/// swimlanes) by a class that implements `OpenCL` — and return no value (those that do are
/// device functions, [`is_kernel`]). Library diagrams are not among them.
pub fn device_diagrams<'db>(sema: &Semantics<'db>) -> Vec<&'db Definition> {
    let mut out: Vec<&'db Definition> = sema
        .def_map()
        .definitions
        .values()
        .flatten()
        .filter(|def| matches!(def.kind, DefKind::Activity(_)))
        .filter(|def| !gudsl_model::library::is_library(sema.db(), def.file))
        .filter(|def| is_kernel(sema, def))
        .collect();
    out.sort_by(|a, b| a.fqn.cmp(&b.fqn));
    out
}

/// Whether an activity diagram is device code: owned by a class that implements `OpenCL`.
pub fn is_device_diagram(sema: &Semantics<'_>, def: &Definition) -> bool {
    sema.activity_owners(def).into_iter().any(|owner| sema.is_gpu_class(owner))
}

/// Whether a device diagram is a kernel (see [`device_diagrams`]): one that returns a value
/// (`final f return v`, as a `call behavior` of it from device code reads) is a device function,
/// generated into the kernels that call it — an OpenCL kernel returns `void`.
pub fn is_kernel(sema: &Semantics<'_>, def: &Definition) -> bool {
    is_device_diagram(sema, def) && !returns_a_value(sema, def)
}

/// Whether a final node of the diagram's own flow returns a value.
fn returns_a_value(sema: &Semantics<'_>, def: &Definition) -> bool {
    let diagram = sema.declaration(def).and_then(|(node, _)| ast::ActivityDiagram::cast(node));
    diagram.is_some_and(|d| {
        d.all_nodes().any(|n| n.kind() == ast::NodeKind::Final && n.container().is_none() && n.return_value().is_some())
    })
}

/// The device diagram that implements the method `method` of the OpenCL class `class` (what a
/// calc node's `call Class::method(…)` launches): owned by the class, with the method's
/// parameter names in order. Otherwise a message that says what is missing.
pub fn implementation<'db>(
    sema: &Semantics<'db>,
    class: &'db Definition,
    method: &str,
) -> Result<&'db Definition, String> {
    let signatures = sema.methods(class, method);
    let Some((_, signature)) = signatures.first() else {
        return Err(format!("`{}` has no method `{method}`", class.fqn));
    };
    let names: Vec<&str> = signature.params.iter().map(|p| p.name.as_str()).collect();
    let owned: Vec<&'db Definition> = device_diagrams(sema)
        .into_iter()
        .filter(|def| sema.activity_owners(def).iter().any(|owner| owner.fqn == class.fqn))
        .collect();
    let matching: Vec<&'db Definition> = owned
        .iter()
        .copied()
        .filter(|def| {
            let DefKind::Activity(activity) = &def.kind else { return false };
            activity.params.iter().map(|p| p.name.as_str()).eq(names.iter().copied())
        })
        .collect();
    match matching[..] {
        [diagram] => Ok(diagram),
        [] if owned.is_empty() => Err(format!(
            "no device diagram implements `{}::{method}`: an activity diagram owned by `{}` (`swimlane …, owner {}`) with the parameters ({}) does",
            class.fqn,
            class.fqn,
            class.fqn,
            names.join(", ")
        )),
        [] => Err(format!(
            "no device diagram owned by `{}` has the parameters of `{method}` ({}); it owns {}",
            class.fqn,
            names.join(", "),
            owned.iter().map(|d| format!("`{}`", d.fqn)).collect::<Vec<_>>().join(", ")
        )),
        _ => Err(format!(
            "several device diagrams implement `{}::{method}`: {}",
            class.fqn,
            matching.iter().map(|d| format!("`{}`", d.fqn)).collect::<Vec<_>>().join(", ")
        )),
    }
}

/// The kernel of a device diagram, validated; or what could not be generated. Remembered by
/// the database ([`queries::device_kernel`]): asked again in the same revision, it is not
/// generated again.
pub fn generate(sema: &Semantics<'_>, diagram: &Definition) -> Result<Kernel, Vec<CodegenError>> {
    let db = sema.db();
    let fqn = gudsl_model::hir::Fqn::new(db, diagram.fqn.clone());
    let remembered = queries::device_kernel(db, sema.workspace(), fqn);
    // The query answers for the first device diagram of the name; a duplicate is generated here.
    match remembered {
        Some(kernel) if queries::device_diagram_named(sema, &diagram.fqn) == Some(diagram) => kernel.clone(),
        _ => queries::generate_uncached(sema, diagram),
    }
}
