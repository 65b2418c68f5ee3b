// Raw phase correction (sec. 4.2.5): A_i(x, y) ← A_i(x + i·u, y + i·v), same for B_i, clamped.
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> flow: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    let u = i32(flow[i]);
    let v = i32(flow[n + i]);
    for (var k = 0; k < 4; k++) {
        let sx = u32(clamp(i32(id.x) + k * u, 0, i32(p.width) - 1));
        let sy = u32(clamp(i32(id.y) + k * v, 0, i32(p.height) - 1));
        let s = sy * p.width + sx;
        let a = u32(2 * k);
        output[a * n + i] = raw[a * n + s];
        output[(a + 1u) * n + i] = raw[(a + 1u) * n + s];
    }
}
