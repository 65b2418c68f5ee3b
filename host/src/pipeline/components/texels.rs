//! Images between the pipeline's planes (4 planes of f32: R, G, B, A) and the `rgba8uint`
//! textures generated device code reads and writes (`image2D_uc`): two small programs recorded
//! into the frame's encoder.

use gudsl_runtime::{BindingKind, BindingSpec, DeviceBuffer, DeviceImage, Gpu, Program, Resource, TexelFormat};

use super::Ctx;

/// The two programs that move an image between the pipeline's planes (4 planes of f32, R G B A)
/// and an `rgba8uint` texture.
pub struct Conversions {
    pack: Program,
    unpack: Program,
}

const PACK: &str = "
struct Size { width: u32, height: u32, _a: u32, _b: u32 }
@group(0) @binding(0) var<uniform> size: Size;
@group(0) @binding(1) var<storage, read> planes: array<f32>;
@group(0) @binding(2) var image: texture_storage_2d<rgba8uint, write>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= size.width || id.y >= size.height { return; }
    let n = size.width * size.height;
    let i = id.y * size.width + id.x;
    let texel = vec4<f32>(planes[i], planes[n + i], planes[2u * n + i], planes[3u * n + i]);
    textureStore(image, vec2<i32>(id.xy), vec4<u32>(clamp(texel, vec4<f32>(0.0), vec4<f32>(255.0))));
}
";

const UNPACK: &str = "
struct Size { width: u32, height: u32, _a: u32, _b: u32 }
@group(0) @binding(0) var<uniform> size: Size;
@group(0) @binding(1) var image: texture_2d<u32>;
@group(0) @binding(2) var<storage, read_write> planes: array<f32>;

@compute @workgroup_size(8, 8)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= size.width || id.y >= size.height { return; }
    let n = size.width * size.height;
    let i = id.y * size.width + id.x;
    let texel = vec4<f32>(textureLoad(image, vec2<i32>(id.xy), 0));
    planes[i] = texel.x;
    planes[n + i] = texel.y;
    planes[2u * n + i] = texel.z;
    planes[3u * n + i] = texel.w;
}
";

impl Conversions {
    pub fn new(gpu: &Gpu) -> Result<Conversions, gudsl_runtime::ProgramError> {
        let format = TexelFormat::Rgba8Uint;
        let uniform = BindingSpec { binding: 0, kind: BindingKind::Uniform };
        let pack = Program::new(
            gpu,
            "planes to image",
            PACK,
            "main",
            &[
                uniform,
                BindingSpec { binding: 1, kind: BindingKind::Storage { writable: false } },
                BindingSpec { binding: 2, kind: BindingKind::StorageTexture { format, dimensions: 2, read: false } },
            ],
        )?;
        let unpack = Program::new(
            gpu,
            "image to planes",
            UNPACK,
            "main",
            &[
                uniform,
                BindingSpec { binding: 1, kind: BindingKind::Texture { format, dimensions: 2 } },
                BindingSpec { binding: 2, kind: BindingKind::Storage { writable: true } },
            ],
        )?;
        Ok(Conversions { pack, unpack })
    }

    pub fn pack(&self, ctx: &mut Ctx, planes: &DeviceBuffer, image: &DeviceImage) -> Result<(), String> {
        Self::record(ctx, &self.pack, image.size(), Resource::Buffer(planes), Resource::Image(image))
    }

    pub fn unpack(&self, ctx: &mut Ctx, image: &DeviceImage, planes: &DeviceBuffer) -> Result<(), String> {
        Self::record(ctx, &self.unpack, image.size(), Resource::Image(image), Resource::Buffer(planes))
    }

    fn record(
        ctx: &mut Ctx,
        program: &Program,
        [width, height, _]: [u32; 3],
        from: Resource,
        to: Resource,
    ) -> Result<(), String> {
        let size: Vec<u8> = [width, height, 0, 0].iter().flat_map(|n| n.to_le_bytes()).collect();
        let resources = [(0, Resource::Uniform(&size)), (1, from), (2, to)];
        let workgroups = [width.div_ceil(8), height.div_ceil(8), 1];
        ctx.device.dispatch(ctx.stage, program, &[], &resources, workgroups).map_err(|e| e.to_string())
    }
}
