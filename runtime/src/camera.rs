//! The camera model: pinhole intrinsics with Brown–Conrady lens distortion (Table 2.1), the
//! per-pixel viewing rays, the projection of points back into the image, and rigid poses.

use crate::Image;

/// Pinhole intrinsics with Brown–Conrady distortion (k1, k2 radial; p1, p2 tangential).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Intrinsics {
    pub width: usize,
    pub height: usize,
    pub fx: f32,
    pub fy: f32,
    pub cx: f32,
    pub cy: f32,
    pub k1: f32,
    pub k2: f32,
    pub p1: f32,
    pub p2: f32,
}

impl Intrinsics {
    /// Table 2.1's camera at another resolution: the same field of view and distortion.
    pub fn camcube_at(width: usize, height: usize) -> Intrinsics {
        let base = Intrinsics::CAMCUBE;
        let (sx, sy) = (width as f32 / base.width as f32, height as f32 / base.height as f32);
        Intrinsics {
            width,
            height,
            fx: base.fx * sx,
            fy: base.fy * sy,
            cx: (base.cx + 0.5) * sx - 0.5,
            cy: (base.cy + 0.5) * sy - 0.5,
            ..base
        }
    }

    /// Table 2.1: the PMD CamCube 3.0 of the dissertation.
    pub const CAMCUBE: Intrinsics = Intrinsics {
        width: 200,
        height: 200,
        fx: 176.14,
        fy: 176.70,
        cx: 103.83,
        cy: 99.06,
        k1: -0.295140,
        k2: 1.191152,
        p1: 0.004619,
        p2: -0.001630,
    };

    /// The image point of camera-frame point `p` (distortion applied), or `None` behind the
    /// camera.
    pub fn project(&self, p: [f32; 3]) -> Option<(f32, f32)> {
        if p[2] <= 0.0 {
            return None;
        }
        let (x, y) = (p[0] / p[2], p[1] / p[2]);
        let (xd, yd) = self.distort(x, y);
        Some((self.fx * xd + self.cx, self.fy * yd + self.cy))
    }

    /// Normalised coordinates with the lens distortion applied.
    pub fn distort(&self, x: f32, y: f32) -> (f32, f32) {
        let r2 = x * x + y * y;
        let radial = 1.0 + self.k1 * r2 + self.k2 * r2 * r2;
        let dx = 2.0 * self.p1 * x * y + self.p2 * (r2 + 2.0 * x * x);
        let dy = self.p1 * (r2 + 2.0 * y * y) + 2.0 * self.p2 * x * y;
        (x * radial + dx, y * radial + dy)
    }

    /// The unit ray through every pixel centre: 3 planes (x, y, z), for the point cloud.
    pub fn rays(&self) -> Image {
        let n = self.width * self.height;
        let mut rays = Image::zeros(self.width, self.height, 3);
        for i in 0..n {
            let ray = self.ray((i % self.width) as f32, (i / self.width) as f32);
            for (k, value) in ray.into_iter().enumerate() {
                rays.data[k * n + i] = value;
            }
        }
        rays
    }

    /// The unit ray (camera frame: x right, y down, z forward) through image point `(u, v)`,
    /// undistorting the normalised coordinates by fixed-point iteration.
    pub fn ray(&self, u: f32, v: f32) -> [f32; 3] {
        let (xd, yd) = ((u - self.cx) / self.fx, (v - self.cy) / self.fy);
        let (mut x, mut y) = (xd, yd);
        for _ in 0..10 {
            let r2 = x * x + y * y;
            let radial = 1.0 + self.k1 * r2 + self.k2 * r2 * r2;
            let dx = 2.0 * self.p1 * x * y + self.p2 * (r2 + 2.0 * x * x);
            let dy = self.p1 * (r2 + 2.0 * y * y) + 2.0 * self.p2 * x * y;
            x = (xd - dx) / radial;
            y = (yd - dy) / radial;
        }
        let n = (x * x + y * y + 1.0).sqrt();
        [x / n, y / n, 1.0 / n]
    }
}

/// A rigid pose as the first three rows of a 4×4 matrix `[R | t]`, row-major (the layout the
/// kernels take as three `vec4`s).
pub type Pose = [f32; 12];

pub const IDENTITY: Pose = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// `pose · p` (with `translate` false: the rotation only).
pub fn apply(pose: &Pose, p: [f32; 3], translate: bool) -> [f32; 3] {
    let t = if translate { 1.0 } else { 0.0 };
    std::array::from_fn(|r| pose[4 * r] * p[0] + pose[4 * r + 1] * p[1] + pose[4 * r + 2] * p[2] + t * pose[4 * r + 3])
}

/// The pose `T(t) · Rz(γ) Ry(β) Rx(α)` of `(α, β, γ)` radians and translation `t` metres.
pub fn pose_from(angles: [f64; 3], translation: [f64; 3]) -> Pose {
    let (sa, ca) = angles[0].sin_cos();
    let (sb, cb) = angles[1].sin_cos();
    let (sg, cg) = angles[2].sin_cos();
    let r = [
        [cg * cb, cg * sb * sa - sg * ca, cg * sb * ca + sg * sa],
        [sg * cb, sg * sb * sa + cg * ca, sg * sb * ca - cg * sa],
        [-sb, cb * sa, cb * ca],
    ];
    std::array::from_fn(|k| if k % 4 == 3 { translation[k / 4] as f32 } else { r[k / 4][k % 4] as f32 })
}

/// `a · b`: first `b`, then `a`.
pub fn compose(a: &Pose, b: &Pose) -> Pose {
    std::array::from_fn(|k| {
        let (row, col) = (k / 4, k % 4);
        let mut v: f64 = (0..3).map(|m| a[4 * row + m] as f64 * b[4 * m + col] as f64).sum();
        if col == 3 {
            v += a[4 * row + 3] as f64;
        }
        v as f32
    })
}

/// The inverse rigid transform `[Rᵀ | −Rᵀ t]`.
pub fn invert(pose: &Pose) -> Pose {
    std::array::from_fn(|k| {
        let (row, col) = (k / 4, k % 4);
        if col == 3 {
            -(0..3).map(|m| pose[4 * m + row] * pose[4 * m + 3]).sum::<f32>()
        } else {
            pose[4 * col + row]
        }
    })
}

/// How far apart two poses are: the rotation angle of `a⁻¹ b` in degrees and the distance of
/// their translations in metres.
pub fn pose_difference(a: &Pose, b: &Pose) -> (f32, f32) {
    let d = compose(&invert(a), b);
    let cos = ((d[0] + d[5] + d[10] - 1.0) / 2.0).clamp(-1.0, 1.0);
    let t = [a[3] - b[3], a[7] - b[7], a[11] - b[11]];
    (cos.acos().to_degrees(), (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt())
}
