// Spatial and range weighted mean (Gaussian when sigma_range is 0, else bilateral), normalised,
// edges replicated: w = exp(-(dx²+dy²)/(2σs²)) · exp(-(I(q)-I(p))²/(2σr²)).
struct Params { width: u32, height: u32, radius: u32, sigma_space: f32, sigma_range: f32, _pad: u32, _pad2: vec2<u32> }

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
    let r = i32(p.radius);
    let centre = at(i32(id.x), i32(id.y));
    var sum = 0.0;
    var weights = 0.0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let value = at(i32(id.x) + dx, i32(id.y) + dy);
            var w = exp(-f32(dx * dx + dy * dy) / (2.0 * p.sigma_space * p.sigma_space));
            if p.sigma_range > 0.0 {
                let d = value - centre;
                w *= exp(-(d * d) / (2.0 * p.sigma_range * p.sigma_range));
            }
            sum += w * value;
            weights += w;
        }
    }
    output[id.y * p.width + id.x] = sum / weights;
}
