// 4-phase PMD demodulation (sec. 2.1.1) of pixel i, its eight samples read with `sample(plane, i)`
// (the including shader's: the raw frame's, or the frame less its black image). Raw planes
// A0 B0 A1 B1 A2 B2 A3 B3, P_i = A_i − B_i: phase = atan2(P3 − P1, P0 − P2) in [0, 2π),
// amplitude = ½·√((P3 − P1)² + (P0 − P2)²), intensity = Σ(A_i + B_i)/4, distance = range·phase/2π.
struct Params { pixels: u32, width: u32, range: f32, _pad: u32, _pad2: vec4<u32> }

const TAU: f32 = 6.283185307179586;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let height = p.pixels / p.width;
    if id.x >= p.width || id.y >= height { return; }
    let i = id.y * p.width + id.x;
    var a: array<f32, 4>;
    var sum = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let ak = sample(2u * k, i);
        let bk = sample(2u * k + 1u, i);
        a[k] = ak - bk;
        sum += ak + bk;
    }
    let y = a[3] - a[1];
    let x = a[0] - a[2];
    var phase = atan2(y, x);
    if phase < 0.0 { phase += TAU; }
    phase_out[i] = phase;
    amplitude_out[i] = 0.5 * sqrt(y * y + x * x);
    intensity_out[i] = sum / 4.0;
    distance_out[i] = p.range * phase / TAU;
}
