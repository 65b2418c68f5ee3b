//! Motion-artifact compensation (chapter 4), one kernel a module with its CPU reference: phase
//! normalization with a per-pixel calibration, motion detection on the channel sums, per-pixel
//! block matching of the phase images along a constant-velocity path (SSD over a motion window,
//! optionally restricted to directions near the previous frame's mean, optionally refined to a
//! quarter pixel), median smoothing of the flow directions, and correction of the raw channels
//! along the flow; and the flow statistics the host needs between frames.

use std::f32::consts::PI;

use crate::Image;

pub mod correct_raw;
pub mod detect_match;
pub mod detect_motion;
pub mod match_blocks;
pub mod mean_direction;
pub mod normalize_phases;
pub mod smooth_flow;

pub use correct_raw::correct_raw;
pub(crate) use correct_raw::CorrectRaw;
pub(crate) use detect_match::{DetectMatch, DetectMatchAround};
pub use detect_motion::detect;
pub(crate) use detect_motion::DetectMotion;
pub use match_blocks::match_blocks;
pub(crate) use match_blocks::MatchBlocks;
pub(crate) use mean_direction::MeanDirection;
pub use normalize_phases::normalize_phases;
pub(crate) use normalize_phases::{NormalizePhases, SubtractBlackNormalizePhases};
pub use smooth_flow::smooth_flow;
pub(crate) use smooth_flow::SmoothFlow;

/// `P⁺_i = A_i + B_i` of phase image `i` at pixel `(x, y)`, coordinates clamped.
fn plus(raw: &Image, i: usize, x: isize, y: isize) -> f32 {
    raw.at_clamped(2 * i, x, y) + raw.at_clamped(2 * i + 1, x, y)
}

/// How far `P⁺_i` around fractional `(x, y)` is from `p0`: the squared differences of the four
/// whole pixels around it, weighted as [`bilinear`] weighs them. Exactly `(p0 − P⁺_i(x, y))²` at
/// whole pixels; where the four differ (an edge), more than the squared difference of their
/// blend — so a fractional vector that would blend an object with its background never matches
/// better than the whole one that samples either. The WGSL twin sums in the same order.
fn blended_squared_difference(raw: &Image, i: usize, x: f32, y: f32, p0: f32) -> f32 {
    bilinear(x, y, |px, py| (p0 - plus(raw, i, px, py)).powi(2))
}

/// The value at fractional `(x, y)` bilinear between the four whole pixels around it, `at`
/// giving a whole pixel's value (clamping as it likes); exactly `at(x, y)` at whole pixels. The
/// WGSL twins blend in the same order.
fn bilinear(x: f32, y: f32, at: impl Fn(isize, isize) -> f32) -> f32 {
    let (x0, y0) = (x.floor(), y.floor());
    let (tx, ty) = (x - x0, y - y0);
    let (x0, y0) = (x0 as isize, y0 as isize);
    let top = (1.0 - tx) * at(x0, y0) + tx * at(x0 + 1, y0);
    let bottom = (1.0 - tx) * at(x0, y0 + 1) + tx * at(x0 + 1, y0 + 1);
    (1.0 - ty) * top + ty * bottom
}

/// Whether candidate `(dx, dy)` lies within `half_width` (radians) of direction `mean` (radians);
/// the zero vector always does.
pub fn allowed(dx: f32, dy: f32, restriction: Option<(f32, f32)>) -> bool {
    let Some((mean, half_width)) = restriction else { return true };
    if dx == 0.0 && dy == 0.0 {
        return true;
    }
    let angle = dy.atan2(dx);
    let mut diff = (angle - mean).abs() % (2.0 * PI);
    if diff > PI {
        diff = 2.0 * PI - diff;
    }
    diff <= half_width + 1e-6
}

/// The direction of `(dx, dy)` in [0, 2π).
pub fn angle_of(dx: f32, dy: f32) -> f32 {
    let a = dy.atan2(dx);
    if a < 0.0 {
        a + 2.0 * PI
    } else {
        a
    }
}

/// The mean direction (radians) of the non-zero flow vectors, as a circular mean; `None` when
/// there are none. The next frame's search is restricted around it.
pub fn mean_direction(flow: &Image) -> Option<f32> {
    let n = flow.pixels();
    let (mut s, mut c, mut count) = (0.0f64, 0.0f64, 0usize);
    for i in 0..n {
        let (u, v) = (flow.data[i], flow.data[n + i]);
        if u != 0.0 || v != 0.0 {
            let a = angle_of(u, v) as f64;
            s += a.sin();
            c += a.cos();
            count += 1;
        }
    }
    (count > 0).then(|| angle_of(c as f32, s as f32))
}

/// The share of candidate vectors the direction restriction leaves out, for `moving` masked
/// pixels (Tables 4.2, 4.3: "rejected directions").
pub fn rejected_share(window: u32, restriction: Option<(f32, f32)>) -> f32 {
    let r = (window as i32 - 1) / 2;
    let total = (window * window) as f32;
    let kept = (-r..=r)
        .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
        .filter(|&(dx, dy)| allowed(dx as f32, dy as f32, restriction))
        .count();
    1.0 - kept as f32 / total
}
