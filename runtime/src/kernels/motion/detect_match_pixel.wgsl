// Motion detection (eq. 4.4, 4.5) and block matching (eq. 4.6–4.10) of one pixel, shared by
// `detect_match.wgsl` and `detect_match_around.wgsl` (each declares `p`, `raw`, `flow` and
// `mask_out`; `around` is the restriction, as `best_flow` takes it): its M (`motion_measure`, as
// `detect_motion.wgsl` computes it), its mask M > θ written, and where it is set its flow
// (`best_flow`, `match_search.wgsl`) as `match_blocks.wgsl` finds it. Each pixel's mask is its
// own (no neighbour's), so the fusion is exact.
fn detect_match_pixel(x: u32, y: u32, around: vec2<f32>) {
    let n = p.width * p.height;
    let i = y * p.width + x;
    let m = motion_measure(i, n);
    let moving = m > p.theta;
    mask_out[i] = select(0.0, 1.0, moving);
    var best = vec2<f32>(0.0, 0.0);
    if moving {
        best = best_flow(i32(x), i32(y), around);
    }
    flow[i] = best.x;
    flow[n + i] = best.y;
}
