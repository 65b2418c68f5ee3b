// The mean direction of a flow's non-zero vectors (a circular mean: the sum of their unit
// vectors), for the next frame's restricted search; while none moved, the direction before.
// One workgroup: thread t sums pixels t, t + 256, …, then the sums are added in a tree (the CPU
// twin adds in the same order). Out: (radians in [0, 2π), 1), or the previous (radians, known).
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> flow: array<f32>;
@group(0) @binding(2) var<storage, read> previous: array<f32>;
@group(0) @binding(3) var<storage, read_write> direction: array<f32>;

const PI: f32 = 3.141592653589793;
const THREADS: u32 = 256u;

var<workgroup> sums: array<vec3<f32>, 256>;

@compute @workgroup_size(256)
fn main(@builtin(local_invocation_index) t: u32) {
    let n = p.width * p.height;
    var sum = vec3<f32>(0.0, 0.0, 0.0);
    for (var i = t; i < n; i += THREADS) {
        let u = flow[i];
        let v = flow[n + i];
        if u != 0.0 || v != 0.0 {
            let r = sqrt(u * u + v * v);
            sum += vec3<f32>(u / r, v / r, 1.0);
        }
    }
    sums[t] = sum;
    workgroupBarrier();
    for (var half = THREADS / 2u; half > 0u; half /= 2u) {
        if t < half {
            sums[t] += sums[t + half];
        }
        workgroupBarrier();
    }
    if t == 0u {
        let total = sums[0];
        if total.z > 0.0 {
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
