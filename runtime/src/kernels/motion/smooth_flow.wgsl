// Flow smoothing ("NH", sec. 4.2.4): each non-zero vector takes the median direction of the
// non-zero vectors in its window (≤ 11×11), keeps its length, rounded to whole pixels. The median
// is circular: directions relative to the pixel's own, wrapped to (−π, π]; the median
// neighbour's direction is the result.
struct Params { width: u32, height: u32, radius: u32, _pad: u32, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> flow: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

const PI: f32 = 3.141592653589793;

// The direction of (a, b) relative to (u, v) in (−π, π], from cross and dot products (exact in
// sign for whole and quarter pixels, so the GPU sorts as the CPU does).
fn relative_angle(u: f32, v: f32, a: f32, b: f32) -> f32 {
    let d = atan2(u * b - v * a, u * a + v * b);
    return select(d, PI, d <= -PI);
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    let u = flow[i];
    let v = flow[n + i];
    if u == 0.0 && v == 0.0 {
        output[i] = 0.0;
        output[n + i] = 0.0;
        return;
    }
    let r = i32(min(p.radius, 5u));
    var angles: array<f32, 121>;
    var vectors: array<vec2<f32>, 121>;
    var count = 0u;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            let nx = i32(id.x) + dx;
            let ny = i32(id.y) + dy;
            if nx < 0 || ny < 0 || nx >= i32(p.width) || ny >= i32(p.height) { continue; }
            let j = u32(ny) * p.width + u32(nx);
            let a = flow[j];
            let b = flow[n + j];
            if a == 0.0 && b == 0.0 { continue; }
            let angle = relative_angle(u, v, a, b);
            // Two breaks, not `while k > 0u && angles[k - 1u] > angle`: see median.wgsl.
            var k = count;
            loop {
                if k == 0u { break; }
                if angles[k - 1u] <= angle { break; }
                angles[k] = angles[k - 1u];
                vectors[k] = vectors[k - 1u];
                k--;
            }
            angles[k] = angle;
            vectors[k] = vec2<f32>(a, b);
            count++;
        }
    }
    let median = vectors[count / 2u];
    let scale = sqrt(u * u + v * v) / sqrt(median.x * median.x + median.y * median.y);
    output[i] = round(median.x * scale);
    output[n + i] = round(median.y * scale);
}
