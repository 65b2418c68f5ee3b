// Foreground (sec. 6.5.2): |I − B_I| > θ_I AND |D − B_D| > θ_D on valid distances, 1 or 0.
struct Params { len: u32, width: u32, theta_intensity: f32, theta_distance: f32, _pad: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> intensity: array<f32>;
@group(0) @binding(2) var<storage, read> distance: array<f32>;
@group(0) @binding(3) var<storage, read> background_intensity: array<f32>;
@group(0) @binding(4) var<storage, read> background_distance: array<f32>;
@group(0) @binding(5) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * p.width + id.x;
    if id.x >= p.width || i >= p.len { return; }
    let d = distance[i];
    let foreground = d != 0.0
        && abs(intensity[i] - background_intensity[i]) > p.theta_intensity
        && abs(d - background_distance[i]) > p.theta_distance;
    output[i] = select(0.0, 1.0, foreground);
}
