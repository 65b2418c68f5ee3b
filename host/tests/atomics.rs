//! OpenCL's atomic functions in device diagrams: a histogram counted with `atomic_inc` in
//! `shared` memory and summed into a buffer with `atomic_add`, a minimum and maximum with
//! `atomic_min`/`atomic_max`, a ticket with `atomic_add`'s old value and a plain store and read
//! of an atomic buffer, `atomic_cmpxchg` that exactly one work-item wins; on lavapipe (and GL in
//! CI) against Rust. What cannot be atomic — a private variable, a pointer that is not `p + i`
//! — is an error at its place.

mod support;

use gudsl_host::{Arg, Launcher, Number, WorkRange};
use gudsl_runtime::{DeviceBuffer, Gpu};
use support::{generated_from, generation};

const CLASS: &str = "ClassDiagram Stats
{
    import OpenCL.GPU.*;

    public class Kernels implements OpenCL
    {
        public void histogram(global ref int values, global ref unsigned int counts, global ref int extremes, shared unsigned int bins);
    }
}
";

/// The histogram kernel, `extra` added to its action.
fn kernel(extra: &str) -> String {
    format!(
        "ActivityDiagram histogram(global ref int values, global ref unsigned int counts, global ref int extremes,
    shared unsigned int bins)
{{
    import OpenCL.GPU.*;

    swimlane Device, owner Stats.Kernels
    {{
        start S {{ => work; }}
        action work
        {{
            var int id = get_global_id(0);
            var int lid = get_local_id(0);
            var int v = values[id];
            if (lid < 16) {{ bins[lid] = 0u; }}
            barrier(barrier_flags.CLK_LOCAL_MEM_FENCE);
            atomic_inc(bins + (v % 16));
            barrier(barrier_flags.CLK_LOCAL_MEM_FENCE);
            if (lid < 16) {{ atomic_add(counts + lid, bins[lid]); }}
            atomic_min(extremes, v);
            atomic_max(extremes + 1, v);
            var int ticket = atomic_add(extremes + 2, 1);
            if (ticket == 0) {{ extremes[3] = extremes[4] + 7; }}
            if (atomic_cmpxchg(extremes + 5, 0, 99) == 0) {{ atomic_inc(extremes + 6); }}
{extra}
            => f;
        }}
        final f;
    }}
}}
"
    )
}

fn sources(extra: &str) -> Vec<(String, String)> {
    vec![("stats.gudsl".into(), CLASS.into()), ("histogram.gudsl".into(), kernel(extra))]
}

fn ints(bytes: &[u8]) -> Vec<i32> {
    bytes.chunks(4).map(|b| i32::from_le_bytes(b.try_into().unwrap())).collect()
}

#[test]
fn atomics_count_a_histogram_and_find_extremes_as_rust_does() {
    let kernel = generated_from(&sources(""), "histogram");
    for line in [
        "var<storage, read_write> counts: array<atomic<u32>>;",
        "var<workgroup> bins: array<atomic<u32>, gudsl_bins_length>;",
        "atomicStore(&extremes[3i], atomicLoad(&extremes[4i]) + 7i);",
        "fn gudsl_cmpxchg_extremes(at: i32, compare: i32, value: i32) -> i32 {",
    ] {
        assert!(kernel.wgsl.contains(line), "{line} in\n{}", kernel.wgsl);
    }
    let Some(gpu) = Gpu::for_tests() else { return };
    let count = 4096usize;
    let mut seed = 0x2545_f491u32;
    let values: Vec<i32> = (0..count)
        .map(|_| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed % 100_000) as i32
        })
        .collect();
    let upload = |label: &str, data: &[i32]| {
        let buffer = DeviceBuffer::new(&gpu, label, 4 * data.len() as u64).unwrap();
        buffer.write(&gpu, &data.iter().flat_map(|v| v.to_le_bytes()).collect::<Vec<u8>>()).unwrap();
        buffer
    };
    let input = upload("values", &values);
    let counts = upload("counts", &[0; 16]);
    let extremes = upload("extremes", &[i32::MAX, i32::MIN, 0, 0, 0, 0, 0]);
    let launcher = Launcher::new(&gpu, &kernel).unwrap();
    let args = [Arg::Buffer(&input), Arg::Buffer(&counts), Arg::Buffer(&extremes), Arg::Number(Number::Int(16 * 4))];
    launcher.launch(&gpu, &args, &WorkRange::linear(count as u32, Some(64))).unwrap();

    let mut histogram = [0i32; 16];
    for v in &values {
        histogram[(*v % 16) as usize] += 1;
    }
    assert_eq!(ints(&counts.read(&gpu).unwrap()), histogram);
    let (min, max) = (*values.iter().min().unwrap(), *values.iter().max().unwrap());
    // One work-item exchanged 0 for 99, and only that one saw 0.
    assert_eq!(ints(&extremes.read(&gpu).unwrap()), [min, max, count as i32, 7, 0, 99, 1]);
}

#[test]
fn what_cannot_be_atomic_is_an_error_at_its_place() {
    let errors = |extra: &str| generation(&sources(extra), "histogram").expect_err("not generated");
    let private = errors("            var int mine = 0;\n            atomic_inc(mine);");
    assert!(private.iter().any(|(_, line, m)| *line == 25 && m.contains("atomic function works on")), "{private:?}");
    let nested = errors("            atomic_inc(counts + 1 + 2);");
    assert!(nested.iter().any(|(_, line, m)| *line == 24 && m.contains("(`p` or `p + i`)")), "{nested:?}");
}
