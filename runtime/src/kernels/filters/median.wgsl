// Median over a (2r+1)² window (r ≤ 2), edges replicated: insertion sort of the window.
struct Params { width: u32, height: u32, radius: u32, _pad: u32, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> input: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

fn at(x: i32, y: i32) -> f32 {
    let cx = clamp(x, 0, i32(p.width) - 1);
    let cy = clamp(y, 0, i32(p.height) - 1);
    return input[u32(cy) * p.width + u32(cx)];
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let r = i32(min(p.radius, 2u));
    var values: array<f32, 25>;
    var n = 0u;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let v = at(i32(id.x) + dx, i32(id.y) + dy);
            // Two breaks, not `while j > 0u && values[j - 1u] > v` (nor one `||`): llvmpipe's GL
            // driver runs naga's GLSL of such a condition wrong (docs/runtime.md, "Portability").
            var j = n;
            loop {
                if j == 0u { break; }
                if values[j - 1u] <= v { break; }
                values[j] = values[j - 1u];
                j--;
            }
            values[j] = v;
            n++;
        }
    }
    output[id.y * p.width + id.x] = values[n / 2u];
}
