// Black-image subtraction and phase normalization in one pass (`normalize_pixel.wgsl`): each
// sample is `less_black` of it, as `subtract_black.wgsl` writes it, so the pass gives what the
// two kernels give, without writing and reading the frame between.
@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> black: array<f32>;
@group(0) @binding(3) var<storage, read> calibration: array<f32>;
@group(0) @binding(4) var<storage, read_write> output: array<f32>;

fn sample(plane: u32, i: u32) -> f32 {
    return less_black(plane * p.width * p.height + i);
}
