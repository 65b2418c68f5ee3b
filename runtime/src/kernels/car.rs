//! CPU references of the car-reconstruction chain of chapter 6 before registration: amplitude
//! masking (eq. 6.1), 3×3 outlier removal, background segmentation on intensity AND distance
//! with morphology, and the point cloud with its normals. A distance of 0 marks an invalid pixel.

use crate::Image;

/// Eq. 6.1: distance kept where `min ≤ amplitude ≤ max`, else 0 (under- or over-saturated).
pub fn mask_amplitude(distance: &Image, amplitude: &Image, min: f32, max: f32) -> Image {
    let data =
        distance.data.iter().zip(&amplitude.data).map(|(&d, &a)| if a >= min && a <= max { d } else { 0.0 }).collect();
    Image { data, ..distance.clone() }
}

/// Sec. 6.5.1.3: a valid pixel stays valid when at least `min_similar` of its valid 8-neighbours
/// lie within `range` metres of it; else it becomes 0 (flying pixels go).
pub fn remove_outliers(distance: &Image, range: f32, min_similar: u32) -> Image {
    let (w, h) = (distance.width as isize, distance.height as isize);
    let mut out = distance.clone();
    for y in 0..h {
        for x in 0..w {
            let d = distance.data[(y * w + x) as usize];
            if d == 0.0 {
                continue;
            }
            let mut similar = 0;
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (nx, ny) = (x + dx, y + dy);
                    if (dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= w || ny >= h {
                        continue;
                    }
                    let n = distance.data[(ny * w + nx) as usize];
                    if n != 0.0 && (n - d).abs() < range {
                        similar += 1;
                    }
                }
            }
            if similar < min_similar {
                out.data[(y * w + x) as usize] = 0.0;
            }
        }
    }
    out
}

/// The median background model (sec. 6.5.2): per pixel, the median over frames of the empty scene.
pub fn background(frames: &[Image]) -> Image {
    let first = &frames[0];
    let mut out = Image::zeros(first.width, first.height, first.planes);
    let mut values = Vec::with_capacity(frames.len());
    for i in 0..first.data.len() {
        values.clear();
        values.extend(frames.iter().map(|f| f.data[i]));
        values.sort_by(f32::total_cmp);
        out.data[i] = values[values.len() / 2];
    }
    out
}

/// Foreground (sec. 6.5.2): `|I − B_I| > θ_I AND |D − B_D| > θ_D` on valid distances, as 1 or 0.
pub fn segment(
    intensity: &Image,
    distance: &Image,
    background_intensity: &Image,
    background_distance: &Image,
    theta_intensity: f32,
    theta_distance: f32,
) -> Image {
    let data = (0..distance.data.len())
        .map(|i| {
            let d = distance.data[i];
            let foreground = d != 0.0
                && (intensity.data[i] - background_intensity.data[i]).abs() > theta_intensity
                && (d - background_distance.data[i]).abs() > theta_distance;
            if foreground {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    Image { data, ..distance.clone() }
}

/// Binary erosion (`dilate` false) or dilation over a `(2r+1)²` square, edges replicated.
pub fn morphology(mask: &Image, radius: u32, dilate: bool) -> Image {
    let r = radius as isize;
    let mut out = mask.clone();
    for y in 0..mask.height as isize {
        for x in 0..mask.width as isize {
            let mut any = false;
            let mut all = true;
            for dy in -r..=r {
                for dx in -r..=r {
                    let on = mask.at_clamped(0, x + dx, y + dy) != 0.0;
                    any |= on;
                    all &= on;
                }
            }
            out.data[y as usize * mask.width + x as usize] =
                if (dilate && any) || (!dilate && all) { 1.0 } else { 0.0 };
        }
    }
    out
}

/// `value · mask` per pixel (a mask of 1 and 0 keeps or clears).
pub fn apply_mask(value: &Image, mask: &Image) -> Image {
    let data = value.data.iter().zip(&mask.data).map(|(v, m)| if *m != 0.0 { *v } else { 0.0 }).collect();
    Image { data, ..value.clone() }
}

/// Polar → Cartesian (sec. 6.5.3): `P = D · ray` with the per-pixel unit rays of the intrinsics
/// (3 planes: x, y, z); invalid distances give the origin.
pub fn point_cloud(distance: &Image, rays: &Image) -> Image {
    let n = distance.pixels();
    let mut out = Image::zeros(distance.width, distance.height, 3);
    for i in 0..n {
        for k in 0..3 {
            out.data[k * n + i] = distance.data[i] * rays.data[k * n + i];
        }
    }
    out
}

/// Normals by central differences (sec. 6.5.3), facing the camera:
/// `n = normalise((P(x, y+1) − P(x, y−1)) × (P(x+1, y) − P(x−1, y)))`; zero where a neighbour
/// is invalid (at the origin) or outside the image.
pub fn normals(points: &Image) -> Image {
    let (w, h) = (points.width, points.height);
    let n = w * h;
    let at = |x: usize, y: usize| points.vector(y * w + x);
    let mut out = Image::zeros(w, h, 3);
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let (l, r, u, d, c) = (at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1), at(x, y));
            if [l, r, u, d, c].iter().any(|p| p[2] == 0.0) {
                continue;
            }
            let a = [d[0] - u[0], d[1] - u[1], d[2] - u[2]];
            let b = [r[0] - l[0], r[1] - l[1], r[2] - l[2]];
            let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
            let len = (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
            if len > 0.0 {
                for (k, c) in cross.into_iter().enumerate() {
                    out.data[k * n + y * w + x] = c / len;
                }
            }
        }
    }
    out
}
