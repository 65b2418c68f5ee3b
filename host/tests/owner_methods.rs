//! Methods of a kernel's OpenCL class as WGSL functions: a device diagram calls methods of its
//! owner (one calling another, one reading `get_global_id`, a float one), they run on the GPU
//! and compute what the same code computes in Rust (one implemented by a diagram it ends with
//! calling); what WGSL cannot take — recursion, a
//! pointer parameter, a field, a method without a body — is an error at its place.

mod support;

use support::{compute_kernel, generated_from, generation, run_compute_kernel};

const CLASS: &str = "ClassDiagram Maths
{
    import OpenCL.GPU.*;

    public class Kernels implements OpenCL
    {
        public void compute(global ref int out);
        public int twice(int v) { return v * 2; }
        public int capped(int v, int limit) { if (v > limit) { return limit; } return v; }
        public int twicePlusOne(int v) { return twice(v) + 1; }
        public float half(int v) { return v / 2.0f; }
        public int idPlus(int k) { return get_global_id(0) + k; }
        public void nothing() { return; }
        public int signOf(int v) { if (v < 500) { return -1; } else { return 1; } }
        public int again(int v) { return twiceAgain(v); }
        public int twiceAgain(int v) { return again(v) * 2; }
        public int byPointer(global ref int p) { return p[0]; }
        public int scale;
        public int scaled(int v) { return v * scale; }
        public int declared(int v);
        public int smaller(int a, int b) { call behavior Smaller(a, b); }
    }
}
";

/// The diagram that implements `smaller` (a body that ends with `call behavior`, Listing 36).
const SMALLER: &str = "ActivityDiagram Smaller(int a, int b)
{
    start s { => pick; }
    decision pick { [a < b] => first; [] => second; }
    final first return a;
    final second return b;
}
";

fn sources(body: &str) -> Vec<(String, String)> {
    vec![
        ("maths.gudsl".into(), CLASS.into()),
        ("smaller.gudsl".into(), SMALLER.into()),
        ("compute.gudsl".into(), compute_kernel("Maths.Kernels", body)),
    ]
}

#[test]
fn owner_methods_run_as_functions_and_compute_what_rust_does() {
    let body = "            nothing();
            out[id] = capped(twicePlusOne(id), 1500) + idPlus(3) - id + (int)half(id) + signOf(id);";
    let kernel = generated_from(&sources(body), "compute");
    for function in
        ["fn Kernels_twice(v: i32) -> i32", "fn Kernels_capped(", "fn Kernels_idPlus(", "fn Kernels_nothing()"]
    {
        assert!(kernel.wgsl.contains(function), "{function} in\n{}", kernel.wgsl);
    }
    // `get_global_id` inside a function reads a private copy the entry point sets.
    assert!(kernel.wgsl.contains("var<private> gudsl_global_id: vec3<u32>;"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> = (0..count as i32)
        .map(|id| (id * 2 + 1).min(1500) + (id + 3) - id + (id as f32 / 2.0) as i32 + if id < 500 { -1 } else { 1 })
        .collect();
    assert_eq!(got, expected);
}

#[test]
fn a_method_implemented_by_a_behavior_returns_the_behaviors_value() {
    let kernel = generated_from(&sources("            out[id] = smaller(id, 600);"), "compute");
    assert!(kernel.wgsl.contains("return Smaller(a, b);"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> = (0..count as i32).map(|id| id.min(600)).collect();
    assert_eq!(got, expected);
}

#[test]
fn what_wgsl_cannot_take_is_an_error_at_its_place() {
    let errors = |body: &str| generation(&sources(body), "compute").expect_err("not generated");
    let recursion = errors("            out[id] = again(id);");
    assert!(
        recursion.iter().any(|(path, line, m)| path == "maths.gudsl" && *line == 15 && m.contains("recursively")),
        "{recursion:?}"
    );
    let pointer = errors("            out[id] = byPointer(out);");
    assert!(pointer.iter().any(|(_, line, m)| *line == 17 && m.contains("numbers and vectors only")), "{pointer:?}");
    let field = errors("            out[id] = scaled(id);");
    assert!(field.iter().any(|(_, line, m)| *line == 19 && m.contains("fields of the class")), "{field:?}");
    let no_body = errors("            out[id] = declared(id);");
    assert!(
        no_body.iter().any(|(path, line, m)| path == "compute.gudsl" && *line == 11 && m.contains("no body")),
        "{no_body:?}"
    );
    let unknown = errors("            out[id] = twice(id, 2);");
    assert!(unknown.iter().any(|(_, _, m)| m.contains("with 2 parameter(s)")), "{unknown:?}");
}
