// Eq. 4.4's motion measure of pixel i of an n-pixel raw frame, M = Σ_{k=1..3} |P⁺_k − P⁺_0| with
// P⁺_k = A_k + B_k; shared by `detect_motion.wgsl` and `detect_match.wgsl` (each declares `raw`).
fn motion_measure(i: u32, n: u32) -> f32 {
    let p0 = raw[i] + raw[n + i];
    var m = 0.0;
    for (var k = 1u; k < 4u; k++) {
        m += abs(raw[2u * k * n + i] + raw[(2u * k + 1u) * n + i] - p0);
    }
    return m;
}
