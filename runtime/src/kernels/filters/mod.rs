//! Chapter 10's neighbourhood filters (mean, median, Gaussian, bilateral) on plane 0, edges
//! replicated, one kernel a module with its CPU reference.

use crate::Image;

pub mod mean;
pub mod median;
pub mod weighted;

pub use mean::mean;
pub(crate) use mean::Mean;
pub use median::median;
pub(crate) use median::Median;
pub use weighted::{bilateral, gaussian};
pub(crate) use weighted::{Bilateral, Gaussian};

fn map_pixels(input: &Image, f: impl Fn(isize, isize) -> f32) -> Image {
    let mut out = Image::zeros(input.width, input.height, 1);
    for y in 0..input.height {
        for x in 0..input.width {
            out.data[y * input.width + x] = f(x as isize, y as isize);
        }
    }
    out
}
