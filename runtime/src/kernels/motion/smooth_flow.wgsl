// Flow smoothing ("NH", sec. 4.2.4): each non-zero vector takes the median direction of the
// non-zero vectors in its window (≤ 11×11), keeps its length, rounded to whole pixels.
struct Params { width: u32, height: u32, radius: u32, _pad: u32, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> flow: array<f32>;
@group(0) @binding(2) var<storage, read_write> output: array<f32>;

const PI: f32 = 3.141592653589793;

fn angle_of(dx: f32, dy: f32) -> f32 {
    let a = atan2(dy, dx);
    return select(a, a + 2.0 * PI, a < 0.0);
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
            let angle = angle_of(a, b);
            // Two breaks, not `while k > 0u && angles[k - 1u] > angle`: see median.wgsl.
            var k = count;
            loop {
                if k == 0u { break; }
                if angles[k - 1u] <= angle { break; }
                angles[k] = angles[k - 1u];
                k--;
            }
            angles[k] = angle;
            count++;
        }
    }
    let median = angles[count / 2u];
    let length = sqrt(u * u + v * v);
    output[i] = round(length * cos(median));
    output[n + i] = round(length * sin(median));
}
