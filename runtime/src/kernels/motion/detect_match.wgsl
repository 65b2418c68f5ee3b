// Motion detection (eq. 4.4, 4.5) and block matching (eq. 4.6–4.10) in one pass: each pixel's
// M (`motion_measure`, as `detect_motion.wgsl` computes it), its mask M > θ written, and
// where it is set its flow (`best_flow`, `match_search.wgsl`) as `match_blocks.wgsl` finds it.
// Each pixel's mask is its own (no neighbour's), so the fusion is exact.
struct Params { width: u32, height: u32, radius: u32, restricted: u32, mean_dir: f32, half_width: f32, subpixel: u32, theta: f32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read_write> flow: array<f32>;
@group(0) @binding(3) var<storage, read_write> mask_out: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    let m = motion_measure(i, n);
    let moving = m > p.theta;
    mask_out[i] = select(0.0, 1.0, moving);
    var best = vec2<f32>(0.0, 0.0);
    if moving {
        best = best_flow(i32(id.x), i32(id.y));
    }
    flow[i] = best.x;
    flow[n + i] = best.y;
}
