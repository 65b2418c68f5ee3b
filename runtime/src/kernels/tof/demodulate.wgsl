// 4-phase PMD demodulation (sec. 2.1.1). Raw planes A0 B0 A1 B1 A2 B2 A3 B3, P_i = A_i − B_i:
// phase = atan2(P3 − P1, P0 − P2) in [0, 2π), amplitude = ½·√((P3 − P1)² + (P0 − P2)²),
// intensity = Σ(A_i + B_i)/4, distance = range·phase/2π.
struct Params { pixels: u32, width: u32, range: f32, _pad: u32, _pad2: vec4<u32> }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read_write> phase_out: array<f32>;
@group(0) @binding(3) var<storage, read_write> amplitude_out: array<f32>;
@group(0) @binding(4) var<storage, read_write> intensity_out: array<f32>;
@group(0) @binding(5) var<storage, read_write> distance_out: array<f32>;

const TAU: f32 = 6.283185307179586;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let height = p.pixels / p.width;
    if id.x >= p.width || id.y >= height { return; }
    let i = id.y * p.width + id.x;
    let n = p.pixels;
    var a: array<f32, 4>;
    var sum = 0.0;
    for (var k = 0u; k < 4u; k++) {
        let ak = raw[(2u * k) * n + i];
        let bk = raw[(2u * k + 1u) * n + i];
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
