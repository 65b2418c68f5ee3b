// One projective point-to-plane ICP step (sec. 6.5.3): per source pixel the pair with the model
// pixel it projects to, a = [p × n, n], b = n·(d − p); pass `main` reduces the 29 sums (upper
// triangle of Σ a aᵀ, Σ a b, pairs, Σ b²) of its 64 pixels together, one tree of 6 barriers, into
// scratch; pass `finish` adds the workgroups' sums.
struct Params {
    pose0: vec4<f32>,
    pose1: vec4<f32>,
    pose2: vec4<f32>,
    focal_centre: vec4<f32>,   // fx, fy, cx, cy
    distortion: vec4<f32>,     // k1, k2, p1, p2
    limits: vec4<f32>,         // width, height, max distance, min cos
}

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> source: array<f32>;
@group(0) @binding(2) var<storage, read> source_normals: array<f32>;
@group(0) @binding(3) var<storage, read> model: array<f32>;
@group(0) @binding(4) var<storage, read> model_normals: array<f32>;
@group(0) @binding(5) var<storage, read_write> sums: array<f32>;
@group(0) @binding(6) var<storage, read_write> partial: array<f32>;

const SUMS: u32 = 29u;
const GROUP: u32 = 64u;
var<workgroup> values: array<f32, 1856>; // GROUP × SUMS

fn at(image: u32, i: u32, n: u32) -> vec3<f32> {
    if image == 0u { return vec3<f32>(source[i], source[n + i], source[2u * n + i]); }
    if image == 1u { return vec3<f32>(source_normals[i], source_normals[n + i], source_normals[2u * n + i]); }
    if image == 2u { return vec3<f32>(model[i], model[n + i], model[2u * n + i]); }
    return vec3<f32>(model_normals[i], model_normals[n + i], model_normals[2u * n + i]);
}

fn transform(v: vec3<f32>, w: f32) -> vec3<f32> {
    let h = vec4<f32>(v, w);
    return vec3<f32>(dot(p.pose0, h), dot(p.pose1, h), dot(p.pose2, h));
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) t: u32,
        @builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let width = u32(p.limits.x);
    let height = u32(p.limits.y);
    let n = width * height;
    let i = id.y * groups.x * GROUP + id.x;
    var a = array<f32, 6>(0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    var b = 0.0;
    var found = false;
    if i < n {
        let s = at(0u, i, n);
        let sn = at(1u, i, n);
        if s.z != 0.0 && any(sn != vec3<f32>(0.0)) {
            let q = transform(s, 1.0);
            let nq = transform(sn, 0.0);
            if q.z > 0.0 {
                let x = q.x / q.z;
                let y = q.y / q.z;
                let r2 = x * x + y * y;
                let radial = 1.0 + p.distortion.x * r2 + p.distortion.y * r2 * r2;
                let xd = x * radial + 2.0 * p.distortion.z * x * y + p.distortion.w * (r2 + 2.0 * x * x);
                let yd = y * radial + p.distortion.z * (r2 + 2.0 * y * y) + 2.0 * p.distortion.w * x * y;
                let u = floor(p.focal_centre.x * xd + p.focal_centre.z + 0.5);
                let v = floor(p.focal_centre.y * yd + p.focal_centre.w + 0.5);
                if u >= 0.0 && v >= 0.0 && u < p.limits.x && v < p.limits.y {
                    let j = u32(v) * width + u32(u);
                    let d = at(2u, j, n);
                    let dn = at(3u, j, n);
                    let diff = d - q;
                    if d.z != 0.0 && any(dn != vec3<f32>(0.0))
                        && dot(diff, diff) <= p.limits.z * p.limits.z && dot(nq, dn) >= p.limits.w {
                        let c = cross(q, dn);
                        a = array<f32, 6>(c.x, c.y, c.z, dn.x, dn.y, dn.z);
                        b = dot(dn, diff);
                        found = true;
                    }
                }
            }
        }
    }
    var k = 0u;
    for (var r = 0u; r < 6u; r++) {
        for (var c = r; c < 6u; c++) {
            values[t * SUMS + k] = a[r] * a[c];
            k++;
        }
        values[t * SUMS + 21u + r] = a[r] * b;
    }
    values[t * SUMS + 27u] = select(0.0, 1.0, found);
    values[t * SUMS + 28u] = b * b;
    workgroupBarrier();
    for (var stride = GROUP / 2u; stride > 0u; stride = stride / 2u) {
        if t < stride {
            for (var m = 0u; m < SUMS; m++) { values[t * SUMS + m] += values[(t + stride) * SUMS + m]; }
        }
        workgroupBarrier();
    }
    if t < SUMS {
        partial[(group.y * groups.x + group.x) * SUMS + t] = values[t];
    }
}

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) t: u32) {
    let n = u32(p.limits.x) * u32(p.limits.y);
    let group_count = (n + GROUP - 1u) / GROUP;
    for (var k = 0u; k < SUMS; k++) {
        var value = 0.0;
        for (var g = t; g < group_count; g += 256u) {
            value += partial[g * SUMS + k];
        }
        let total = reduce_workgroup(t, value);
        if t == 0u { sums[k] = total; }
    }
}
