//! How far a measured depth image is from the truth, on the foreground the camera measured
//! (nearer than 3.85 m, the dissertation's clamping distance): per pixel, the radial error
//! |D − truth| of the pixel's centre ray; as a cloud, the cloud-to-model distance of each
//! back-projected point to the nearest point of the true surface, as CloudCompare measures
//! Tables 4.1–4.3 (the surface sampled 4×4 per pixel: at 3 m about 3 mm apart, so a distance is
//! at most about 1 mm too long).

use gudsl_runtime::sim::{surface_points, Camera, Motion, Scene};
use gudsl_runtime::Image;
use kiddo::{ImmutableKdTree, SquaredEuclidean};

/// Measured depths beyond this are the wall, left out (sec. 4.3.1).
pub const CLAMP_M: f32 = 3.85;

/// Mean and σ of a set of errors, in cm.
#[derive(Debug, Clone, Copy, Default)]
pub struct Stats {
    pub mean: f64,
    pub sigma: f64,
}

impl Stats {
    fn of(errors_m: impl Iterator<Item = f32>) -> Stats {
        let cm: Vec<f64> = errors_m.map(|e| e as f64 * 100.0).collect();
        let n = cm.len().max(1) as f64;
        let mean = cm.iter().sum::<f64>() / n;
        let sigma = (cm.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n).sqrt();
        Stats { mean, sigma }
    }

    /// The mean of several frames' statistics.
    pub fn average(all: &[Stats]) -> Stats {
        let n = all.len().max(1) as f64;
        Stats { mean: all.iter().map(|s| s.mean).sum::<f64>() / n, sigma: all.iter().map(|s| s.sigma).sum::<f64>() / n }
    }
}

/// Both errors of one depth image.
#[derive(Debug, Clone, Copy, Default)]
pub struct Score {
    pub radial: Stats,
    pub c2m: Stats,
}

impl Score {
    pub fn average(all: &[Score]) -> Score {
        let pick = |f: fn(&Score) -> Stats| Stats::average(&all.iter().map(f).collect::<Vec<_>>());
        Score { radial: pick(|s| s.radial), c2m: pick(|s| s.c2m) }
    }
}

/// The truth of one frame: its radial distances and its surface.
pub struct Truth {
    pub distance: Image,
    surface: ImmutableKdTree<f32, 3>,
    rays: Image,
}

impl Truth {
    pub fn new(scene: &Scene, motion: Motion, camera: &Camera, index: usize, distance: Image) -> Truth {
        let points = surface_points(scene, motion, camera, index, 4, 4);
        Truth { distance, surface: ImmutableKdTree::new_from_slice(&points), rays: camera.intrinsics.rays() }
    }

    /// The errors of `measured` (radial distance in metres) over its pixels nearer than
    /// [`CLAMP_M`].
    pub fn score(&self, measured: &Image) -> Score {
        let n = measured.pixels();
        let foreground = || (0..n).filter(|&i| measured.data[i] > 0.0 && measured.data[i] < CLAMP_M);
        let radial = Stats::of(
            foreground()
                .filter(|&i| self.distance.data[i].is_finite())
                .map(|i| (measured.data[i] - self.distance.data[i]).abs()),
        );
        let c2m = Stats::of(foreground().map(|i| {
            let ray = self.rays.vector(i);
            let d = measured.data[i];
            self.surface.nearest_one::<SquaredEuclidean>(&[d * ray[0], d * ray[1], d * ray[2]]).distance.sqrt()
        }));
        Score { radial, c2m }
    }
}
