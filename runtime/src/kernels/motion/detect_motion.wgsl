// Motion detection (eq. 4.4, 4.5): M (`motion_measure`) and the mask M > θ.
struct Params { width: u32, height: u32, theta: f32, _pad: u32, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read_write> m_out: array<f32>;
@group(0) @binding(3) var<storage, read_write> mask_out: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    let m = motion_measure(i, n);
    m_out[i] = m;
    mask_out[i] = select(0.0, 1.0, m > p.theta);
}
