// Eq. 6.1: distance kept where min ≤ amplitude ≤ max, else 0 (invalid).
struct Params { len: u32, width: u32, min_amplitude: f32, max_amplitude: f32, _pad: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> distance: array<f32>;
@group(0) @binding(2) var<storage, read> amplitude: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * p.width + id.x;
    if id.x >= p.width || i >= p.len { return; }
    let a = amplitude[i];
    output[i] = select(0.0, distance[i], a >= p.min_amplitude && a <= p.max_amplitude);
}
