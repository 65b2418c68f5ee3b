//! Chapter 10's image filters as a person writes them in WGSL, on RGBA8 images as the
//! listings' `image2D_uc` parameters hold them (Listing 15: mean, Listing 16: bilateral; border
//! pixels written invalid), with their CPU references: the yardstick the code generator's kernels
//! are checked and timed against (10.4.5 compares generated with hand-written code). Each runs
//! as a [`Program`](crate::program::Program) with [`BINDINGS`]: its parameters at 0, the input
//! texture at 1, the output storage texture at 2, one work-item per pixel in 8×8 work-groups.
//! [`find_index`] is Listings 34–39's reduction, the yardstick of the generated findIndex.

use crate::program::{BindingKind, BindingSpec, TexelFormat};

pub mod find_index;

/// Listing 15's mean filter.
pub const MEAN_WGSL: &str = include_str!("mean.wgsl");
/// Listing 16's bilateral filter.
pub const BILATERAL_WGSL: &str = include_str!("bilateral.wgsl");
/// The entry point of both.
pub const ENTRY_POINT: &str = "main";

/// The bindings of both filters.
pub const BINDINGS: [BindingSpec; 3] = [
    BindingSpec { binding: 0, kind: BindingKind::Uniform },
    BindingSpec { binding: 1, kind: BindingKind::Texture { format: TexelFormat::Rgba8Uint, dimensions: 2 } },
    BindingSpec {
        binding: 2,
        kind: BindingKind::StorageTexture { format: TexelFormat::Rgba8Uint, dimensions: 2, read: false },
    },
];

/// The work-groups that cover a `width × height` image.
pub fn workgroups(width: u32, height: u32) -> [u32; 3] {
    [width.div_ceil(8), height.div_ceil(8), 1]
}

fn words(words: &[[u8; 4]]) -> Vec<u8> {
    words.concat()
}

/// The mean filter's parameter block.
pub fn mean_params(kernel_size: i32, width: u32, height: u32) -> Vec<u8> {
    words(&[kernel_size.to_le_bytes(), (width as i32).to_le_bytes(), (height as i32).to_le_bytes(), [0; 4]])
}

/// The bilateral filter's parameter block.
pub fn bilateral_params(radius: f32, sigma_spatial: f32, sigma_range: f32, width: u32, height: u32) -> Vec<u8> {
    words(&[
        radius.to_le_bytes(),
        sigma_spatial.to_le_bytes(),
        sigma_range.to_le_bytes(),
        [0; 4],
        (width as i32).to_le_bytes(),
        (height as i32).to_le_bytes(),
        [0; 4],
        [0; 4],
    ])
}

/// The texel at `(x, y)` of a packed RGBA8 image, RGB as floats.
fn rgb(texels: &[u8], width: usize, x: usize, y: usize) -> [f32; 3] {
    let at = 4 * (y * width + x);
    [texels[at] as f32, texels[at + 1] as f32, texels[at + 2] as f32]
}

/// Runs `pixel` on every pixel at least `r` from the border, writes the rest invalid.
fn map_interior(width: usize, height: usize, r: usize, pixel: impl Fn(usize, usize) -> [f32; 3]) -> Vec<u8> {
    let mut out = vec![0u8; 4 * width * height];
    for y in 0..height {
        for x in 0..width {
            let at = 4 * (y * width + x);
            out[at + 3] = 255;
            if x < r || y < r || x + r >= width || y + r >= height {
                continue;
            }
            let value = pixel(x, y);
            for c in 0..3 {
                out[at + c] = value[c] as i32 as u8;
            }
        }
    }
    out
}

/// Listing 15 on the CPU: `texels` packed RGBA8, row after row.
pub fn mean(texels: &[u8], width: usize, height: usize, kernel_size: i32) -> Vec<u8> {
    let r = (kernel_size / 2).max(0) as usize;
    let count = ((2 * r + 1) * (2 * r + 1)) as f32;
    map_interior(width, height, r, |x, y| {
        let mut sum = [0.0f32; 3];
        for u in x - r..=x + r {
            for v in y - r..=y + r {
                let texel = rgb(texels, width, u, v);
                for c in 0..3 {
                    sum[c] += texel[c] / 255.0;
                }
            }
        }
        sum.map(|s| s / count * 255.0)
    })
}

/// Listing 16 on the CPU: `texels` packed RGBA8, row after row.
pub fn bilateral(
    texels: &[u8],
    width: usize,
    height: usize,
    radius: f32,
    sigma_spatial: f32,
    sigma_range: f32,
) -> Vec<u8> {
    let r = radius.max(0.0) as usize;
    map_interior(width, height, r, |x, y| {
        let centre = rgb(texels, width, x, y);
        let (mut sum, mut weights) = ([0.0f32; 3], 0.0f32);
        for u in x - r..=x + r {
            for v in y - r..=y + r {
                let texel = rgb(texels, width, u, v);
                let (du, dv) = (u as f32 - x as f32, v as f32 - y as f32);
                let difference: f32 = (0..3).map(|c| (texel[c] - centre[c]).powi(2)).sum();
                let weight = (-(du * du + dv * dv) / (2.0 * sigma_spatial * sigma_spatial)).exp()
                    * (-difference / (2.0 * sigma_range * sigma_range)).exp();
                for c in 0..3 {
                    sum[c] += texel[c] * weight;
                }
                weights += weight;
            }
        }
        sum.map(|s| s / weights)
    })
}
