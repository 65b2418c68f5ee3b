//! Block matching (eq. 4.6–4.10): raw frame, mask → flow (dx, dy per phase image) over a
//! `window × window` search, optionally restricted to directions near the previous mean, and
//! optionally refined to a quarter pixel.

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;

use super::{allowed, blended_squared_difference};
use crate::{
    kernels::{
        pixels::{per_pixel, scatter},
        Pass, Shape, Unit,
    },
    Image,
};

/// The uniform block of `match_blocks.wgsl`, field for field.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable)]
pub(crate) struct Params {
    width: u32,
    height: u32,
    radius: u32,
    /// 1 when the search is restricted to directions near `mean_dir`.
    restricted: u32,
    mean_dir: f32,
    half_width: f32,
    /// 1 when the flow is refined to a quarter pixel.
    subpixel: u32,
    /// The motion threshold of `detect_match.wgsl` (padding in `match_blocks.wgsl`).
    theta: f32,
}

impl Params {
    /// The block with `detect_match.wgsl`'s threshold.
    pub(crate) fn with_theta(self, theta: f32) -> Params {
        Params { theta, ..self }
    }
}

/// Block matching over MWS `window`, the restriction (mean direction, half width) in radians,
/// whole pixels or refined to a quarter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MatchBlocks {
    pub(crate) window: u32,
    pub(crate) restriction: Option<(f32, f32)>,
    pub(crate) subpixel: bool,
}

impl Unit for MatchBlocks {
    const NAME: &'static str = "match_blocks";
    const SOURCE: &'static str = concat!(include_str!("match_search.wgsl"), include_str!("match_blocks.wgsl"));
    const INPUTS: &'static [Option<usize>] = &[Some(8), Some(1)];
    type Params = Params;

    fn params(&self, inputs: &[Shape]) -> Params {
        let s = inputs[0];
        let (mean_dir, half_width) = self.restriction.unwrap_or((0.0, 0.0));
        Params {
            width: s.width as u32,
            height: s.height as u32,
            radius: (self.window - 1) / 2,
            restricted: u32::from(self.restriction.is_some()),
            mean_dir,
            half_width,
            subpixel: u32::from(self.subpixel),
            theta: 0.0,
        }
    }

    fn outputs(&self, inputs: &[Shape]) -> Vec<Shape> {
        vec![Shape { planes: 2, ..inputs[0] }]
    }

    fn passes(&self, inputs: &[Shape]) -> Vec<Pass> {
        vec![Pass::tiles(inputs[0])]
    }

    fn cpu(&self, inputs: &[&Image]) -> Vec<Image> {
        vec![match_blocks(inputs[0], inputs[1], self.window, self.restriction, self.subpixel)]
    }
}

/// The steps of the sub-pixel refinement, in pixels.
const REFINEMENT_STEPS: [f32; 2] = [0.5, 0.25];

/// Block matching (eq. 4.6–4.10): for each masked pixel the displacement per phase image
/// `(dx, dy)` within `±(window−1)/2` minimising `Σ_{i=1..3} (P⁺_0(x,y) − P⁺_i(x+i·dx, y+i·dy))²`
/// (ties: the shorter vector, then scan order); unmasked pixels get (0, 0). Two planes: dx, dy.
///
/// With `subpixel` (beyond the text), the whole-pixel vector is refined: the eight vectors half
/// a pixel around it, then the eight a quarter pixel around the better one, each scored by the
/// bilinearly weighted squared differences of the whole pixels around its samples (see
/// [`blended_squared_difference`]: a blend across an edge scores worse than either side) and
/// taken only when strictly better. The text's whole pixels leave
/// up to half a pixel per phase image, three halves by the last one: at 1 cm per phase image and
/// 3 m the image moves about 0.9 px, and a turn moves most pixels less than half of one.
pub fn match_blocks(raw: &Image, mask: &Image, window: u32, restriction: Option<(f32, f32)>, subpixel: bool) -> Image {
    let (w, h) = (raw.width, raw.height);
    let r = (window as i32 - 1) / 2;
    // The candidates every pixel tries, in scan order: the restriction is the same for all.
    let candidates: Vec<(i32, i32)> = (-r..=r)
        .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
        .filter(|&(dx, dy)| allowed(dx as f32, dy as f32, restriction))
        .collect();
    let sums = PhaseSums::new(raw, 3 * r as usize + 2);
    let flow = per_pixel(w, h, |x, y| {
        if mask.data[y * w + x] == 0.0 {
            return [0.0, 0.0];
        }
        let (xi, yi) = (x as isize, y as isize);
        let p0 = sums.at(0, xi, yi);
        let mut best = (f32::INFINITY, i32::MAX, 0, 0);
        for &(dx, dy) in &candidates {
            let ssd: f32 = (1..4)
                .map(|k| {
                    let d = p0 - sums.at(k, xi + (k as i32 * dx) as isize, yi + (k as i32 * dy) as isize);
                    d * d
                })
                .sum();
            let length = dx * dx + dy * dy;
            if ssd < best.0 || (ssd == best.0 && length < best.1) {
                best = (ssd, length, dx, dy);
            }
        }
        let (ssd, u, v) = (best.0, best.2 as f32, best.3 as f32);
        if subpixel {
            let (_, u, v) = refined(raw, (x as f32, y as f32), p0, (ssd, u, v), restriction);
            return [u, v];
        }
        [u, v]
    });
    let mut out = Image::zeros(w, h, 2);
    scatter(&mut out.data, w * h, &flow);
    out
}

/// The whole-pixel vector `(ssd, u, v)` of the pixel at `at` refined by half, then quarter
/// pixels, each step's eight neighbours taken only when strictly better.
fn refined(
    raw: &Image,
    at: (f32, f32),
    p0: f32,
    whole: (f32, f32, f32),
    restriction: Option<(f32, f32)>,
) -> (f32, f32, f32) {
    let (mut ssd, mut u, mut v) = whole;
    for step in REFINEMENT_STEPS {
        let (cu, cv) = (u, v);
        for oy in -1..=1 {
            for ox in -1..=1 {
                let (du, dv) = (cu + ox as f32 * step, cv + oy as f32 * step);
                if (ox == 0 && oy == 0) || !allowed(du, dv, restriction) {
                    continue;
                }
                let candidate: f32 = (1..4)
                    .map(|k| {
                        let (fx, fy) = (at.0 + k as f32 * du, at.1 + k as f32 * dv);
                        blended_squared_difference(raw, k, fx, fy, p0)
                    })
                    .sum();
                if candidate < ssd {
                    (ssd, u, v) = (candidate, du, dv);
                }
            }
        }
    }
    (ssd, u, v)
}

/// `P⁺_k = A_k + B_k` of the four phase images, computed once a frame on a border of `pad`
/// pixels that repeats the edge (as clamping would): a candidate up to `pad` pixels out reads
/// one value, no clamping.
struct PhaseSums {
    planes: Vec<Vec<f32>>,
    width: usize,
    height: usize,
    pad: usize,
}

impl PhaseSums {
    fn new(raw: &Image, pad: usize) -> PhaseSums {
        let (w, h, n) = (raw.width, raw.height, raw.pixels());
        let (width, height) = (w + 2 * pad, h + 2 * pad);
        let clamped = |at: usize, size: usize| at.saturating_sub(pad).min(size - 1);
        let planes = (0..4)
            .into_par_iter()
            .map(|k| {
                let (a, b) = (&raw.data[2 * k * n..(2 * k + 1) * n], &raw.data[(2 * k + 1) * n..(2 * k + 2) * n]);
                let mut plane = Vec::with_capacity(width * height);
                for py in 0..height {
                    let row = clamped(py, h) * w;
                    plane.extend((0..width).map(|px| row + clamped(px, w)).map(|i| a[i] + b[i]));
                }
                plane
            })
            .collect();
        PhaseSums { planes, width, height, pad }
    }

    /// `P⁺_k` at `(x, y)`, coordinates clamped (beyond the border only, where a refinement or a
    /// large window reaches).
    fn at(&self, k: usize, x: isize, y: isize) -> f32 {
        let x = (x + self.pad as isize).clamp(0, self.width as isize - 1) as usize;
        let y = (y + self.pad as isize).clamp(0, self.height as isize - 1) as usize;
        self.planes[k][y * self.width + x]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 16 × 5 raw frame whose phase image `k` has `P⁺ = value(k, x) + 1000·y` (split evenly
    /// over A and B: the rows differ so much that only horizontal vectors match), all pixels
    /// masked.
    fn frame(value: impl Fn(usize, usize) -> f32) -> (Image, Image) {
        let width = 16;
        let mut raw = Image::zeros(width, 5, 8);
        let n = raw.pixels();
        for k in 0..4 {
            for i in 0..n {
                let half = (value(k, i % width) + 1000.0 * (i / width) as f32) / 2.0;
                raw.data[2 * k * n + i] = half;
                raw.data[(2 * k + 1) * n + i] = half;
            }
        }
        let mut mask = Image::zeros(width, 5, 1);
        mask.data.fill(1.0);
        (raw, mask)
    }

    #[test]
    fn a_ramp_moving_half_a_pixel_per_phase_image_is_refined_to_half_a_pixel() {
        let (raw, mask) = frame(|k, x| 10.0 * (x as f32 - 0.5 * k as f32));
        let i = 2 * 16 + 4;
        let whole = match_blocks(&raw, &mask, 5, None, false);
        assert!(whole.data[i] == 0.0 || whole.data[i] == 1.0, "whole pixels: {}", whole.data[i]);
        let refined = match_blocks(&raw, &mask, 5, None, true);
        assert_eq!((refined.data[i], refined.data[refined.pixels() + i]), (0.5, 0.0));
    }

    #[test]
    fn a_vector_that_would_blend_object_and_wall_does_not_beat_a_whole_one() {
        // The object (P⁺ 100) left of the wall (200) moves one pixel per phase image; the
        // reference pixel at x = 8 is mixed (150) in phase image 0 only. Half a pixel blends
        // object and wall to exactly 150 in every later phase image: bilinear samples would
        // match it perfectly, the blended squared difference scores it as the whole vectors.
        let (raw, mask) = frame(|k, x| match (x as isize - k as isize).cmp(&8) {
            std::cmp::Ordering::Less => 100.0,
            std::cmp::Ordering::Equal if k == 0 => 150.0,
            _ => 200.0,
        });
        let i = 2 * 16 + 8;
        let flow = match_blocks(&raw, &mask, 5, None, true);
        let (u, v) = (flow.data[i], flow.data[flow.pixels() + i]);
        assert_eq!((u.fract(), v.fract()), (0.0, 0.0), "({u}, {v}) blends across the edge");
    }
}
