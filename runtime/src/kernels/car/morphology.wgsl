// Binary erosion (dilate = 0) or dilation over a (2r+1)² square, edges replicated.
struct Params { width: u32, height: u32, radius: u32, dilate: u32, _pad: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> mask: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let r = i32(p.radius);
    var any_on = false;
    var all_on = true;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let x = u32(clamp(i32(id.x) + dx, 0, i32(p.width) - 1));
            let y = u32(clamp(i32(id.y) + dy, 0, i32(p.height) - 1));
            let on = mask[y * p.width + x] != 0.0;
            any_on = any_on || on;
            all_on = all_on && on;
        }
    }
    let result = select(all_on, any_on, p.dilate != 0u);
    output[id.y * p.width + id.x] = select(0.0, 1.0, result);
}
