// Phase normalization (sec. 4.2.2.1, eq. 4.1) of pixel i: each channel A_i, B_i, read with
// `sample(plane, i)` (the including shader's: the raw frame's, or the frame less its black
// image), through its pixel's tap function f(X) = a·sqrt(max(X + b, 0)) + c·X + d; calibration
// planes a b c d of tap A, then B.
struct Params { width: u32, height: u32, _pad: vec2<u32>, _pad2: vec4<u32> }

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    let n = p.width * p.height;
    let i = id.y * p.width + id.x;
    for (var plane = 0u; plane < 8u; plane++) {
        let tap = plane % 2u;
        let a = calibration[(4u * tap) * n + i];
        let b = calibration[(4u * tap + 1u) * n + i];
        let c = calibration[(4u * tap + 2u) * n + i];
        let d = calibration[(4u * tap + 3u) * n + i];
        let x = sample(plane, i);
        output[plane * n + i] = a * sqrt(max(x + b, 0.0)) + c * x + d;
    }
}
