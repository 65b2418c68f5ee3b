// Block matching's search (eq. 4.6–4.10), shared by `match_blocks.wgsl` and the fused passes
// (`detect_match_pixel.wgsl`; each declares `p: Params` with the fields used here and `raw`):
// for pixel (x, y) the displacement per phase image (dx, dy) in ±radius minimising
// Σ_{i=1..3} (P⁺_0(x,y) − P⁺_i(x+i·dx, y+i·dy))², optionally only directions within half_width
// of a mean direction (radians, `around`); ties: shorter vector, then scan order. With subpixel, refined: the eight vectors ½ px around,
// then ¼ px around the better one, scored by the bilinearly weighted squared differences of the
// pixels around each sample and taken only when strictly better.
const PI: f32 = 3.141592653589793;

fn plus(k: u32, x: i32, y: i32) -> f32 {
    let n = p.width * p.height;
    let cx = u32(clamp(x, 0, i32(p.width) - 1));
    let cy = u32(clamp(y, 0, i32(p.height) - 1));
    let i = cy * p.width + cx;
    return raw[2u * k * n + i] + raw[(2u * k + 1u) * n + i];
}

// The squared differences of P⁺_k at the four pixels around fractional (x, y) from p0, weighted
// bilinearly (coordinates clamped): a blend across an edge scores worse than either side.
fn blended_squared_difference(k: u32, x: f32, y: f32, p0: f32) -> f32 {
    let x0 = floor(x);
    let y0 = floor(y);
    let tx = x - x0;
    let ty = y - y0;
    let xi = i32(x0);
    let yi = i32(y0);
    let top = (1.0 - tx) * squared(p0 - plus(k, xi, yi)) + tx * squared(p0 - plus(k, xi + 1, yi));
    let bottom = (1.0 - tx) * squared(p0 - plus(k, xi, yi + 1)) + tx * squared(p0 - plus(k, xi + 1, yi + 1));
    return (1.0 - ty) * top + ty * bottom;
}

fn squared(d: f32) -> f32 {
    return d * d;
}

// `around`: the restriction, (1, the direction in radians) or (0, ·) for none — from the
// uniforms, or from a buffer the GPU wrote.
fn allowed(dx: f32, dy: f32, around: vec2<f32>) -> bool {
    if around.x == 0.0 || (dx == 0.0 && dy == 0.0) { return true; }
    let angle = atan2(dy, dx);
    var diff = abs(angle - around.y) % (2.0 * PI);
    if diff > PI { diff = 2.0 * PI - diff; }
    return diff <= p.half_width + 1e-6;
}

fn best_flow(x: i32, y: i32, around: vec2<f32>) -> vec2<f32> {
    let r = i32(p.radius);
    let p0 = plus(0u, x, y);
    var best = 3.4e38;
    var best_length = 2147483647;
    var best_dx = 0;
    var best_dy = 0;
    for (var dy = -r; dy <= r; dy++) {
        for (var dx = -r; dx <= r; dx++) {
            if !allowed(f32(dx), f32(dy), around) { continue; }
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
    var u = f32(best_dx);
    var v = f32(best_dy);
    if p.subpixel == 1u {
        for (var level = 0; level < 2; level++) {
            let step = select(0.25, 0.5, level == 0);
            let cu = u;
            let cv = v;
            for (var oy = -1; oy <= 1; oy++) {
                for (var ox = -1; ox <= 1; ox++) {
                    let du = cu + f32(ox) * step;
                    let dv = cv + f32(oy) * step;
                    if (ox == 0 && oy == 0) || !allowed(du, dv, around) { continue; }
                    var ssd = 0.0;
                    for (var k = 1; k < 4; k++) {
                        ssd += blended_squared_difference(u32(k), f32(x) + f32(k) * du, f32(y) + f32(k) * dv, p0);
                    }
                    if ssd < best {
                        best = ssd;
                        u = du;
                        v = dv;
                    }
                }
            }
        }
    }
    return vec2<f32>(u, v);
}
