//! Projective point-to-plane ICP (sec. 6.5.3, eq. 6.2): each source point, moved by the current
//! pose, is projected into the model image and paired with the model point and normal there
//! (rejected beyond `max_distance` metres or when the normals differ by more than the angle
//! whose cosine is `min_cos`); each pair adds `a = [p × n, n]`, `b = n·(d − p)` to the 6×6 system
//! `Σ a aᵀ x = Σ a b`, reduced on the GPU; the host solves it (Cholesky) and updates the pose.
//! Also the rigid transform of a point cloud. One kernel a module, with its CPU reference.

use crate::camera::{pose_from, Pose};

pub mod icp_reduce;
pub mod transform_points;

pub use icp_reduce::reduce;
pub(crate) use icp_reduce::IcpReduce;
pub use transform_points::transform_points;
pub(crate) use transform_points::TransformPoints;

/// Values reduced per ICP step: the 21 entries of the upper triangle of `Σ a aᵀ` (row by row),
/// the 6 of `Σ a b`, the number of pairs and `Σ b²`.
pub const SUMS: usize = 29;

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
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
