//! Methods of a kernel's OpenCL class as WGSL functions: a device diagram calls methods of its
//! owner (one calling another, one reading `get_global_id`, a float one), they run on the GPU
//! and compute what the same code computes in Rust (one implemented by a diagram it ends with
//! calling), and methods that take the kernel's buffer write into it; what WGSL cannot take —
//! recursion, a value where a buffer belongs, a field, a method without a body — is an error at
//! its place.

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
        public void store(global ref int p, int at, int v) { p[at] = v; }
        public void storeTwice(global ref int p, int at, int v) { store(p, at, v * 2); }
        public int bump(global ref int counts, int bin) { return atomic_add(counts + bin, 1); }
        public void bumpVia(global ref int counts, int bin) { bump(counts, bin); }
        public int firstAtLeast(global ref int p, int n, int bound, out int steps)
        {
            call behavior FirstAtLeast(p, n, bound, steps);
        }
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
fn a_buffer_passed_to_methods_is_the_kernels_own_buffer_in_them() {
    let body = "            store(out, id, id * 3);
            if (id % 2 == 0) { storeTwice(out, id, id); }";
    let kernel = generated_from(&sources(body), "compute");
    // One specialisation for `out`, whether the kernel or `storeTwice` passes it; the kernel
    // binds `out` writable because `store` writes it.
    assert_eq!(kernel.wgsl.matches("fn Kernels_store_out(at: i32, v: i32)").count(), 1, "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("Kernels_store_out(at, v * 2i);"), "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("out[at] = v;"), "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("var<storage, read_write> out"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> = (0..count as i32).map(|id| if id % 2 == 0 { id * 2 } else { id * 3 }).collect();
    assert_eq!(got, expected);
}

/// The device diagram that implements `firstAtLeast`: a device function (it returns a value)
/// that scans the buffer it is passed and counts its steps into an `out` parameter.
const FIRST_AT_LEAST: &str = "ActivityDiagram FirstAtLeast(global ref int p, int n, int bound, out int steps)
{
    var int i = 0;
    swimlane Device, owner Maths.Kernels
    {
        start S { steps = 0; => test; }
        decision test { [i >= n || p[i] >= bound] => done; [] => next; }
        action next { i++; steps = steps + 1; => test; }
        final done return i;
    }
}
";

#[test]
fn a_method_implemented_by_a_device_diagram_hands_it_its_buffer_and_out_parameter() {
    let body = "            var int steps = 0;
            var int at = firstAtLeast(out, 8, id, steps);
            out[id] = at + steps;";
    let mut files = sources(body);
    files.push(("first.gudsl".into(), FIRST_AT_LEAST.into()));
    let kernel = generated_from(&files, "compute");
    for expected in [
        "fn Kernels_firstAtLeast_out(n: i32, bound: i32, steps: ptr<function, i32>) -> i32",
        "return FirstAtLeast_out(n, bound, steps);",
        "fn FirstAtLeast_out(n: i32, bound: i32, steps: ptr<function, i32>) -> i32",
        "*steps = 0i;",
        "Kernels_firstAtLeast_out(8i, id, &steps)",
    ] {
        assert!(kernel.wgsl.contains(expected), "{expected} in\n{}", kernel.wgsl);
    }
}

#[test]
fn an_atomic_function_in_a_method_makes_the_kernels_buffer_atomic() {
    let kernel = generated_from(&sources("            bumpVia(out, id % 10);"), "compute");
    assert!(kernel.wgsl.contains("var<storage, read_write> out: array<atomic<i32>>"), "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("atomicAdd(&out[bin], 1i)"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> = (0..count).map(|i| if i < 10 { 100 } else { 0 }).collect();
    assert_eq!(got, expected);
}

/// A kernel of two buffers and work-group memory that hands each to methods of its class.
const TWO_BUFFERS: &str = "ActivityDiagram twoBuffers(global ref int a, global ref int b, shared int scratch)
{
    import OpenCL.GPU.*;

    swimlane Device, owner Maths.Kernels
    {
        start S { => work; }
        action work
        {
            var int id = get_global_id(0);
            store(a, id, id);
            store(b, id, id * 5);
            a[id] = a[id] + groupFirst(scratch, get_local_id(0), id);
            => f;
        }
        final f;
    }
}
";

#[test]
fn each_buffer_a_method_is_passed_gets_its_specialisation_and_shared_memory_its_barrier() {
    let class = CLASS.replace(
        "        public int declared(int v);",
        "        public int declared(int v);
        public int groupFirst(shared ref int s, int lid, int v)
        {
            if (lid == 0) { s[0] = v; }
            barrier(barrier_flags.CLK_LOCAL_MEM_FENCE);
            return s[0];
        }",
    );
    let files = vec![
        ("maths.gudsl".to_string(), class),
        ("smaller.gudsl".to_string(), SMALLER.to_string()),
        ("two.gudsl".to_string(), TWO_BUFFERS.to_string()),
    ];
    // naga validated the module (generation does).
    let kernel = generated_from(&files, "twoBuffers");
    for expected in [
        "fn Kernels_store_a(at: i32, v: i32)",
        "fn Kernels_store_b(at: i32, v: i32)",
        "fn Kernels_groupFirst_scratch(lid: i32, v: i32) -> i32",
        "scratch[0i] = v;",
        "workgroupBarrier();",
    ] {
        assert!(kernel.wgsl.contains(expected), "{expected} in\n{}", kernel.wgsl);
    }
    assert!(kernel.uses_barriers, "a barrier in a method synchronises the kernel's work-group");
}

#[test]
fn what_wgsl_cannot_take_is_an_error_at_its_place() {
    let errors = |body: &str| generation(&sources(body), "compute").expect_err("not generated");
    let recursion = errors("            out[id] = again(id);");
    assert!(
        recursion.iter().any(|(path, line, m)| path == "maths.gudsl" && *line == 15 && m.contains("recursively")),
        "{recursion:?}"
    );
    let pointer = errors("            out[id] = byPointer(id);");
    assert!(
        pointer.iter().any(|(path, line, m)| path == "compute.gudsl"
            && *line == 11
            && m.contains("pass a parameter of the kernel")),
        "{pointer:?}"
    );
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

/// Parentheses go where WGSL's operator tiers need them, and only there; the values are C's.
#[test]
fn operators_keep_their_meaning_with_the_parentheses_wgsl_needs() {
    let body = "            out[id] = (id - (id / 3 - 7)) * 2 + ((id + 1) << 2) - (id & 12) + id % 7 * (id / 5) - -id + (id ^ 3 | 8);";
    let kernel = generated_from(&sources(body), "compute");
    for expected in [
        "(id - (id / 3i - 7i)) * 2i",
        "(id + 1i) << 2u",
        "- (id & 12i)",
        "id % 7i * (id / 5i)",
        "- -id",
        "(id ^ 3i) | 8i",
    ] {
        assert!(kernel.wgsl.contains(expected), "{expected} in\n{}", kernel.wgsl);
    }
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> = (0..count as i32)
        .map(|id| (id - (id / 3 - 7)) * 2 + ((id + 1) << 2) - (id & 12) + id % 7 * (id / 5) - -id + ((id ^ 3) | 8))
        .collect();
    assert_eq!(got, expected);
}
