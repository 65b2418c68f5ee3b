//! CPU references of motion-artifact compensation (chapter 4): motion detection on the channel
//! sums, per-pixel block matching of the phase images along a constant-velocity path (SSD over
//! a motion window, optionally restricted to directions near the previous frame's mean), median
//! smoothing of the flow directions, and correction of the raw channels along the flow.

use std::f32::consts::PI;

use crate::Image;

/// `P⁺_i = A_i + B_i` of phase image `i` at pixel `(x, y)`, coordinates clamped.
fn plus(raw: &Image, i: usize, x: isize, y: isize) -> f32 {
    raw.at_clamped(2 * i, x, y) + raw.at_clamped(2 * i + 1, x, y)
}

/// Motion detection (eq. 4.4, 4.5): `M = Σ_{i=1..3} |P⁺_i − P⁺_0|` and the mask `M > θ` (1 or 0).
pub fn detect(raw: &Image, theta: f32) -> [Image; 2] {
    let (w, h) = (raw.width, raw.height);
    let mut m = Image::zeros(w, h, 1);
    for y in 0..h {
        for x in 0..w {
            let (x, y) = (x as isize, y as isize);
            let p0 = plus(raw, 0, x, y);
            m.data[y as usize * w + x as usize] = (1..4).map(|i| (plus(raw, i, x, y) - p0).abs()).sum();
        }
    }
    let mask = Image { data: m.data.iter().map(|&v| if v > theta { 1.0 } else { 0.0 }).collect(), ..m.clone() };
    [m, mask]
}

/// Whether candidate `(dx, dy)` lies within `half_width` (radians) of direction `mean` (radians);
/// the zero vector always does.
pub fn allowed(dx: i32, dy: i32, restriction: Option<(f32, f32)>) -> bool {
    let Some((mean, half_width)) = restriction else { return true };
    if dx == 0 && dy == 0 {
        return true;
    }
    let angle = (dy as f32).atan2(dx as f32);
    let mut diff = (angle - mean).abs() % (2.0 * PI);
    if diff > PI {
        diff = 2.0 * PI - diff;
    }
    diff <= half_width + 1e-6
}

/// Block matching (eq. 4.6–4.10): for each masked pixel the displacement per phase image
/// `(dx, dy)` within `±(window−1)/2` minimising `Σ_{i=1..3} (P⁺_0(x,y) − P⁺_i(x+i·dx, y+i·dy))²`
/// (ties: the shorter vector, then scan order); unmasked pixels get (0, 0). Two planes: dx, dy.
pub fn match_blocks(raw: &Image, mask: &Image, window: u32, restriction: Option<(f32, f32)>) -> Image {
    let (w, h) = (raw.width, raw.height);
    let r = (window as i32 - 1) / 2;
    let mut flow = Image::zeros(w, h, 2);
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            if mask.data[i] == 0.0 {
                continue;
            }
            let (xi, yi) = (x as isize, y as isize);
            let p0 = plus(raw, 0, xi, yi);
            let mut best = (f32::INFINITY, i32::MAX, 0, 0);
            for dy in -r..=r {
                for dx in -r..=r {
                    if !allowed(dx, dy, restriction) {
                        continue;
                    }
                    let ssd: f32 = (1..4)
                        .map(|k| {
                            let d = p0 - plus(raw, k, xi + (k as i32 * dx) as isize, yi + (k as i32 * dy) as isize);
                            d * d
                        })
                        .sum();
                    let length = dx * dx + dy * dy;
                    if ssd < best.0 || (ssd == best.0 && length < best.1) {
                        best = (ssd, length, dx, dy);
                    }
                }
            }
            flow.data[i] = best.2 as f32;
            flow.data[w * h + i] = best.3 as f32;
        }
    }
    flow
}

/// Flow smoothing ("NH", sec. 4.2.4): each non-zero vector takes the median direction of the
/// non-zero vectors in its `window × window` neighbourhood, keeps its length, and is rounded
/// to whole pixels.
pub fn smooth_flow(flow: &Image, window: u32) -> Image {
    let (w, h) = (flow.width, flow.height);
    let r = (window as isize - 1) / 2;
    let n = w * h;
    let mut out = flow.clone();
    for y in 0..h as isize {
        for x in 0..w as isize {
            let i = y as usize * w + x as usize;
            let (u, v) = (flow.data[i], flow.data[n + i]);
            if u == 0.0 && v == 0.0 {
                continue;
            }
            let mut angles: Vec<f32> = Vec::new();
            for dy in -r..=r {
                for dx in -r..=r {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                        continue;
                    }
                    let j = ny as usize * w + nx as usize;
                    let (a, b) = (flow.data[j], flow.data[n + j]);
                    if a != 0.0 || b != 0.0 {
                        angles.push(angle_of(a, b));
                    }
                }
            }
            angles.sort_by(f32::total_cmp);
            let median = angles[angles.len() / 2];
            let length = (u * u + v * v).sqrt();
            out.data[i] = (length * median.cos()).round();
            out.data[n + i] = (length * median.sin()).round();
        }
    }
    out
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

/// Raw phase correction (sec. 4.2.5): `A_i(x, y) ← A_i(x + i·u, y + i·v)` and the same for `B_i`,
/// with `(u, v)` the pixel's flow, coordinates clamped.
pub fn correct_raw(raw: &Image, flow: &Image) -> Image {
    let (w, h) = (raw.width, raw.height);
    let n = w * h;
    let mut out = raw.clone();
    for y in 0..h {
        for x in 0..w {
            let i = y * w + x;
            let (u, v) = (flow.data[i] as isize, flow.data[n + i] as isize);
            for k in 0..4 {
                let (sx, sy) = (x as isize + k as isize * u, y as isize + k as isize * v);
                for plane in [2 * k, 2 * k + 1] {
                    out.data[plane * n + i] = raw.at_clamped(plane, sx, sy);
                }
            }
        }
    }
    out
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
        .filter(|&(dx, dy)| allowed(dx, dy, restriction))
        .count();
    1.0 - kept as f32 / total
}
