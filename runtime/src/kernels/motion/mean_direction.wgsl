// The mean direction of a flow's non-zero vectors (a circular mean: the sum of their unit
// vectors), for the next frame's restricted search; while none moved, the direction before.
// Pass `main`: each workgroup of 256 threads takes 256 × 16 pixels, thread t the pixels t,
// t + 256, … of them, and adds its threads' sums of unit vectors in a tree into
// `partial`; pass `finish`, one workgroup: thread t adds the partial sums t, t + 256, …, then a
// tree again (the CPU twin adds in the same order). Out: (radians in [0, 2π), 1), or the
// direction before (radians, known) where nothing moved or the unit vectors cancel.
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> flow: array<f32>;
@group(0) @binding(2) var<storage, read> previous: array<f32>;
@group(0) @binding(3) var<storage, read_write> direction: array<f32>;
@group(0) @binding(4) var<storage, read_write> partial: array<f32>;

const PI: f32 = 3.141592653589793;
const THREADS: u32 = 256u;
const PER_THREAD: u32 = 16u;

var<workgroup> sums: array<vec2<f32>, 256>;

// The workgroups of pass `main`.
fn group_count() -> u32 {
    return (p.width * p.height + THREADS * PER_THREAD - 1u) / (THREADS * PER_THREAD);
}

// The workgroup's sum of its threads' `value`s, in a tree; every thread gets it.
fn workgroup_total(t: u32, value: vec2<f32>) -> vec2<f32> {
    sums[t] = value;
    workgroupBarrier();
    for (var stride = THREADS / 2u; stride > 0u; stride /= 2u) {
        if t < stride { sums[t] += sums[t + stride]; }
        workgroupBarrier();
    }
    return sums[0];
}

@compute @workgroup_size(256)
fn main(@builtin(local_invocation_index) t: u32, @builtin(workgroup_id) group: vec3<u32>,
        @builtin(num_workgroups) groups: vec3<u32>) {
    let n = p.width * p.height;
    let g = group.y * groups.x + group.x;
    var sum = vec2<f32>(0.0, 0.0);
    for (var k = 0u; k < PER_THREAD; k++) {
        let i = (g * PER_THREAD + k) * THREADS + t;
        if i < n {
            let u = flow[i];
            let v = flow[n + i];
            if u != 0.0 || v != 0.0 {
                let r = sqrt(u * u + v * v);
                sum += vec2<f32>(u / r, v / r);
            }
        }
    }
    let total = workgroup_total(t, sum);
    if t == 0u && g < group_count() {
        partial[2u * g] = total.x;
        partial[2u * g + 1u] = total.y;
    }
}

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) t: u32) {
    var sum = vec2<f32>(0.0, 0.0);
    for (var g = t; g < group_count(); g += THREADS) {
        sum += vec2<f32>(partial[2u * g], partial[2u * g + 1u]);
    }
    let total = workgroup_total(t, sum);
    if t == 0u {
        // Vectors that cancel (as many to the left as to the right) have no direction either.
        if total.x != 0.0 || total.y != 0.0 {
            var angle = atan2(total.y, total.x);
            if angle < 0.0 { angle += 2.0 * PI; }
            direction[0] = angle;
            direction[1] = 1.0;
        } else {
            direction[0] = previous[0];
            direction[1] = previous[1];
        }
    }
}
