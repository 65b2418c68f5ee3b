//! The bundled library's OpenCL C built-ins as WGSL: work-item functions from the entry point's
//! built-in values and the uniform block, `barrier`/`mem_fence` as work-group and storage
//! barriers, math and geometric functions; image functions are `images.rs`'s, atomic ones
//! `atomics.rs`'s.

use gudsl_model::{
    ast::{self, AstNode},
    hir::Ty,
    library::OPENCL_INTERFACE,
};

use crate::emitter::{bare, Emitter};

/// OpenCL math and geometric functions and their WGSL names.
const MATH: &[(&str, &str)] = &[
    ("abs", "abs"),
    ("fabs", "abs"),
    ("acos", "acos"),
    ("asin", "asin"),
    ("atan", "atan"),
    ("atan2", "atan2"),
    ("ceil", "ceil"),
    ("clamp", "clamp"),
    ("cos", "cos"),
    ("cross", "cross"),
    ("distance", "distance"),
    ("dot", "dot"),
    ("exp", "exp"),
    ("exp2", "exp2"),
    ("floor", "floor"),
    ("fmax", "max"),
    ("fmin", "min"),
    ("length", "length"),
    ("log", "log"),
    ("log2", "log2"),
    ("max", "max"),
    ("min", "min"),
    ("mix", "mix"),
    ("normalize", "normalize"),
    ("pow", "pow"),
    ("round", "round"),
    ("rsqrt", "inverseSqrt"),
    ("sign", "sign"),
    ("sin", "sin"),
    ("sqrt", "sqrt"),
    ("step", "step"),
    ("tan", "tan"),
    ("trunc", "trunc"),
];

impl Emitter<'_> {
    /// A call: an OpenCL built-in of the bundled library, or a method of the owner
    /// (`functions.rs`).
    pub fn call(&mut self, call: &ast::CallExpr) -> String {
        let Some(ast::Expr::NameExpr(callee)) = call.callee() else {
            return self.unsupported(call.syntax(), "calls on a receiver are not generated for the GPU yet");
        };
        let name = callee.name_ref().map(|n| n.text()).unwrap_or_default();
        if !self.sema.has_method(OPENCL_INTERFACE, &name) {
            return self.method_call(call, &name);
        }
        let args: Vec<ast::Expr> = call.args().collect();
        let result = self.ty(&ast::Expr::CallExpr(call.clone()));
        let dimension = |emitter: &mut Self| match args.first() {
            Some(arg) => emitter.dimension(arg),
            None => ".x".to_string(),
        };
        match name.as_str() {
            "get_global_id" => format!("i32(gudsl_global_id{})", dimension(self)),
            "get_local_id" => format!("i32(gudsl_local_id{})", dimension(self)),
            "get_group_id" => format!("i32(gudsl_group_id{})", dimension(self)),
            "get_num_groups" => format!("i32(gudsl_num_groups{})", dimension(self)),
            "get_local_size" => format!("i32(gudsl_local_size{})", dimension(self)),
            "get_global_size" => format!("i32(params.gudsl_global_size{})", dimension(self)),
            "get_work_dim" => "i32(params.gudsl_work_dim)".into(),
            "get_global_offset" => "0i".into(),
            "barrier" | "mem_fence" | "read_mem_fence" | "write_mem_fence" => self.barrier(&args),
            "read_imagef" | "read_imagei" | "read_imageui" => self.read_image(call, &args, &result),
            "write_imagef" | "write_imagei" | "write_imageui" => self.write_image(call, &args),
            atomic if atomic.starts_with("atomic_") => self.atomic(call, atomic, &args),
            "get_image_width" => self.image_size(call, &args, "x"),
            "get_image_height" => self.image_size(call, &args, "y"),
            "get_image_depth" => self.image_size(call, &args, "z"),
            _ => match MATH.iter().find(|(opencl, _)| *opencl == name) {
                Some((_, wgsl)) => {
                    let parts: Vec<String> = args.iter().map(|arg| bare(self.math_argument(arg, &result))).collect();
                    format!("{wgsl}({})", parts.join(", "))
                }
                None => self.unsupported(call.syntax(), format!("`{name}` has no WGSL form in the generator yet")),
            },
        }
    }

    /// The component of a `vec3<u32>` a dimension argument selects.
    fn dimension(&mut self, arg: &ast::Expr) -> String {
        if let ast::Expr::Literal(literal) = arg {
            match literal.token().map(|t| t.text().to_string()).as_deref() {
                Some("0") => return ".x".into(),
                Some("1") => return ".y".into(),
                Some("2") => return ".z".into(),
                _ => {}
            }
        }
        format!("[{}]", self.expr_as(arg, &Ty::UInt))
    }

    /// A math argument in the type the WGSL function takes: the call's type for scalars of a
    /// vector call (splatted) and for numbers of another kind; vectors of a scalar result
    /// (`dot`, `length`) as they are.
    fn math_argument(&mut self, arg: &ast::Expr, result: &Ty) -> String {
        let ty = self.ty(arg);
        match (ty.dereferenced(), result.dereferenced()) {
            (Ty::Vector(..), Ty::Int | Ty::UInt | Ty::Float) => self.expr(arg),
            (_, Ty::Int | Ty::UInt | Ty::Float | Ty::Vector(..)) => self.expr_as(arg, result),
            _ => self.expr(arg),
        }
    }

    /// `barrier(CLK_LOCAL_MEM_FENCE)`: a work-group barrier; `CLK_GLOBAL_MEM_FENCE`: a storage
    /// barrier; both when both are named.
    fn barrier(&mut self, args: &[ast::Expr]) -> String {
        self.uses_barriers = true;
        let flags = args.first().map(|a| a.syntax().text().to_string()).unwrap_or_default();
        let mut barriers = Vec::new();
        if flags.contains("GLOBAL") {
            barriers.push("storageBarrier()");
        }
        if flags.contains("LOCAL") || barriers.is_empty() {
            barriers.push("workgroupBarrier()");
        }
        barriers.join("; ")
    }
}
