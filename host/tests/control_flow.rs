//! Control flow of generated kernels on the GPU: a structured diagram (a loop left in the
//! middle) becomes structured WGSL, diagrams whose graphs are not structured (branches that
//! cross, a loop with two entries) fall back to the state loop, and every form computes, per
//! work-item, what the diagram says (checked against the same flow written in Rust); `return`
//! leaves its node, from any depth of loops and `switch`es, and the transitions follow.

mod support;

use gudsl_host::{Arg, Launcher, WorkRange};
use gudsl_runtime::{DeviceBuffer, Gpu};
use support::generated_from;

/// A kernel class with one diagram per test, each writing one `int` per work-item.
const CLASS: &str = "ClassDiagram Flow
{
    import OpenCL.GPU.*;

    public class Kernels implements OpenCL
    {
        public void crossing(global ref int out);
        public void exitInTheMiddle(global ref int out);
        public void twoEntries(global ref int out);
        public void leaving(global ref int out);
        public void leavingCrossing(global ref int out);
    }
}
";

/// `body`: the swimlane of diagram `name(global ref int out)`, variables `id`, `acc`, `k`.
fn diagram(name: &str, body: &str) -> String {
    format!(
        "ActivityDiagram {name}(global ref int out)
{{
    import OpenCL.GPU.*;

    public int id;
    public int acc;
    public int k;

    swimlane Device, owner Flow.Kernels
    {{
        start S {{ => a; }}
{body}
        action done {{ out[id] = acc; => f; }}
        final f;
    }}
}}
"
    )
}

/// Runs diagram `name` over `count` work-items; its WGSL and what each work-item wrote.
fn run(gpu: &Gpu, name: &str, body: &str, count: u32) -> (String, Vec<i32>) {
    let sources = [("flow.gudsl".to_string(), format!("{CLASS}\n{}", diagram(name, body)))];
    let kernel = generated_from(&sources, name);
    let out = DeviceBuffer::new(gpu, "out", 4 * count as u64).unwrap();
    let launcher = Launcher::new(gpu, &kernel).unwrap();
    launcher.launch(gpu, &[Arg::Buffer(&out)], &WorkRange::linear(count, None)).unwrap();
    let bytes = out.read(gpu).unwrap();
    (kernel.wgsl, bytes.chunks(4).map(|b| i32::from_le_bytes(b.try_into().unwrap())).collect())
}

const COUNT: u32 = 1000;

#[test]
fn branches_that_cross_run_as_a_state_loop() {
    let Some(gpu) = Gpu::for_tests() else { return };
    // `c` is reached from `a` and from inside `b`'s branch: no if/else nests that.
    let body = "
        action a { id = get_global_id(0); acc = 1; [id % 2 == 0] => b; [] => c; }
        action b { acc = acc * 10 + 2; [id % 3 == 0] => c; [] => done; }
        action c { acc = acc * 10 + 3; => done; }";
    let (wgsl, out) = run(&gpu, "crossing", body, COUNT);
    assert!(wgsl.contains("switch gudsl_state"), "{wgsl}");
    for (id, &value) in out.iter().enumerate() {
        let mut acc = 1;
        if id % 2 == 0 {
            acc = acc * 10 + 2;
            if id % 3 == 0 {
                acc = acc * 10 + 3;
            }
        } else {
            acc = acc * 10 + 3;
        }
        assert_eq!(value, acc, "work-item {id}");
    }
}

#[test]
fn a_loop_left_in_the_middle_is_structured() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let body = "
        action a { id = get_global_id(0); k = id % 7; acc = 0; => test; }
        action test { [k <= 0] => done; [] => step; }
        action step { acc = acc + k; k = k - 1; [acc > 12] => big; [] => test; }
        action big { acc = acc + 1000; => done; }";
    let (wgsl, out) = run(&gpu, "exitInTheMiddle", body, COUNT);
    assert!(!wgsl.contains("gudsl_state") && wgsl.contains("loop {") && wgsl.contains("continue;"), "{wgsl}");
    for (id, &value) in out.iter().enumerate() {
        let (mut k, mut acc) = (id as i32 % 7, 0);
        while k > 0 {
            acc += k;
            k -= 1;
            if acc > 12 {
                acc += 1000;
                break;
            }
        }
        assert_eq!(value, acc, "work-item {id}");
    }
}

#[test]
fn a_loop_with_two_entries_runs_as_a_state_loop() {
    let Some(gpu) = Gpu::for_tests() else { return };
    // `b` and `c` form a loop entered at either: not reducible to one WGSL loop.
    let body = "
        action a { id = get_global_id(0); acc = 0; k = id % 5; [k > 2] => c; [] => b; }
        action b { acc = acc + 1; k = k + 1; => c; }
        action c { acc = acc + 10; [k < 4] => b; [] => done; }";
    let (wgsl, out) = run(&gpu, "twoEntries", body, COUNT);
    assert!(wgsl.contains("switch gudsl_state"), "{wgsl}");
    for (id, &value) in out.iter().enumerate() {
        let (mut k, mut acc) = (id as i32 % 5, 0);
        if k <= 2 {
            acc += 1;
            k += 1;
        }
        loop {
            acc += 10;
            if k >= 4 {
                break;
            }
            acc += 1;
            k += 1;
        }
        assert_eq!(value, acc, "work-item {id}");
    }
}

/// Nodes that `return` from a `for`, a `switch`, a loop node's iteration and an `if`; where
/// `crossing`, `c` is also reached from `a` and `d` from `b` (branches that cross: a state loop).
fn leaving_body(crossing: bool) -> String {
    let a_exit = if crossing { "[id % 4 == 1] => c; [] => b;" } else { "=> b;" };
    let b_exit = if crossing { "[id % 9 == 4] => d; [] => c;" } else { "=> c;" };
    format!(
        "
        action a
        {{
            id = get_global_id(0);
            acc = 1;
            var int i;
            for (i = 0 : 1 : i < 10) {{ if (i == id % 7) {{ acc = acc * 10 + i; return; }} }}
            acc = -1;
            {a_exit}
        }}
        action b
        {{
            switch id % 3: {{ case 0: acc = acc + 100; return; default: acc = acc + 200; }}
            acc = acc + 1000;
            {b_exit}
        }}
        loop c(var int j = 0; j < 5; j = j + 1)
        {{
            if ((j == 2) && (id % 2 == 0)) {{ acc = acc + 7; return; }}
            acc = acc + 1;
            => d;
        }}
        action d {{ acc = acc * 2; if (id % 5 == 0) {{ return; }} acc = acc + 1; => done; }}"
    )
}

/// What `leaving_body` computes for work-item `id`.
fn leaving_in_rust(id: i32, crossing: bool) -> i32 {
    let mut acc = 10 + id % 7;
    let via_b = !(crossing && id % 4 == 1);
    if via_b {
        if id % 3 == 0 {
            acc += 100;
        } else {
            acc += 1200;
        }
    }
    if !(via_b && crossing && id % 9 == 4) {
        for j in 0..5 {
            if j == 2 && id % 2 == 0 {
                acc += 7;
                break;
            }
            acc += 1;
        }
    }
    acc *= 2;
    if id % 5 != 0 {
        acc += 1;
    }
    acc
}

#[test]
fn return_leaves_its_node_from_any_depth_and_the_transitions_follow() {
    let Some(gpu) = Gpu::for_tests() else { return };
    for (name, crossing) in [("leaving", false), ("leavingCrossing", true)] {
        let (wgsl, out) = run(&gpu, name, &leaving_body(crossing), COUNT);
        assert_eq!(wgsl.contains("switch gudsl_state"), crossing, "{wgsl}");
        // The one `return;` is the guard of the spare work-items.
        assert!(wgsl.contains("gudsl_leave_node = true; break;") && wgsl.matches("return;").count() == 1, "{wgsl}");
        for (id, &value) in out.iter().enumerate() {
            assert_eq!(value, leaving_in_rust(id as i32, crossing), "{name}, work-item {id}");
        }
    }
}
