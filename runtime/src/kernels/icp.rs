//! Projective point-to-plane ICP (sec. 6.5.3, eq. 6.2): each source point, moved by the current
//! pose, is projected into the model image and paired with the model point and normal there
//! (rejected beyond `max_distance` metres or when the normals differ by more than the angle
//! whose cosine is `min_cos`); each pair adds `a = [p × n, n]`, `b = n·(d − p)` to the 6×6 system
//! `Σ a aᵀ x = Σ a b`, reduced on the GPU; the host solves it (Cholesky) and updates the pose.
//! Also the rigid transform of a point cloud.

use crate::camera::{apply, pose_from, Intrinsics, Pose};
use crate::Image;

/// Values reduced per ICP step: the 21 entries of the upper triangle of `Σ a aᵀ` (row by row),
/// the 6 of `Σ a b`, the number of pairs and `Σ b²`.
pub const SUMS: usize = 29;

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The sums of one ICP step (see [`SUMS`]) over `[source, source normals, model, model normals]`,
/// accumulated in f64.
pub fn reduce(
    clouds: [&Image; 4],
    pose: &Pose,
    intrinsics: &Intrinsics,
    max_distance: f32,
    min_cos: f32,
) -> [f64; SUMS] {
    let mut sums = [0.0f64; SUMS];
    for i in 0..clouds[0].pixels() {
        if let Some((a, b)) = pair(clouds, pose, intrinsics, max_distance, min_cos, i) {
            let mut k = 0;
            for r in 0..6 {
                for c in r..6 {
                    sums[k] += (a[r] * a[c]) as f64;
                    k += 1;
                }
            }
            for r in 0..6 {
                sums[21 + r] += (a[r] * b) as f64;
            }
            sums[27] += 1.0;
            sums[28] += (b * b) as f64;
        }
    }
    sums
}

/// The linearised pair of source pixel `i`, if it has a model partner.
fn pair(
    [source, source_normals, model, model_normals]: [&Image; 4],
    pose: &Pose,
    intrinsics: &Intrinsics,
    max_distance: f32,
    min_cos: f32,
    i: usize,
) -> Option<([f32; 6], f32)> {
    let (s, sn) = (source.vector(i), source_normals.vector(i));
    if s[2] == 0.0 || sn == [0.0; 3] {
        return None;
    }
    let p = apply(pose, s, true);
    let np = apply(pose, sn, false);
    let (u, v) = intrinsics.project(p)?;
    let (u, v) = ((u + 0.5).floor(), (v + 0.5).floor());
    if u < 0.0 || v < 0.0 || u >= model.width as f32 || v >= model.height as f32 {
        return None;
    }
    let j = v as usize * model.width + u as usize;
    let (d, n) = (model.vector(j), model_normals.vector(j));
    if d[2] == 0.0 || n == [0.0; 3] {
        return None;
    }
    let diff = [d[0] - p[0], d[1] - p[1], d[2] - p[2]];
    if dot(diff, diff) > max_distance * max_distance || dot(np, n) < min_cos {
        return None;
    }
    let pn = cross(p, n);
    Some(([pn[0], pn[1], pn[2], n[0], n[1], n[2]], dot(n, diff)))
}

/// Solves the step's 6×6 system (Cholesky) for `(α, β, γ, tx, ty, tz)`; `None` when it is
/// singular (too few or degenerate pairs).
pub fn solve(sums: &[f64; SUMS]) -> Option<[f64; 6]> {
    // Entry (r, c), r ≤ c, of the upper triangle: after the 6 + 5 + … entries of the rows above.
    let upper = |r: usize, c: usize| sums[6 * r - r * r.saturating_sub(1) / 2 + c - r];
    let a: [[f64; 6]; 6] = std::array::from_fn(|r| std::array::from_fn(|c| upper(r.min(c), r.max(c))));
    crate::linalg::cholesky_solve(&a, &std::array::from_fn(|r| sums[21 + r]))
}

/// `increment · pose`, the increment `(α, β, γ, tx, ty, tz)` as in [`pose_from`].
pub fn compose(x: &[f64; 6], pose: &Pose) -> Pose {
    crate::camera::compose(&pose_from([x[0], x[1], x[2]], [x[3], x[4], x[5]]), pose)
}

/// Moves every valid point (not at the origin) by `pose`.
pub fn transform_points(points: &Image, pose: &Pose) -> Image {
    let n = points.pixels();
    let mut out = Image::zeros(points.width, points.height, 3);
    for i in 0..n {
        let p = points.vector(i);
        if p[2] == 0.0 {
            continue;
        }
        for (k, value) in apply(pose, p, true).into_iter().enumerate() {
            out.data[k * n + i] = value;
        }
    }
    out
}
