// Per-pixel optimal integration time (sec. 5.3, eq. 5.4–5.8): I_corr = h(I) (identity below
// h's range, h's upper bound above it), t_opt(x,y) = I_opt / I_corr · t_curr clamped to the
// camera's range, w' = w · g with w a centred Gaussian (σ = width / 4); pass `main` sums
// w'·t_opt and w' per workgroup, pass `finish` writes Σ w' t_opt / Σ w'.
struct Params {
    size: vec4<f32>,   // width, height, t_curr, I_opt
    h: vec4<f32>,      // cubic, highest degree first
    limits: vec4<f32>, // h low, h high, gain, t_min
    extra: vec4<f32>,  // t_max
}

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> intensity: array<f32>;
@group(0) @binding(2) var<storage, read_write> result: array<f32>;
@group(0) @binding(3) var<storage, read_write> partial: array<f32>;

@compute @workgroup_size(256)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(local_invocation_index) t: u32,
        @builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let width = u32(p.size.x);
    let n = width * u32(p.size.y);
    let i = id.y * groups.x * 256u + id.x;
    var weighted = 0.0;
    var weight = 0.0;
    if i < n && intensity[i] > 0.0 {
        let measured = intensity[i];
        var corrected = measured;
        if measured >= p.limits.x {
            let x = min(measured, p.limits.y);
            corrected = ((p.h.x * x + p.h.y) * x + p.h.z) * x + p.h.w;
        }
        let t_opt = clamp(p.size.w / corrected * p.size.z, p.limits.w, p.extra.x);
        let dx = (f32(i % width) + 0.5) / p.size.x - 0.5;
        let dy = (f32(i / width) + 0.5) / p.size.y - 0.5;
        // σ = a quarter of the side: exp(−r² / (2 σ²)) with r in units of the side.
        weight = exp(-(dx * dx + dy * dy) * 8.0) * p.limits.z;
        weighted = weight * t_opt;
    }
    let group_index = group.y * groups.x + group.x;
    let weighted_sum = reduce_workgroup(t, weighted);
    let weight_sum = reduce_workgroup(t, weight);
    if t == 0u {
        partial[2u * group_index] = weighted_sum;
        partial[2u * group_index + 1u] = weight_sum;
    }
}

@compute @workgroup_size(256)
fn finish(@builtin(local_invocation_index) t: u32) {
    let n = u32(p.size.x) * u32(p.size.y);
    let group_count = (n + 255u) / 256u;
    var weighted = 0.0;
    var weight = 0.0;
    for (var g = t; g < group_count; g += 256u) {
        weighted += partial[2u * g];
        weight += partial[2u * g + 1u];
    }
    let weighted_sum = reduce_workgroup(t, weighted);
    let weight_sum = reduce_workgroup(t, weight);
    if t == 0u {
        result[0] = select(p.size.z, weighted_sum / weight_sum, weight_sum > 0.0);
    }
}
