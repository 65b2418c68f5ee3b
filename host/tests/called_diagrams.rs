//! `call behavior` between device diagrams: a kernel calls diagrams that become WGSL functions
//! (decisions and a loop over nodes, `final … return` values, one that returns nothing, one
//! calling another, one specialised for the kernel's buffer it takes, a device diagram that
//! returns a value), runs on the GPU and
//! computes what the same steps compute in Rust (an `out` parameter sets the caller's variable);
//! what WGSL cannot take — recursion, a value where a buffer or a variable belongs — is an error
//! at its place.

mod support;

use support::{collatz_steps, compute_kernel, generated_from, generation, run_compute_kernel, CLAMP_AND_COLLATZ};

/// The called diagrams (besides the ones shared with the host's tests).
const CALLED: &str = "ActivityDiagram Nothing(int n)
{
    var int unused = n;
    swimlane L
    {
        start S { => f; }
        final f;
    }
}

ActivityDiagram Forever(int n)
{
    var int r;
    swimlane L
    {
        start S { => a; }
        action a { r = call behavior Again(n); => f; }
        final f return r;
    }
}

ActivityDiagram Again(int n)
{
    var int r;
    swimlane L
    {
        start S { => a; }
        action a { r = call behavior Forever(n) + 1; => f; }
        final f return r;
    }
}

ActivityDiagram Untyped(int n)
{
    swimlane L
    {
        start S { => f; }
        final f return call behavior Clamp(n, 0, 1);
    }
}

ActivityDiagram FromPointer(global ref int p)
{
    swimlane L
    {
        start S { => f; }
        final f return p[0];
    }
}

ActivityDiagram Written(int n, out int m)
{
    swimlane L
    {
        start S { => set; }
        action set { m = n * 2; => f; }
        final f return n;
    }
}

ActivityDiagram WrittenPair(int n, out int2 v)
{
    swimlane L
    {
        start S { => set; }
        action set { v.x = n; v.y = v.x + 1; => f; }
        final f return n;
    }
}
";

/// The OpenCL class that owns the kernel.
const CLASS: &str = "ClassDiagram Steps
{
    import OpenCL.GPU.*;

    public class Kernels implements OpenCL
    {
        public void compute(global ref int out);
    }
}
";

fn sources(body: &str) -> Vec<(String, String)> {
    vec![
        ("steps.gudsl".into(), CLASS.into()),
        ("shared.gudsl".into(), CLAMP_AND_COLLATZ.into()),
        ("called.gudsl".into(), CALLED.into()),
        ("compute.gudsl".into(), compute_kernel("Steps.Kernels", body)),
    ]
}

/// A device diagram (its swimlane owned by the OpenCL class) that returns a value.
const DEVICE_FUNCTION: &str = "ActivityDiagram Smallest(int a, int b)
{
    swimlane Device, owner Steps.Kernels
    {
        start S { => pick; }
        decision pick { [a < b] => first; [] => second; }
        final first return a;
        final second return b;
    }
}
";

#[test]
fn a_device_diagram_that_returns_a_value_is_a_device_function_not_a_kernel() {
    let mut files = sources("            out[id] = call behavior Smallest(id, 600);");
    files.push(("smallest.gudsl".into(), DEVICE_FUNCTION.into()));
    let kernel = generated_from(&files, "compute");
    assert!(kernel.wgsl.contains("fn Smallest(a: i32, b: i32) -> i32"), "{}", kernel.wgsl);
    support::with_diagram(&files, "Smallest", |sema, def| {
        assert!(gudsl_codegen::is_device_diagram(sema, def), "device code");
        assert!(!gudsl_codegen::is_kernel(sema, def), "no kernel");
        assert!(!gudsl_codegen::device_diagrams(sema).iter().any(|d| d.fqn == "Smallest"), "no kernel to list");
        // `check` (E0301) finds nothing to say: it is not generated as a kernel of its own.
        let problems = gudsl_codegen::queries::device_diagnostics(sema.db(), sema.workspace(), def.file);
        assert!(problems.is_empty(), "{problems:?}");
    });
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    assert_eq!(got, (0..count as i32).map(|id| id.min(600)).collect::<Vec<_>>());
}

#[test]
fn called_diagrams_run_as_functions_and_compute_what_rust_does() {
    let body = "            call behavior Nothing(id);
            out[id] = call behavior ClampedSteps(id) * 1000 + call behavior Clamp(id - 500, -100, 100);";
    let kernel = generated_from(&sources(body), "compute");
    for function in
        ["fn Clamp(v: i32, low: i32, high: i32) -> i32", "fn CollatzSteps(n: i32) -> i32", "fn Nothing(n: i32) {"]
    {
        assert!(kernel.wgsl.contains(function), "{function} in\n{}", kernel.wgsl);
    }
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    let expected: Vec<i32> =
        (0..count as i32).map(|id| collatz_steps(id).clamp(0, 100) * 1000 + (id - 500).clamp(-100, 100)).collect();
    assert_eq!(got, expected);
}

#[test]
fn an_out_parameter_points_to_the_callers_variable() {
    let body = "            var int m = 0;
            var int r = call behavior Written(id, m);
            out[id] = r + m;";
    let kernel = generated_from(&sources(body), "compute");
    assert!(kernel.wgsl.contains("fn Written(n: i32, m: ptr<function, i32>) -> i32"), "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("*m = n * 2i;"), "{}", kernel.wgsl);
    assert!(kernel.wgsl.contains("Written(id, &m)"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    assert_eq!(got, (0..count as i32).map(|id| 3 * id).collect::<Vec<_>>());
}

#[test]
fn a_vector_out_parameters_components_are_written_through_its_pointer() {
    let body = "            var int2 v = 0;
            var int r = call behavior WrittenPair(id, v);
            out[id] = r + v.x * 10 + v.y;";
    let kernel = generated_from(&sources(body), "compute");
    assert!(kernel.wgsl.contains("(*v).y = (*v).x + 1i;"), "{}", kernel.wgsl);
    let count = 1000u32;
    let Some(got) = run_compute_kernel(&kernel, count) else { return };
    assert_eq!(got, (0..count as i32).map(|id| id + id * 10 + id + 1).collect::<Vec<_>>());
}

#[test]
fn what_a_called_diagram_cannot_be_is_an_error_at_its_place() {
    let errors = |body: &str| generation(&sources(body), "compute").expect_err("not generated");
    let recursion = errors("            out[id] = call behavior Forever(id);");
    assert!(
        recursion.iter().any(|(path, line, m)| path == "called.gudsl" && *line == 17 && m.contains("recursively")),
        "{recursion:?}"
    );
    // A diagram that takes a buffer is specialised for the kernel's buffer it is passed …
    let kernel = generation(&sources("            out[id] = call behavior FromPointer(out);"), "compute").unwrap();
    assert!(kernel.wgsl.contains("fn FromPointer_out() -> i32"), "{}", kernel.wgsl);
    // … and is passed nothing else.
    let pointer = errors("            out[id] = call behavior FromPointer(id);");
    assert!(
        pointer.iter().any(|(path, line, m)| path == "compute.gudsl"
            && *line == 11
            && m.contains("pass a parameter of the kernel")),
        "{pointer:?}"
    );
    let untyped = errors("            out[id] = call behavior Untyped(id);");
    assert!(
        untyped.iter().any(|(path, line, m)| path == "compute.gudsl" && *line == 11 && m.contains("no known type")),
        "{untyped:?}"
    );
    let not_a_variable = errors("            out[id] = call behavior Written(id, id + 1);");
    assert!(
        not_a_variable
            .iter()
            .any(|(path, line, m)| path == "compute.gudsl" && *line == 11 && m.contains("pass a variable")),
        "{not_a_variable:?}"
    );
}
