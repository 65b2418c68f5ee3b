// Listing 15's mean filter written by hand: the mean of the (2r+1)² window of an RGBA8 image
// (r = kernelSize / 2), in the listing's arithmetic (channels scaled to 0..1, summed, divided by
// the count, scaled back and truncated) so that results compare exactly; pixels closer than r to
// the border are written invalid (0, 0, 0, 255).
struct Params { kernel_size: i32, width: i32, height: i32, _pad: i32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var input: texture_2d<u32>;
@group(0) @binding(2) var output: texture_storage_2d<rgba8uint, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let x = i32(id.x);
    let y = i32(id.y);
    if x >= p.width || y >= p.height { return; }
    let r = p.kernel_size / 2;
    if x >= p.width - r || y >= p.height - r || x < r || y < r {
        textureStore(output, id.xy, vec4<u32>(0u, 0u, 0u, 255u));
        return;
    }
    var sum = vec3<f32>(0.0);
    for (var u = -r; u <= r; u++) {
        for (var v = -r; v <= r; v++) {
            sum += vec3<f32>(textureLoad(input, vec2<i32>(x + u, y + v), 0).xyz) / 255.0;
        }
    }
    let side = 2 * r + 1;
    let mean = sum / f32(side * side);
    textureStore(output, id.xy, vec4<u32>(vec3<u32>(vec3<i32>(mean * 255.0)), 255u));
}
