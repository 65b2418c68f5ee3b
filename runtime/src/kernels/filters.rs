//! CPU references of the neighbourhood filters (mean, median, Gaussian, bilateral) on plane 0,
//! edges replicated, as their WGSL twins compute them.

use crate::Image;

/// The window radius of a Gaussian of `sigma`: ⌈3σ⌉, at least 1.
pub(super) fn gaussian_radius(sigma: f32) -> u32 {
    ((3.0 * sigma).ceil() as u32).max(1)
}

fn map_pixels(input: &Image, f: impl Fn(isize, isize) -> f32) -> Image {
    let mut out = Image::zeros(input.width, input.height, 1);
    for y in 0..input.height {
        for x in 0..input.width {
            out.data[y * input.width + x] = f(x as isize, y as isize);
        }
    }
    out
}

/// Box mean over a `(2r+1)²` window.
pub fn mean(input: &Image, radius: u32) -> Image {
    let r = radius as isize;
    map_pixels(input, |x, y| {
        let mut sum = 0.0f32;
        for dy in -r..=r {
            for dx in -r..=r {
                sum += input.at_clamped(0, x + dx, y + dy);
            }
        }
        sum / ((2 * r + 1) * (2 * r + 1)) as f32
    })
}

/// Median over a `(2r+1)²` window.
pub fn median(input: &Image, radius: u32) -> Image {
    let r = radius as isize;
    map_pixels(input, |x, y| {
        let mut values: Vec<f32> = Vec::with_capacity(((2 * r + 1) * (2 * r + 1)) as usize);
        for dy in -r..=r {
            for dx in -r..=r {
                values.push(input.at_clamped(0, x + dx, y + dy));
            }
        }
        values.sort_by(f32::total_cmp);
        values[values.len() / 2]
    })
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
