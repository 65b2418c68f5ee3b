// Black-image subtraction and demodulation in one pass (`demodulate_pixel.wgsl`): each sample
// is `less_black` of it, as `subtract_black.wgsl` writes it, so the pass gives what the two
// kernels give, without writing and reading the frame between.
@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> black: array<f32>;
@group(0) @binding(3) var<storage, read_write> phase_out: array<f32>;
@group(0) @binding(4) var<storage, read_write> amplitude_out: array<f32>;
@group(0) @binding(5) var<storage, read_write> intensity_out: array<f32>;
@group(0) @binding(6) var<storage, read_write> distance_out: array<f32>;

fn sample(plane: u32, i: u32) -> f32 {
    return less_black(plane * p.pixels + i);
}
