// Block matching (eq. 4.6–4.10) of the masked pixels (`best_flow`, `match_search.wgsl`); the
// others' flow is 0.
struct Params { width: u32, height: u32, radius: u32, restricted: u32, mean_dir: f32, half_width: f32, subpixel: u32, _pad: u32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> mask: array<f32>;
@group(0) @binding(3) var<storage, read_write> flow: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    var best = vec2<f32>(0.0, 0.0);
    if mask[i] != 0.0 {
        best = best_flow(i32(id.x), i32(id.y), vec2<f32>(f32(p.restricted), p.mean_dir));
    }
    flow[i] = best.x;
    flow[n + i] = best.y;
}
