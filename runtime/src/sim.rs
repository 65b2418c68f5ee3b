//! A simulated PMD camera with ground truth, after the evaluation setup of chapter 4: a planar
//! wall at 4 m and an object at about 3 m (sphere, box, a relief or a bunny), seen by a
//! 200×200 sensor with the intrinsics and distortion of Table 2.1 at 20 MHz. The four phase
//! images are taken one after another, the camera moving (1 cm) or turning (1°) between them;
//! each pixel integrates 3×3 sub-rays, so depth edges give flying pixels. A and B channels carry
//! `S/2·(1 ± m·cos(φ + i·π/2))` with `S` falling with distance and rising with reflectivity and
//! integration time, plus ambient light, times a per-tap gain (pixel response non-uniformity, off
//! by default), a fixed-pattern offset (the black image), shot noise, a response that bends above
//! a knee and saturation at 65535.

use std::f32::consts::PI;

pub use crate::camera::Intrinsics;
use crate::camera::{apply, compose, pose_from, Pose, IDENTITY};
use crate::kernels::tof::SPEED_OF_LIGHT;
use crate::Image;

/// The object in front of the wall.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Object {
    Sphere {
        centre: [f32; 3],
        radius: f32,
    },
    /// An axis-aligned box.
    Cuboid {
        min: [f32; 3],
        max: [f32; 3],
    },
    /// A box of half-extents `half` around `centre`, turned by `rotation` (its axes as the
    /// columns of a camera-frame rotation): three faces in view, so it fixes all six degrees of
    /// freedom of a registration (the car of chapter 6, roughly).
    TurnedBox {
        centre: [f32; 3],
        half: [f32; 3],
        rotation: Pose,
    },
    /// Plates facing the camera at `distance` (chapter 5: eight metal plates at about 1 m), two
    /// rows of four, each `size` wide and twice as high, filling the view; reflectivities left to
    /// right, top row first.
    Plates {
        distance: f32,
        size: f32,
        reflectivities: [f32; 8],
    },
    /// A relief facing the camera: `z = base − height(x, y)` over a square of side `size`
    /// around `centre` (x, y), with fine ridges (a stand-in for the scanned figures of chapter 4).
    HeightField {
        centre: [f32; 2],
        base: f32,
        size: f32,
    },
    /// A bunny of ellipsoids around `centre` (body, head, two thin ears, tail, paw), about
    /// 0.5 m wide and 0.7 m tall: thin structures and a detailed silhouette, a stand-in for the
    /// scanned buddha and dragon of chapter 4.
    Bunny {
        centre: [f32; 3],
    },
}

/// The bunny's ellipsoids relative to its centre: (centre, semi-axes) in metres, y downwards.
const BUNNY: [([f32; 3], [f32; 3]); 6] = [
    ([0.0, 0.08, 0.0], [0.22, 0.18, 0.18]),
    ([0.12, -0.15, -0.05], [0.11, 0.10, 0.10]),
    ([0.08, -0.33, -0.05], [0.03, 0.12, 0.025]),
    ([0.17, -0.32, -0.02], [0.028, 0.12, 0.025]),
    ([-0.22, 0.05, 0.0], [0.05, 0.05, 0.05]),
    ([0.15, 0.25, -0.1], [0.06, 0.03, 0.05]),
];

/// A wall at `wall_distance` (plane z = const) and an object, with their reflectivities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scene {
    pub wall_distance: f32,
    pub wall_reflectivity: f32,
    pub object: Option<Object>,
    pub object_reflectivity: f32,
}

impl Scene {
    /// The chapter 4 setup: wall at 4 m, the object at about 3 m.
    pub fn wall_and(object: Object) -> Scene {
        Scene { wall_distance: 4.0, wall_reflectivity: 0.8, object: Some(object), object_reflectivity: 0.6 }
    }

    pub fn sphere() -> Scene {
        Scene::wall_and(Object::Sphere { centre: [0.0, 0.0, 3.0], radius: 0.45 })
    }

    pub fn cuboid() -> Scene {
        Scene::wall_and(Object::Cuboid { min: [-0.4, -0.3, 2.8], max: [0.3, 0.4, 3.3] })
    }

    pub fn height_field() -> Scene {
        Scene::wall_and(Object::HeightField { centre: [0.0, 0.0], base: 3.1, size: 1.0 })
    }

    pub fn bunny() -> Scene {
        Scene::wall_and(Object::Bunny { centre: [0.0, 0.05, 3.0] })
    }

    /// A box turned 35° about the vertical and 20° about the horizontal axis at about 3 m.
    pub fn turned_box() -> Scene {
        let rotation = crate::camera::pose_from([20f64.to_radians(), 35f64.to_radians(), 0.0], [0.0; 3]);
        Scene::wall_and(Object::TurnedBox { centre: [0.1, 0.05, 3.0], half: [0.45, 0.25, 0.3], rotation })
    }

    /// Chapter 5's static scene: black, metallic, blue, green, red, silver, yellow and white
    /// plates at 1 m.
    pub fn plates() -> Scene {
        let reflectivities = [0.05, 0.45, 0.2, 0.3, 0.35, 0.6, 0.75, 0.9];
        Scene::wall_and(Object::Plates { distance: 1.0, size: 0.3, reflectivities })
    }

    /// The wall alone (the empty scene of the background model).
    pub fn empty() -> Scene {
        Scene { object: None, ..Scene::sphere() }
    }

    /// The nearest hit of the ray from `origin` along unit `dir`: distance, reflectivity and the
    /// cosine of the incidence angle.
    fn hit(&self, origin: [f32; 3], dir: [f32; 3]) -> Option<(f32, f32, f32)> {
        let mut best: Option<(f32, f32, f32)> = None;
        let mut consider = |t: f32, reflectivity: f32, cos: f32| {
            if t > 1e-4 && best.is_none_or(|b| t < b.0) {
                best = Some((t, reflectivity, cos.abs().max(0.05)));
            }
        };
        if dir[2] > 1e-6 {
            consider((self.wall_distance - origin[2]) / dir[2], self.wall_reflectivity, dir[2]);
        }
        if let Some(object) = self.object {
            if let Some((t, normal)) = intersect(object, origin, dir) {
                let reflectivity = match object {
                    Object::Plates { size, reflectivities, .. } => {
                        let p = along(origin, dir, t);
                        let column = ((p[0] / size + 2.0).max(0.0) as usize).min(3);
                        reflectivities[column + if p[1] < 0.0 { 0 } else { 4 }]
                    }
                    _ => self.object_reflectivity,
                };
                consider(t, reflectivity, dot(normal, dir));
            }
        }
        best
    }
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn along(origin: [f32; 3], dir: [f32; 3], t: f32) -> [f32; 3] {
    [origin[0] + t * dir[0], origin[1] + t * dir[1], origin[2] + t * dir[2]]
}

/// Relief height of the height field at `(x, y)` relative to its centre: a dome with ridges.
fn relief(x: f32, y: f32, size: f32) -> f32 {
    let (u, v) = (x / size, y / size);
    let dome = 0.25 * (1.0 - 4.0 * (u * u + v * v)).max(0.0);
    dome + 0.02 * (40.0 * u).sin() * (30.0 * v).cos()
}

/// Distance along the ray and surface normal of the first hit on `object`.
fn intersect(object: Object, o: [f32; 3], d: [f32; 3]) -> Option<(f32, [f32; 3])> {
    match object {
        Object::Sphere { centre, radius } => intersect_ellipsoid(centre, [radius; 3], o, d),
        Object::Bunny { centre } => BUNNY
            .iter()
            .filter_map(|&(offset, semi)| {
                let c = [centre[0] + offset[0], centre[1] + offset[1], centre[2] + offset[2]];
                intersect_ellipsoid(c, semi, o, d)
            })
            .min_by(|a, b| a.0.total_cmp(&b.0)),
        Object::Cuboid { min, max } => {
            let (mut near, mut far, mut axis) = (f32::NEG_INFINITY, f32::INFINITY, 0);
            for k in 0..3 {
                if d[k].abs() < 1e-9 {
                    if o[k] < min[k] || o[k] > max[k] {
                        return None;
                    }
                    continue;
                }
                let (a, b) = ((min[k] - o[k]) / d[k], (max[k] - o[k]) / d[k]);
                let (a, b) = (a.min(b), a.max(b));
                if a > near {
                    near = a;
                    axis = k;
                }
                far = far.min(b);
            }
            if near > far || near <= 0.0 {
                return None;
            }
            let mut n = [0.0; 3];
            n[axis] = -d[axis].signum();
            Some((near, n))
        }
        Object::TurnedBox { centre, half, rotation } => {
            // Into the box's frame (rotation transposed), intersect there, the normal back out.
            let local = |v: [f32; 3]| apply(&crate::camera::invert(&rotation), v, false);
            let o = local([o[0] - centre[0], o[1] - centre[1], o[2] - centre[2]]);
            let (min, max) = ([-half[0], -half[1], -half[2]], half);
            let (t, n) = intersect(Object::Cuboid { min, max }, o, local(d))?;
            Some((t, apply(&rotation, n, false)))
        }
        Object::Plates { distance, size, .. } => {
            let t = (distance - o[2]) / d[2];
            let p = along(o, d, t);
            let inside = p[0].abs() <= 2.0 * size && p[1].abs() <= 2.0 * size;
            (d[2] > 1e-6 && t > 0.0 && inside).then_some((t, [0.0, 0.0, -1.0]))
        }
        Object::HeightField { centre, base, size } => {
            // March through the slab the relief occupies, then bisect the crossing.
            let half = size / 2.0;
            let inside = |p: [f32; 3]| (p[0] - centre[0]).abs() <= half && (p[1] - centre[1]).abs() <= half;
            let below = |p: [f32; 3]| p[2] >= base - relief(p[0] - centre[0], p[1] - centre[1], size);
            if d[2] <= 1e-6 {
                return None;
            }
            let (t0, t1) = ((base - 0.3 - o[2]) / d[2], (base - o[2]) / d[2]);
            let steps = 200;
            let mut previous = t0;
            for s in 1..=steps {
                let t = t0 + (t1 - t0) * s as f32 / steps as f32;
                let p = along(o, d, t);
                if inside(p) && below(p) {
                    let (mut lo, mut hi) = (previous, t);
                    for _ in 0..20 {
                        let mid = 0.5 * (lo + hi);
                        if below(along(o, d, mid)) {
                            hi = mid;
                        } else {
                            lo = mid;
                        }
                    }
                    let p = along(o, d, hi);
                    let e = 1e-3;
                    let (x, y) = (p[0] - centre[0], p[1] - centre[1]);
                    let gx = (relief(x + e, y, size) - relief(x - e, y, size)) / (2.0 * e);
                    let gy = (relief(x, y + e, size) - relief(x, y - e, size)) / (2.0 * e);
                    let len = (gx * gx + gy * gy + 1.0).sqrt();
                    return Some((hi, [gx / len, gy / len, -1.0 / len]));
                }
                previous = t;
            }
            None
        }
    }
}

/// Distance along the ray and surface normal of the first hit on the axis-aligned ellipsoid
/// around `c` with semi-axes `semi`: a unit sphere after scaling by `1/semi`.
fn intersect_ellipsoid(c: [f32; 3], semi: [f32; 3], o: [f32; 3], d: [f32; 3]) -> Option<(f32, [f32; 3])> {
    let scaled = |v: [f32; 3]| [v[0] / semi[0], v[1] / semi[1], v[2] / semi[2]];
    let (o_s, d_s) = (scaled([o[0] - c[0], o[1] - c[1], o[2] - c[2]]), scaled(d));
    let (a, b, cc) = (dot(d_s, d_s), dot(o_s, d_s), dot(o_s, o_s) - 1.0);
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return None;
    }
    let t = (-b - disc.sqrt()) / a;
    let p = along(o_s, d_s, t);
    let n = [p[0] / semi[0], p[1] / semi[1], p[2] / semi[2]];
    let length = dot(n, n).sqrt();
    (t > 0.0).then_some((t, [n[0] / length, n[1] / length, n[2] / length]))
}

/// How the camera moves between two phase images.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Motion {
    Still,
    /// Translation in metres per phase image (chapter 4: 1 cm lateral).
    Translation([f32; 3]),
    /// Rotation about the line of sight in degrees per phase image (chapter 4: 1°).
    Rotation(f32),
}

/// Acquisition settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub intrinsics: Intrinsics,
    pub modulation_hz: f32,
    /// Integration time per phase image in microseconds.
    pub integration_us: f32,
    /// Signal per channel sum for reflectivity 1 at 1 m and 1 µs.
    pub gain: f32,
    /// Demodulation contrast m.
    pub contrast: f32,
    /// Ambient light per channel per µs.
    pub ambient: f32,
    /// Shot noise on or off.
    pub noise: bool,
    /// Pixel response non-uniformity: each pixel's A and B taps have their own gain, spread
    /// with this relative σ around 1 (a fixed pattern, like the black image); 0 for none.
    pub gain_spread: f32,
    /// Sub-rays per pixel side (3: 3×3).
    pub supersampling: usize,
    pub seed: u64,
    /// Channel charge above which the pixel's response compresses (it clips at 65535): the
    /// non-linearity that chapter 5's intensity correction h undoes.
    pub knee: f32,
    /// Where the camera stands: camera → world (the wall's frame); the motion is relative to it.
    pub pose: Pose,
}

impl Default for Camera {
    fn default() -> Camera {
        Camera {
            intrinsics: Intrinsics::CAMCUBE,
            modulation_hz: 20.0e6,
            integration_us: 1000.0,
            gain: 60.0,
            contrast: 0.6,
            ambient: 0.05,
            noise: true,
            gain_spread: 0.0,
            supersampling: 3,
            seed: 1,
            knee: 40_000.0,
            pose: IDENTITY,
        }
    }
}

/// One simulated frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Raw channels `A0 B0 A1 B1 A2 B2 A3 B3`, whole numbers in 0..=65535.
    pub raw: Image,
    /// The chip's black image (fixed-pattern offset per channel), as the camera would record it.
    pub black: Image,
    /// Ground truth: radial distance in metres per pixel at the first phase image's pose
    /// (centre ray; NaN where the ray hits nothing).
    pub truth: Image,
}

/// A small deterministic generator (xorshift64*) with Gaussian samples.
struct Random(u64);

impl Random {
    fn uniform(&mut self) -> f32 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 40) as f32 + 0.5) / (1u64 << 24) as f32
    }

    fn gaussian(&mut self) -> f32 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * PI * v).cos()
    }
}

/// The camera pose (origin, rotation about z in radians) at phase step `step` (4 per frame).
fn pose(motion: Motion, step: usize) -> ([f32; 3], f32) {
    let s = step as f32;
    match motion {
        Motion::Still => ([0.0; 3], 0.0),
        Motion::Translation(v) => ([v[0] * s, v[1] * s, v[2] * s], 0.0),
        Motion::Rotation(degrees) => ([0.0; 3], (degrees * s).to_radians()),
    }
}

/// The camera standing still where `motion` has taken it at phase step `step`: its frames show
/// the view a motion compensation of that step's frame reconstructs (the static reference of
/// chapter 4's Table 4.1, seen from the same place).
pub fn standing_at(camera: &Camera, motion: Motion, step: usize) -> Camera {
    let (origin, angle) = pose(motion, step);
    let moved = pose_from([0.0, 0.0, angle as f64], origin.map(f64::from));
    Camera { pose: compose(&camera.pose, &moved), ..*camera }
}

/// The world ray (origin, direction) of camera-frame ray `dir` at a phase step's pose.
fn world_ray(camera: &Camera, (origin, angle): ([f32; 3], f32), dir: [f32; 3]) -> ([f32; 3], [f32; 3]) {
    (apply(&camera.pose, origin, true), apply(&camera.pose, rotate_z(dir, angle), false))
}

fn rotate_z([x, y, z]: [f32; 3], angle: f32) -> [f32; 3] {
    let (s, c) = angle.sin_cos();
    [c * x - s * y, s * x + c * y, z]
}

/// The charge a pixel reports for `charge` collected: linear up to `knee`, then bending towards
/// 1.2 × 65535 (it clips at 65535 once the charge is about 1.8 × (65535 − knee) past the knee).
fn response(charge: f32, knee: f32) -> f32 {
    if charge <= knee {
        return charge;
    }
    let headroom = 1.2 * 65535.0 - knee;
    knee + headroom * ((charge - knee) / headroom).tanh()
}

/// The scene's visible surface at frame `index`'s first phase image (the pose its ground truth
/// is at) as a dense cloud in that camera's frame: `per_side × per_side` hits per pixel, over
/// the image and `margin` pixels around it. The model a cloud-to-model distance is measured
/// against (CloudCompare measures against the mesh; this samples it finer than the pixels).
pub fn surface_points(
    scene: &Scene,
    motion: Motion,
    camera: &Camera,
    index: usize,
    per_side: usize,
    margin: usize,
) -> Vec<[f32; 3]> {
    let k = camera.intrinsics;
    let first = pose(motion, 4 * index);
    let side = |pixels: usize| (pixels + 2 * margin) * per_side;
    let (columns, rows) = (side(k.width), side(k.height));
    let mut points = Vec::with_capacity(columns * rows);
    for row in 0..rows {
        for column in 0..columns {
            let at = |j: usize| (j as f32 + 0.5) / per_side as f32 - 0.5 - margin as f32;
            let dir = k.ray(at(column), at(row));
            let (origin, world_dir) = world_ray(camera, first, dir);
            if let Some((t, _, _)) = scene.hit(origin, world_dir) {
                points.push([t * dir[0], t * dir[1], t * dir[2]]);
            }
        }
    }
    points
}

/// Simulates frame number `index` of a sequence (its phase images are steps `4·index … 4·index+3`).
pub fn simulate(scene: &Scene, motion: Motion, camera: &Camera, index: usize) -> Frame {
    simulate_unless(scene, motion, camera, index, &|| false).expect("never stopped")
}

/// [`simulate`], giving up (`None`) as soon as `stopped` says so — asked once a row, so a run
/// cancelled in a large frame stops within a row's work. Memory: 84 bytes a pixel, whatever
/// the supersampling (sub-pixel rays are made as they are cast).
pub fn simulate_unless(
    scene: &Scene,
    motion: Motion,
    camera: &Camera,
    index: usize,
    stopped: &dyn Fn() -> bool,
) -> Option<Frame> {
    let k = camera.intrinsics;
    let (w, h) = (k.width, k.height);
    let n = w * h;
    let mut raw = Image::zeros(w, h, 8);
    let mut black = Image::zeros(w, h, 8);
    let mut truth = Image::zeros(w, h, 1);
    let mut random = Random(camera.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ (index as u64 + 1));
    // The fixed pattern does not change between frames: its own generator.
    let mut pattern = Random(0x005e_ed0f_b1ac);
    for value in black.data.iter_mut() {
        *value = (60.0 + 15.0 * pattern.gaussian()).round().max(0.0);
    }
    // The taps' gains: a fixed pattern of its own (planes A, B), drawn even when unused so
    // that one does not change the other.
    let mut gains = Random(0x0009_a145_eed5);
    let tap_gain: Vec<f32> = (0..2 * n).map(|_| 1.0 + camera.gain_spread * gains.gaussian()).collect();
    let wavelength_phase = 4.0 * PI * camera.modulation_hz / SPEED_OF_LIGHT;
    let ss = camera.supersampling.max(1);
    let sub_ray = |pixel: usize, sub: usize| {
        let u = (pixel % w) as f32 + ((sub % ss) as f32 + 0.5) / ss as f32 - 0.5;
        let v = (pixel / w) as f32 + ((sub / ss) as f32 + 0.5) / ss as f32 - 0.5;
        k.ray(u, v)
    };
    let first = pose(motion, 4 * index);
    for pixel in 0..n {
        let (origin, dir) = world_ray(camera, first, k.ray((pixel % w) as f32, (pixel / w) as f32));
        truth.data[pixel] = scene.hit(origin, dir).map_or(f32::NAN, |(t, _, _)| t);
    }
    for phase in 0..4 {
        let step = pose(motion, 4 * index + phase);
        let offset = phase as f32 * PI / 2.0;
        for pixel in 0..n {
            if pixel % w == 0 && stopped() {
                return None;
            }
            let (mut sum, mut modulated) = (0.0f32, 0.0f32);
            for sub in 0..ss * ss {
                let (origin, dir) = world_ray(camera, step, sub_ray(pixel, sub));
                if let Some((t, reflectivity, cos)) = scene.hit(origin, dir) {
                    let signal = camera.gain * camera.integration_us * reflectivity * cos / (t * t);
                    sum += signal;
                    modulated += signal * (wavelength_phase * t + offset).cos();
                }
            }
            let (sum, modulated) = (sum / (ss * ss) as f32, modulated / (ss * ss) as f32);
            let ambient = camera.ambient * camera.integration_us;
            for (channel, sign) in [(0, 1.0), (1, -1.0)] {
                let plane = 2 * phase + channel;
                let clean =
                    tap_gain[channel * n + pixel] * (0.5 * (sum + sign * camera.contrast * modulated) + ambient);
                let noisy = if camera.noise { clean + clean.max(0.0).sqrt() * random.gaussian() } else { clean };
                let value = (response(noisy, camera.knee) + black.data[plane * n + pixel]).round().clamp(0.0, 65535.0);
                raw.data[plane * n + pixel] = value;
            }
        }
    }
    Some(Frame { raw, black, truth })
}
