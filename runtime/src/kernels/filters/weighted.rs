//! Spatial and range weighted means on one shader (`weighted.wgsl`): the Gaussian (no range
//! weight) and the bilateral filter of chapter 10, normalised, edges replicated.

use bytemuck::{Pod, Zeroable};

use super::map_pixels;
use crate::{
    kernels::{Pass, Shape, Unit},
    Image,
};

/// The uniform block of `weighted.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    sigma_space: f32,
    /// 0 turns the range weight off: a plain Gaussian.
    sigma_range: f32,
    _pad: u32,
    _pad2: [u32; 2],
}

impl Params {
    fn new(input: Shape, radius: u32, sigma_space: f32, sigma_range: f32) -> Params {
        let (width, height) = (input.width as u32, input.height as u32);
        Params { width, height, radius, sigma_space, sigma_range, _pad: 0, _pad2: [0; 2] }
    }
}

/// Gaussian of σ over a `(2⌈3σ⌉+1)²` window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Gaussian {
    pub(crate) sigma: f32,
}

impl Unit for Gaussian {
    const NAME: &'static str = "gaussian";
    const SOURCE: &'static str = include_str!("weighted.wgsl");
    const INPUTS: &'static [Option<usize>] = &[None];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        Params::new(inputs[0], gaussian_radius(self.sigma), self.sigma, 0.0)
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![gaussian(inputs[0], self.sigma)]
    }
}

/// Bilateral filter over a `(2r+1)²` window: spatial and range Gaussians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Bilateral {
    pub(crate) radius: u32,
    pub(crate) sigma_space: f32,
    pub(crate) sigma_range: f32,
}

impl Unit for Bilateral {
    const NAME: &'static str = "bilateral";
    const SOURCE: &'static str = include_str!("weighted.wgsl");
    const INPUTS: &'static [Option<usize>] = &[None];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        Params::new(inputs[0], self.radius, self.sigma_space, self.sigma_range.max(f32::MIN_POSITIVE))
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 1, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![bilateral(inputs[0], self.radius, self.sigma_space, self.sigma_range)]
    }
}

/// The window radius of a Gaussian of `sigma`: ⌈3σ⌉, at least 1.
fn gaussian_radius(sigma: f32) -> u32 {
    ((3.0 * sigma).ceil() as u32).max(1)
}

/// Spatial and range weighted mean: `w = exp(-(dx²+dy²)/(2σs²)) · exp(-(I(q)-I(p))²/(2σr²))`,
/// the range factor left out when `sigma_range` is 0.
fn weighted(input: &Image, radius: u32, sigma_space: f32, sigma_range: f32) -> Image {
    let r = radius as isize;
    map_pixels(input, |x, y| {
        let centre = input.at_clamped(0, x, y);
        let (mut sum, mut weights) = (0.0f32, 0.0f32);
        for dy in -r..=r {
            for dx in -r..=r {
                let value = input.at_clamped(0, x + dx, y + dy);
                let mut w = (-((dx * dx + dy * dy) as f32) / (2.0 * sigma_space * sigma_space)).exp();
                if sigma_range > 0.0 {
                    let d = value - centre;
                    w *= (-(d * d) / (2.0 * sigma_range * sigma_range)).exp();
                }
                sum += w * value;
                weights += w;
            }
        }
        sum / weights
    })
}

/// Gaussian of `sigma` over a `(2⌈3σ⌉+1)²` window, normalised.
pub fn gaussian(input: &Image, sigma: f32) -> Image {
    weighted(input, gaussian_radius(sigma), sigma, 0.0)
}

/// Bilateral filter over a `(2r+1)²` window.
pub fn bilateral(input: &Image, radius: u32, sigma_space: f32, sigma_range: f32) -> Image {
    weighted(input, radius, sigma_space, sigma_range.max(f32::MIN_POSITIVE))
}
