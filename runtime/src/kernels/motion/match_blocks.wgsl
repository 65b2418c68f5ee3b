// Block matching (eq. 4.6–4.10): per masked pixel, the displacement per phase image (dx, dy) in
// ±radius minimising Σ_{i=1..3} (P⁺_0(x,y) − P⁺_i(x+i·dx, y+i·dy))², optionally only directions
// within half_width of mean_dir (radians); ties: shorter vector, then scan order.
struct Params { width: u32, height: u32, radius: u32, restricted: u32, mean_dir: f32, half_width: f32, _pad: vec2<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> mask: array<f32>;
@group(0) @binding(3) var<storage, read_write> flow: array<f32>;

const PI: f32 = 3.141592653589793;

fn plus(k: u32, x: i32, y: i32) -> f32 {
    let n = p.width * p.height;
    let cx = u32(clamp(x, 0, i32(p.width) - 1));
    let cy = u32(clamp(y, 0, i32(p.height) - 1));
    let i = cy * p.width + cx;
    return raw[2u * k * n + i] + raw[(2u * k + 1u) * n + i];
}

fn allowed(dx: i32, dy: i32) -> bool {
    if p.restricted == 0u || (dx == 0 && dy == 0) { return true; }
    let angle = atan2(f32(dy), f32(dx));
    var diff = abs(angle - p.mean_dir) % (2.0 * PI);
    if diff > PI { diff = 2.0 * PI - diff; }
    return diff <= p.half_width + 1e-6;
}

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    if mask[i] == 0.0 {
        flow[i] = 0.0;
        flow[n + i] = 0.0;
        return;
    }
    let x = i32(id.x);
    let y = i32(id.y);
    let r = i32(p.radius);
    let p0 = plus(0u, x, y);
    var best = 3.4e38;
    var best_length = 2147483647;
    var best_dx = 0;
    var best_dy = 0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            if !allowed(dx, dy) { continue; }
            var ssd = 0.0;
            for (var k = 1; k < 4; k++) {
                let d = p0 - plus(u32(k), x + k * dx, y + k * dy);
                ssd += d * d;
            }
            let length = dx * dx + dy * dy;
            if ssd < best || (ssd == best && length < best_length) {
                best = ssd;
                best_length = length;
                best_dx = dx;
                best_dy = dy;
            }
        }
    }
    flow[i] = f32(best_dx);
    flow[n + i] = f32(best_dy);
}
