// Motion detection and block matching in one pass (`detect_match_pixel.wgsl`), the search
// restricted (or not) as the uniforms say.
struct Params { width: u32, height: u32, radius: u32, restricted: u32, mean_dir: f32, half_width: f32, subpixel: u32, theta: f32 }

@group(0) @binding(0) var<uniform> p: Params;
@group(0) @binding(1) var<storage, read> raw: array<f32>;
@group(0) @binding(2) var<storage, read_write> flow: array<f32>;
@group(0) @binding(3) var<storage, read_write> mask_out: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= p.width || id.y >= p.height { return; }
    detect_match_pixel(id.x, id.y, vec2<f32>(f32(p.restricted), p.mean_dir));
}
