// A raw sample less the chip's black image, clamped at 0 (sec. 2.1.2): the one expression of
// it, for the subtraction's own kernel and for the kernels it is fused into, so that both give
// the same bits (the including shader binds `raw` and `black`).
fn less_black(at: u32) -> f32 {
    return max(raw[at] - black[at], 0.0);
}
