//! The CPU references' loop over pixels: rows shared out over the machine's cores (rayon),
//! each pixel computed alone, results in scan order — so a reference gives the same image on
//! one core or sixteen.

use rayon::prelude::*;

/// `pixel(x, y)` for every pixel of a `width × height` image, in scan order, rows in parallel.
pub(crate) fn per_pixel<T: Send>(width: usize, height: usize, pixel: impl Fn(usize, usize) -> T + Sync) -> Vec<T> {
    (0..height).into_par_iter().flat_map_iter(|y| (0..width).map(move |x| (x, y))).map(|(x, y)| pixel(x, y)).collect()
}

/// Writes each pixel's `planes` values into the planes of `data` (`pixels` values a plane).
pub(crate) fn scatter<const P: usize>(data: &mut [f32], pixels: usize, values: &[[f32; P]]) {
    for (i, value) in values.iter().enumerate() {
        for (plane, v) in value.iter().enumerate() {
            data[plane * pixels + i] = *v;
        }
    }
}
