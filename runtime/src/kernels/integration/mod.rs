//! Per-pixel automatic integration time (sec. 5.3): the sensor model of Table 5.1 and the
//! estimate of the next frame's integration time from the current intensity image (eq. 5.4–5.8),
//! a kernel with its CPU reference.

use crate::linalg::polyval;

pub mod integration_time;

pub use integration_time::estimate;
pub(crate) use integration_time::IntegrationTime;

/// The sensor model the estimate needs: the optimal intensity, the intensity correction `h`
/// with its range, the gain, and the integration times the camera can take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntegrationModel {
    /// Amplitude with the lowest distance error, and the intensity it maps to (eq. 5.2).
    pub a_opt: f32,
    pub i_opt: f32,
    /// Amplitude → intensity (eq. 5.1), highest degree first.
    pub m: [f32; 2],
    /// Measured → linear intensity (eq. 5.3), highest degree first, valid on `h_range`.
    pub h: [f32; 4],
    pub h_range: (f32, f32),
    /// The pixel gain g of eq. 5.7 (one value for all pixels, as in Table 5.1).
    pub gain: f32,
    /// The integration times the camera can take, µs (the sweep of sec. 5.4: 50–8000).
    pub t_range: (f32, f32),
}

impl IntegrationModel {
    /// Table 5.1: the PMD CamCube 3.0 of the dissertation.
    pub const CAMCUBE: IntegrationModel = IntegrationModel {
        a_opt: 18_000.0,
        i_opt: 7353.0,
        m: [0.6067281, -3475.016],
        h: [2.2026e-10, 4.417871e-05, 0.4276858, 1100.069],
        h_range: (10_000.0, 25_000.0),
        gain: 1.11,
        t_range: (50.0, 8000.0),
    };

    /// The runtime's simulated camera (`sim.rs`), as the preprocessing of sec. 5.3.1 finds it
    /// on a sweep of 200–8000 µs over `Scene::plates` (`tests/integration_time.rs` checks that
    /// it still does).
    pub const SIMULATED: IntegrationModel = IntegrationModel {
        a_opt: 36_517.414,
        i_opt: 76_480.195,
        m: [0.89216876, 43_900.496],
        h: [-8.0347395e-10, 0.00028668254, -30.154741, 1_070_720.8],
        h_range: (77_842.31, 124_915.89),
        gain: 1.11,
        t_range: (50.0, 8000.0),
    };

    /// Eq. 5.4: the linearised intensity (identity below h's range, h's upper bound above it).
    pub fn correct(&self, measured: f32) -> f32 {
        if measured < self.h_range.0 {
            return measured;
        }
        let h = self.h.map(f64::from);
        polyval(&h, measured.min(self.h_range.1) as f64) as f32
    }
}

/// The weight map w: a Gaussian centred on the image, σ a quarter of the side, 1 in the middle.
pub fn weight(x: usize, y: usize, width: usize, height: usize) -> f32 {
    let dx = (x as f32 + 0.5) / width as f32 - 0.5;
    let dy = (y as f32 + 0.5) / height as f32 - 0.5;
    (-(dx * dx + dy * dy) * 8.0).exp()
}
