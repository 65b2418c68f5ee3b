// Polar → Cartesian: P = D · ray with the per-pixel unit rays (3 planes).
struct Params { len: u32, width: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> distance: array<f32>;
@group(0) @binding(2) var<storage, read> rays: array<f32>;
@group(0) @binding(3) var<storage, read_write> points: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.y * p.width + id.x;
    if id.x >= p.width || i >= p.len { return; }
    let d = distance[i];
    for (var k = 0u; k < 3u; k++) {
        points[k * p.len + i] = d * rays[k * p.len + i];
    }
}
