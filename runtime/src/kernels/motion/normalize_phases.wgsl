// Phase normalization of a raw frame as it is (`normalize_pixel.wgsl`).
@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read> calibration: array<f32>;
@group(0) @binding(3) var<storage, read_write> output: array<f32>;

fn sample(plane: u32, i: u32) -> f32 {
    return raw[plane * p.width * p.height + i];
}
