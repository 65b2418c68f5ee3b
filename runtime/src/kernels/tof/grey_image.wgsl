// An amplitude as a grey RGBA image: min(255, floor(amplitude × gain + 0.5)) in R, G, B; 255 in A.
struct Params { len: u32, width: u32, gain: f32, _pad: u32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> amplitude: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * p.width + id.x;
    if id.x >= p.width || i >= p.len { return; }
    let grey = min(max(floor(amplitude[i] * p.gain + 0.5), 0.0), 255.0);
    output[i] = grey;
    output[p.len + i] = grey;
    output[2u * p.len + i] = grey;
    output[3u * p.len + i] = 255.0;
}
