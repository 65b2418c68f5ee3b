// 3×3 outlier removal (sec. 6.5.1.3): a valid pixel stays when at least min_similar of its valid
// 8-neighbours lie within range metres of it; else 0.
struct Params { width: u32, height: u32, range: f32, min_similar: u32, _pad: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> distance: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let i = id.y * p.width + id.x;
    let d = distance[i];
    if d == 0.0 {
        output[i] = 0.0;
        return;
    }
    var similar = 0u;
    for (var dy = -1; dy <= 1; dy++) {
        for (var dx = -1; dx <= 1; dx++) {
            let nx = i32(id.x) + dx;
            let ny = i32(id.y) + dy;
            if (dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= i32(p.width) || ny >= i32(p.height) { continue; }
            let n = distance[u32(ny) * p.width + u32(nx)];
            if n != 0.0 && abs(n - d) < p.range { similar++; }
        }
    }
    output[i] = select(0.0, d, similar >= p.min_similar);
}
