// value kept where the mask is non-zero, else 0.
struct Params { len: u32, width: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> value: array<f32>;
@group(0) @binding(2) var<storage, read> mask: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * p.width + id.x;
    if id.x >= p.width || i >= p.len { return; }
    output[i] = select(0.0, value[i], mask[i] != 0.0);
}
