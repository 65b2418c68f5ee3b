// Listing 16's bilateral filter written by hand: over the (2r+1)² window of an RGBA8 image
// (r = radius truncated), weights exp(-(u²+v²)/(2σs²)) · exp(-|I(q)-I(p)|²/(2σr²)) on the RGB
// distance, the weighted mean truncated; pixels closer than r to the border are written invalid
// (0, 0, 0, 255). The constant factors are computed once, not per texel.
struct Params { radius: f32, sigma_spatial: f32, sigma_range: f32, _pad: f32, width: i32, height: i32, _pad2: vec2<i32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var input: texture_2d<u32>;
@group(0) @binding(2) var output: texture_storage_2d<rgba8uint, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let x = i32(id.x);
    let y = i32(id.y);
    if x >= p.width || y >= p.height { return; }
    let r = i32(p.radius);
    if x >= p.width - r || y >= p.height - r || x < r || y < r {
        textureStore(output, id.xy, vec4<u32>(0u, 0u, 0u, 255u));
        return;
    }
    let spatial_scale = -1.0 / (2.0 * p.sigma_spatial * p.sigma_spatial);
    let range_scale = -1.0 / (2.0 * p.sigma_range * p.sigma_range);
    let centre = vec3<f32>(textureLoad(input, vec2<i32>(x, y), 0).xyz);
    var sum = vec3<f32>(0.0);
    var weights = 0.0;
    for (var u = -r; u <= r; u++) {
        for (var v = -r; v <= r; v++) {
            let texel = vec3<f32>(textureLoad(input, vec2<i32>(x + u, y + v), 0).xyz);
            let difference = texel - centre;
            let weight = exp(f32(u * u + v * v) * spatial_scale) * exp(dot(difference, difference) * range_scale);
            sum += texel * weight;
            weights += weight;
        }
    }
    textureStore(output, id.xy, vec4<u32>(vec3<u32>(vec3<i32>(sum / weights)), 255u));
}
