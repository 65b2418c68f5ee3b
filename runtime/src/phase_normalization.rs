//! Phase normalization's calibration (sec. 4.2.2.1, after Lindner and Kolb [LK09]): from static
//! recordings of homogeneous walls at several distances and reflectivities, per pixel and tap
//! (A, B) the function `f(X) = a·√(X + b) + c·X + d` that maps the tap's value to what the
//! brightest pixel of the wall recorded, so that the normalised channels of every recording sum
//! to its reference (eq. 4.2). It evens out the pixels' gains and the light's fall-off towards
//! the border, which the block matching would otherwise take for motion. Stored as a `.npy`
//! array of shape (8, H, W): a, b, c, d of tap A, then of tap B; applied by
//! [`Kernel::NormalizePhases`](crate::Kernel::NormalizePhases).

use std::{fmt, path::Path};

use gudsl_formats::arrays::{self, ArrayError, Dtype};

use crate::{
    kernels::{filters::mean, tof::subtract_black},
    linalg::{least_squares, polyfit},
    sim::{simulate, Camera, Motion, Scene},
    Image,
};

/// The walls of the simulated sweep: distances in metres and reflectivities, spanning the
/// brightness of chapter 4's scenes (objects at about 3 m, the wall at 4 m).
pub const SWEEP_DISTANCES: [f32; 4] = [2.0, 3.0, 4.0, 5.0];
pub const SWEEP_REFLECTIVITIES: [f32; 3] = [0.2, 0.5, 0.9];
/// Frames averaged per wall of the simulated sweep (shot noise).
const FRAMES_PER_WALL: usize = 4;
/// The offsets `b` tried per pixel; the one of least residual is kept.
const OFFSETS: [f64; 4] = [0.0, 1_000.0, 10_000.0, 100_000.0];

/// The per-pixel coefficients (8 planes: a, b, c, d of tap A, then of tap B).
#[derive(Debug, Clone, PartialEq)]
pub struct PhaseCalibration {
    pub coefficients: Image,
}

#[derive(Debug)]
pub enum NormalizationError {
    /// Fewer than four recordings: the function has four coefficients.
    TooFewRecordings(usize),
    /// A recording is not a raw frame (8 planes) of the first one's size.
    Shapes {
        index: usize,
    },
    File(ArrayError),
    /// The file's array is not (8, H, W).
    FileShape(Vec<usize>),
}

impl fmt::Display for NormalizationError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            NormalizationError::TooFewRecordings(n) => {
                write!(f, "phase normalization needs at least 4 static recordings to fit 4 coefficients; {n} given")
            }
            NormalizationError::Shapes { index } => {
                write!(f, "recording {index} is not a raw frame (8 planes) of the first recording's size")
            }
            NormalizationError::File(e) => write!(f, "{e}"),
            NormalizationError::FileShape(shape) => write!(
                f,
                "a phase-normalization calibration is an array of shape (8, H, W) (a, b, c, d of taps A and B); \
                 this one has shape {shape:?}"
            ),
        }
    }
}

impl std::error::Error for NormalizationError {}

impl PhaseCalibration {
    /// The identity (a = b = d = 0, c = 1) for frames of `width × height`.
    pub fn identity(width: usize, height: usize) -> PhaseCalibration {
        let mut coefficients = Image::zeros(width, height, 8);
        for tap in 0..2 {
            coefficients.plane_mut(4 * tap + 2).fill(1.0);
        }
        PhaseCalibration { coefficients }
    }

    /// Fits the calibration on static recordings (black subtracted, 8 planes each) of
    /// homogeneous walls; see the module's documentation.
    pub fn fit(recordings: &[Image]) -> Result<PhaseCalibration, NormalizationError> {
        if recordings.len() < 4 {
            return Err(NormalizationError::TooFewRecordings(recordings.len()));
        }
        let (w, h) = (recordings[0].width, recordings[0].height);
        if let Some(index) = recordings.iter().position(|r| r.planes != 8 || r.width != w || r.height != h) {
            return Err(NormalizationError::Shapes { index });
        }
        let n = w * h;
        // Each recording's reference: its brightest channel sum, 5×5-averaged against noise.
        let references: Vec<f64> = recordings
            .iter()
            .map(|r| {
                let sums = Image::from_plane(w, h, (0..n).map(|i| (0..8).map(|p| r.data[p * n + i]).sum()).collect());
                mean(&sums, 2).data.iter().copied().fold(0.0f32, f32::max) as f64
            })
            .collect();
        let mut coefficients = Image::zeros(w, h, 8);
        for tap in 0..2 {
            for i in 0..n {
                let samples: Vec<(f64, f64)> = recordings
                    .iter()
                    .zip(&references)
                    .map(|(r, &reference)| {
                        let x = (0..4).map(|phase| r.data[(2 * phase + tap) * n + i] as f64).sum::<f64>() / 4.0;
                        (x, reference / 8.0)
                    })
                    .collect();
                for (k, value) in fit_pixel(&samples).into_iter().enumerate() {
                    coefficients.data[(4 * tap + k) * n + i] = value as f32;
                }
            }
        }
        Ok(PhaseCalibration { coefficients })
    }

    /// Fits the calibration on the simulated camera's walls ([`SWEEP_DISTANCES`] ×
    /// [`SWEEP_REFLECTIVITIES`], each the mean of a few frames), as one would record them.
    pub fn simulated(camera: &Camera) -> PhaseCalibration {
        let recordings: Vec<Image> = SWEEP_DISTANCES
            .iter()
            .flat_map(|&d| SWEEP_REFLECTIVITIES.iter().map(move |&r| (d, r)))
            .map(|(distance, reflectivity)| {
                let wall = Scene { wall_distance: distance, wall_reflectivity: reflectivity, ..Scene::empty() };
                let frames: Vec<Image> = (0..FRAMES_PER_WALL)
                    .map(|k| {
                        let frame = simulate(&wall, Motion::Still, camera, k);
                        subtract_black(&frame.raw, &frame.black)
                    })
                    .collect();
                let mut average = frames[0].clone();
                for (i, value) in average.data.iter_mut().enumerate() {
                    *value = frames.iter().map(|f| f.data[i]).sum::<f32>() / frames.len() as f32;
                }
                average
            })
            .collect();
        PhaseCalibration::fit(&recordings).expect("the sweep has twelve recordings of one size")
    }

    /// Writes the calibration as a float32 `.npy` array of shape (8, H, W).
    pub fn save(&self, path: &Path) -> Result<(), ArrayError> {
        let c = &self.coefficients;
        arrays::write(path, &[8, c.height, c.width], &c.data, Dtype::F32)
    }

    /// Reads a calibration [`PhaseCalibration::save`] wrote (any float or integer dtype), at
    /// `path` beneath `folder`.
    pub fn load(folder: &gudsl_files::Folder, path: &Path) -> Result<PhaseCalibration, NormalizationError> {
        let array = arrays::read(folder, path).map_err(NormalizationError::File)?;
        match array.shape[..] {
            [8, height, width] if width > 0 && height > 0 => {
                Ok(PhaseCalibration { coefficients: Image { width, height, planes: 8, data: array.values } })
            }
            _ => Err(NormalizationError::FileShape(array.shape)),
        }
    }
}

/// The least-squares `y = a·√(x + b) + c·x + d` through `samples`, `b` the best of [`OFFSETS`];
/// the straight line `c·x + d` where no curve fits (too little spread), the identity where not
/// even that does.
fn fit_pixel(samples: &[(f64, f64)]) -> [f64; 4] {
    let x_max = samples.iter().map(|s| s.0.abs()).fold(1.0, f64::max);
    let residual = |[a, b, c, d]: [f64; 4]| -> f64 {
        samples.iter().map(|&(x, y)| (a * (x + b).max(0.0).sqrt() + c * x + d - y).powi(2)).sum()
    };
    let line = polyfit::<2>(samples).map(|[c, d]| [0.0, 0.0, c, d]);
    let curves = OFFSETS.iter().filter_map(|&b| {
        // Basis functions scaled to about 1 for conditioning.
        let root_max = (x_max + b).sqrt();
        least_squares(samples.iter().map(|&(x, y)| ([(x + b).max(0.0).sqrt() / root_max, x / x_max, 1.0], y)))
            .map(|[a, c, d]| [a / root_max, b, c / x_max, d])
    });
    line.into_iter()
        .chain(curves)
        .filter(|f| f.iter().all(|v| v.is_finite()))
        .min_by(|f, g| residual(*f).total_cmp(&residual(*g)))
        .unwrap_or([0.0, 0.0, 1.0, 0.0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{camera::Intrinsics, kernels::motion::normalize_phases};

    /// A small camera with a 3 % gain spread: the pattern normalization exists to undo.
    fn camera() -> Camera {
        Camera { intrinsics: Intrinsics::camcube_at(40, 40), gain_spread: 0.03, ..Camera::default() }
    }

    fn sums(raw: &Image) -> Vec<f32> {
        let n = raw.pixels();
        (0..n).map(|i| (0..8).map(|p| raw.data[p * n + i]).sum()).collect()
    }

    /// Relative spread (σ / mean) of a wall's channel sums.
    fn spread(values: &[f32]) -> f32 {
        let mean = values.iter().sum::<f32>() / values.len() as f32;
        let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f32>() / values.len() as f32;
        variance.sqrt() / mean
    }

    #[test]
    fn a_wall_between_the_sweeps_walls_comes_out_even() {
        let camera = camera();
        let calibration = PhaseCalibration::simulated(&camera);
        // A wall the sweep did not record: 3.5 m, reflectivity 0.7, noise-free.
        let wall = Scene { wall_distance: 3.5, wall_reflectivity: 0.7, ..Scene::empty() };
        let frame = simulate(&wall, Motion::Still, &Camera { noise: false, ..camera }, 0);
        let raw = subtract_black(&frame.raw, &frame.black);
        let before = spread(&sums(&raw));
        let after = spread(&sums(&normalize_phases(&raw, &calibration.coefficients)));
        assert!(before > 0.03, "the raw wall is uneven (gains, fall-off): {before}");
        assert!(after < before / 5.0, "normalised it is even: {before} → {after}");
    }

    #[test]
    fn the_fit_recovers_a_known_curve_and_falls_back_to_a_line() {
        let curve = |x: f64| 3.0 * (x + 1000.0).sqrt() + 0.5 * x - 20.0;
        let samples: Vec<(f64, f64)> = [100.0, 900.0, 3000.0, 7000.0, 15000.0].iter().map(|&x| (x, curve(x))).collect();
        let [a, b, c, d] = fit_pixel(&samples);
        assert_eq!(b, 1000.0);
        assert!((a - 3.0).abs() < 1e-6 && (c - 0.5).abs() < 1e-9 && (d + 20.0).abs() < 1e-4, "{a} {c} {d}");
        // Four samples of one value: no curve, no line; the identity.
        assert_eq!(fit_pixel(&[(5.0, 7.0); 4]), [0.0, 0.0, 1.0, 0.0]);
    }

    #[test]
    fn a_calibration_survives_its_file_and_bad_files_are_refused() {
        let dir = std::env::temp_dir().join(format!("gudsl-phase-normalization-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("calibration.npy");
        let mut calibration = PhaseCalibration::identity(5, 3);
        calibration.coefficients.data[7] = 2.5;
        calibration.save(&path).unwrap();
        assert_eq!(PhaseCalibration::load(&gudsl_files::Folder::open(&dir).unwrap(), &path).unwrap(), calibration);
        arrays::write(&path, &[4, 3, 5], &[0.0; 60], Dtype::F32).unwrap();
        let error = PhaseCalibration::load(&gudsl_files::Folder::open(&dir).unwrap(), &path).unwrap_err().to_string();
        assert!(error.contains("shape (8, H, W)") && error.contains("[4, 3, 5]"), "{error}");
        assert!(PhaseCalibration::fit(&[]).unwrap_err().to_string().contains("at least 4"));
    }
}
