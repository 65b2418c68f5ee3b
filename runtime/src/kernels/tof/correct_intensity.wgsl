// Intensity-related distance correction (sec. 2.1.2.2):
// D_c = D_m − (q2·x² + q1·x + q0), x = I_m · intT_calib / intT.
struct Params { len: u32, width: u32, q0: f32, q1: f32, q2: f32, scale: f32, _pad: vec2<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> distance: array<f32>;
@group(0) @binding(2) var<storage, read> intensity: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let height = p.len / p.width;
    if id.x >= p.width || id.y >= height { return; }
    let i = id.y * p.width + id.x;
    let x = intensity[i] * p.scale;
    output[i] = distance[i] - (p.q2 * x * x + p.q1 * x + p.q0);
}
