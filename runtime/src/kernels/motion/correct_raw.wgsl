// Raw phase correction (sec. 4.2.5): A_i(x, y) ← A_i(x + i·u, y + i·v), same for B_i, clamped;
// bilinear between the four pixels around where the flow is fractional.
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> flow: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

// The raw value of `plane` at (x, y), coordinates clamped.
fn at(plane: u32, x: i32, y: i32) -> f32 {
    let cx = u32(clamp(x, 0, i32(p.width) - 1));
    let cy = u32(clamp(y, 0, i32(p.height) - 1));
    return raw[plane * p.width * p.height + cy * p.width + cx];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    let u = flow[i];
    let v = flow[n + i];
    for (var k = 0u; k < 4u; k++) {
        let sx = f32(id.x) + f32(k) * u;
        let sy = f32(id.y) + f32(k) * v;
        let x0 = floor(sx);
        let y0 = floor(sy);
        let tx = sx - x0;
        let ty = sy - y0;
        for (var plane = 2u * k; plane < 2u * k + 2u; plane++) {
            let top = (1.0 - tx) * at(plane, i32(x0), i32(y0)) + tx * at(plane, i32(x0) + 1, i32(y0));
            let bottom = (1.0 - tx) * at(plane, i32(x0), i32(y0) + 1) + tx * at(plane, i32(x0) + 1, i32(y0) + 1);
            output[plane * n + i] = (1.0 - ty) * top + ty * bottom;
        }
    }
}
