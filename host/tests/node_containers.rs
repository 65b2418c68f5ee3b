//! Node containers (Sec. 9.2.2.3) run as the grammar says: a node runs its statements, then the
//! flow of the nodes it holds from their start node to a final node, then its transitions; a
//! loop node does both each round. The same two-level model — a loop holding a loop holding a
//! decision — runs on the host interpreter and as a generated kernel on the GPU, and both give
//! what the flow written in Rust gives.

mod support;

use gudsl_host::run::Ending;
use gudsl_runtime::Gpu;
use support::{generated_from, prepared, run_compute_kernel};

/// What one work-item or one round of `each` computes for `id`: a loop of `id % 7` rounds,
/// each adding one, then tripling on an even round and adding `5 + k` on an odd one.
fn expected(id: i32) -> i32 {
    let mut acc = 0;
    for k in 0..id % 7 {
        acc += 1;
        acc = if k % 2 == 0 { acc * 3 } else { acc + 5 + k };
    }
    acc
}

/// The nested flow, as the body of a container that has `id` and `acc` in scope.
const NESTED: &str = "
            start inner { => outer; }
            loop outer(var int k = 0; k < id % 7; k = k + 1)
            {
                acc = acc + 1;
                start s2 { => pick; }
                decision pick { [k % 2 == 0] => even; [] => odd; }
                action even { acc = acc * 3; => end; }
                action odd { acc = acc + 5 + k; => end; }
                final end;
                => report;
            }";

#[test]
fn nested_flows_run_on_the_host_as_written() {
    let Some(gpu) = Gpu::for_tests() else { return };
    let text = format!(
        "ClassDiagram App {{ public class Host {{ }} }}

ActivityDiagram Test()
{{
    import Framework.Cpp.*;
    public int acc = 0;
    public int id = 0;
    swimlane L, owner App.Host
    {{
        start S {{ => each; }}
        loop each(id = 0; id < 20; id = id + 1)
        {{
            acc = 0;{NESTED}
            action report {{ CPPMethods::printf(\"%d\\n\", acc, 0); => done; }}
            final done;
            => f;
        }}
        final f;
    }}
}}
"
    );
    let mut sources = support::main_sources(|t| t);
    sources.push(("containers.gudsl".to_string(), text));
    let main = prepared(&sources, "Test").unwrap_or_else(|e| panic!("{e:?}"));
    let dir = std::env::temp_dir().join(format!("gudsl-containers-{}", std::process::id()));
    let report = main.run(&gpu, &mut support::output(&dir), &mut ());
    assert_eq!(report.outcome, Ok(Ending::Final("f".into())));
    let want: Vec<String> = (0..20).map(|id| format!("{}\n", expected(id))).collect();
    assert_eq!(report.printed, want);
}

#[test]
fn nested_flows_run_in_generated_kernels() {
    let class = "ClassDiagram Nest { import OpenCL.GPU.*; public class K implements OpenCL { public void compute(global ref int out); } }";
    let kernel = format!(
        "ActivityDiagram compute(global ref int out)
{{
    import OpenCL.GPU.*;
    public int id;
    public int acc;
    swimlane Device, owner Nest.K
    {{
        start S {{ => work; }}
        action work
        {{
            id = get_global_id(0);
            acc = 0;{NESTED}
            action report {{ out[id] = acc; => done; }}
            final done;
            => f;
        }}
        final f;
    }}
}}
"
    );
    let sources = [("nest.gudsl".to_string(), format!("{class}\n{kernel}"))];
    let generated = generated_from(&sources, "compute");
    assert!(generated.wgsl.contains("gudsl_state_work") && generated.wgsl.contains("gudsl_state_outer"));
    let Some(out) = run_compute_kernel(&generated, 500) else { return };
    for (id, &value) in out.iter().enumerate() {
        assert_eq!(value, expected(id as i32), "work-item {id}\n{}", generated.wgsl);
    }
}
