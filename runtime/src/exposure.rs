//! Automatic integration time (chapter 5) around the per-pixel estimate: the preprocessing of
//! sec. 5.3.1 that fits a sensor's model (A_opt, m, h) from a sweep of integration times, May et
//! al.'s proportional controller on the mean intensity as the baseline, and the closed loop that
//! takes each frame at the time the previous one chose (sec. 5.4).

use std::fmt;

use crate::kernels::integration::{estimate, IntegrationModel};
use crate::linalg::polyfit;
use crate::Image;

/// One demodulated frame and the integration time it was taken at.
#[derive(Debug, Clone, PartialEq)]
pub struct Sample {
    pub integration_us: f32,
    pub amplitude: Image,
    pub intensity: Image,
    pub distance: Image,
}

#[derive(Debug, Clone, PartialEq)]
pub enum CalibrationError {
    /// Too few pixels with ground truth in the sweep to find the amplitude of least error.
    NoErrorMinimum,
    /// The sweep never leaves the linear range (or never enters it): no h to fit.
    NoNonLinearity,
    /// A fit was singular.
    Degenerate(&'static str),
}

impl fmt::Display for CalibrationError {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match self {
            CalibrationError::NoErrorMinimum => {
                write!(f, "the sweep has too few pixels with ground truth to find the amplitude of least error")
            }
            CalibrationError::NoNonLinearity => {
                write!(f, "the sweep's intensities stay linear (or never are): sweep up to longer integration times")
            }
            CalibrationError::Degenerate(what) => write!(f, "the {what} fit is singular: the sweep lacks spread"),
        }
    }
}

impl std::error::Error for CalibrationError {}

/// The preprocessing of sec. 5.3.1 on a sweep of a static scene with ground truth `truth`
/// (radial distance, NaN where unknown): A_opt = the amplitude of least mean distance error
/// (sec. 5.2.3), m = the linear intensity-over-amplitude fit on [A_opt / 3, A_opt] (5.2.4), h =
/// the cubic from measured to linear intensity where they part (5.2.5; the linear intensity of
/// a pixel is its shortest well-lit time's intensity scaled by time).
pub fn calibrate(sweep: &[Sample], truth: &Image, t_range: (f32, f32)) -> Result<IntegrationModel, CalibrationError> {
    let a_opt = least_error_amplitude(sweep, truth).ok_or(CalibrationError::NoErrorMinimum)?;
    let pairs: Vec<(f64, f64)> = sweep
        .iter()
        .flat_map(|s| s.amplitude.data.iter().zip(&s.intensity.data))
        .filter(|(a, _)| **a >= a_opt / 3.0 && **a <= a_opt)
        .map(|(a, i)| (*a as f64, *i as f64))
        .collect();
    let m = polyfit::<2>(&pairs).ok_or(CalibrationError::Degenerate("amplitude–intensity"))?;
    let i_opt = (m[0] * a_opt as f64 + m[1]) as f32;
    let (h, h_range) = intensity_correction(sweep)?;
    Ok(IntegrationModel {
        a_opt,
        i_opt,
        m: m.map(|v| v as f32),
        h: h.map(|v| v as f32),
        h_range,
        gain: IntegrationModel::CAMCUBE.gain,
        t_range,
    })
}

/// The centre of the logarithmic amplitude bin (8 per decade) with the least mean error.
fn least_error_amplitude(sweep: &[Sample], truth: &Image) -> Option<f32> {
    const BINS: usize = 48;
    let bin = |a: f32| ((a.max(1.0).log10() * 8.0) as usize).min(BINS - 1);
    let mut sums = [(0.0f64, 0usize); BINS];
    for sample in sweep {
        for ((a, d), t) in sample.amplitude.data.iter().zip(&sample.distance.data).zip(&truth.data) {
            if t.is_finite() && *a > 0.0 {
                let entry = &mut sums[bin(*a)];
                entry.0 += (d - t).abs() as f64;
                entry.1 += 1;
            }
        }
    }
    let best = (0..BINS)
        .filter(|&b| sums[b].1 >= 500)
        .min_by(|&a, &b| (sums[a].0 / sums[a].1 as f64).total_cmp(&(sums[b].0 / sums[b].1 as f64)))?;
    Some(10f32.powf((best as f32 + 0.5) / 8.0))
}

/// h and its range: measured intensity against linear intensity, binned by the linear one (bins
/// of 1 % of the largest), from where measured stays 1 % short to where it rises at under a
/// fifth of the linear rate (beyond that it is saturated and h cannot recover it).
fn intensity_correction(sweep: &[Sample]) -> Result<([f64; 4], (f32, f32)), CalibrationError> {
    let mut order: Vec<&Sample> = sweep.iter().collect();
    order.sort_by(|a, b| a.integration_us.total_cmp(&b.integration_us));
    let n = sweep.first().map_or(0, |s| s.intensity.pixels());
    let mut pairs = Vec::new();
    for pixel in 0..n {
        let Some(reference) = order.iter().find(|s| s.intensity.data[pixel] >= 2000.0) else { continue };
        let rate = reference.intensity.data[pixel] / reference.integration_us;
        pairs.extend(order.iter().map(|s| (s.intensity.data[pixel], rate * s.integration_us)));
    }
    let top = pairs.iter().map(|p| p.1).fold(0.0f32, f32::max);
    if top <= 0.0 {
        return Err(CalibrationError::NoNonLinearity);
    }
    let width = top / 100.0;
    let mut bins = vec![(0.0f64, 0usize); 101];
    for &(measured, linear) in &pairs {
        let entry = &mut bins[(linear / width) as usize];
        entry.0 += measured as f64;
        entry.1 += 1;
    }
    // (linear, mean measured) per populated bin.
    let curve: Vec<(f32, f32)> = bins
        .iter()
        .enumerate()
        .filter(|(_, b)| b.1 >= 20)
        .map(|(k, b)| ((k as f32 + 0.5) * width, (b.0 / b.1 as f64) as f32))
        .collect();
    // From the first bin after which measured stays 1 % short of linear.
    let short = |&(linear, measured): &(f32, f32)| measured < 0.99 * linear;
    let start = curve.iter().rposition(|c| !short(c)).map_or(0, |k| k + 1);
    let end = (start + 1..curve.len())
        .find(|&k| (curve[k].1 - curve[k - 1].1) < 0.2 * (curve[k].0 - curve[k - 1].0))
        .unwrap_or(curve.len())
        - 1;
    // A bend worth correcting: by its end, measured is at least 10 % short.
    if start >= curve.len() || end <= start + 2 || curve[end].1 > 0.9 * curve[end].0 {
        return Err(CalibrationError::NoNonLinearity);
    }
    let (low, high, linear_high) = (curve[start].1, curve[end].1, curve[end].0);
    let fit: Vec<(f64, f64)> = pairs
        .iter()
        .filter(|(m, l)| *m >= low && *m <= high && *l <= linear_high)
        .map(|&(m, l)| (m as f64, l as f64))
        .collect();
    let h = polyfit::<4>(&fit).ok_or(CalibrationError::Degenerate("intensity correction"))?;
    Ok((h, (low, high)))
}

/// The mean intensity gained per µs of integration on the sweep's linear part (for tuning the
/// proportional controller to a scene).
pub fn intensity_rate(sweep: &[Sample], model: &IntegrationModel) -> f32 {
    let rates: Vec<f32> = sweep
        .iter()
        .map(|s| (mean(&s.intensity), s.integration_us))
        .filter(|(i, _)| *i < model.h_range.0 && *i > 0.0)
        .map(|(i, t)| i / t)
        .collect();
    rates.iter().sum::<f32>() / rates.len().max(1) as f32
}

fn mean(image: &Image) -> f32 {
    (image.data.iter().map(|&v| v as f64).sum::<f64>() / image.data.len().max(1) as f64) as f32
}

/// May et al. [MWSP06]: a proportional controller driving the mean intensity to a target,
/// `t' = t + k · (target − mean I)`, clamped to the camera's range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProportionalController {
    pub target: f32,
    /// µs per unit of intensity.
    pub k: f32,
    pub t_range: (f32, f32),
}

impl ProportionalController {
    /// Tuned to a scene whose mean intensity grows by `rate` per µs: half the error corrected per
    /// frame while the sensor is linear.
    pub fn tuned(target: f32, rate: f32, t_range: (f32, f32)) -> ProportionalController {
        ProportionalController { target, k: 0.5 / rate, t_range }
    }

    pub fn next(&self, intensity: &Image, t: f32) -> f32 {
        (t + self.k * (self.target - mean(intensity))).clamp(self.t_range.0, self.t_range.1)
    }
}

/// How the next frame's integration time is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Controller {
    /// The per-pixel method of sec. 5.3 (eq. 5.4–5.8).
    PerPixel(IntegrationModel),
    /// May et al.'s baseline.
    Proportional(ProportionalController),
}

impl Controller {
    pub fn next(&self, sample: &Sample) -> f32 {
        match self {
            Controller::PerPixel(model) => estimate(&sample.intensity, sample.integration_us, model),
            Controller::Proportional(p) => p.next(&sample.intensity, sample.integration_us),
        }
    }
}

/// One frame of a closed-loop run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoopFrame {
    pub integration_us: f32,
    /// Mean |distance − truth| over pixels with truth and a measurement, metres.
    pub mean_error: f32,
    /// Pixels with amplitude in [A_opt · 250 / 18000, A_opt] (sec. 5.4's 250–18000).
    pub well_saturated: usize,
}

/// Runs `frames` frames from `initial` µs: `acquire(frame, t)` takes a frame at `t` with its
/// truth, the controller picks the next time.
pub fn closed_loop(
    controller: &Controller,
    a_opt: f32,
    initial: f32,
    frames: usize,
    mut acquire: impl FnMut(usize, f32) -> (Sample, Image),
) -> Vec<LoopFrame> {
    let mut t = initial;
    (0..frames)
        .map(|k| {
            let (sample, truth) = acquire(k, t);
            let (mut error, mut count) = (0.0f64, 0usize);
            for (d, truth) in sample.distance.data.iter().zip(&truth.data) {
                if truth.is_finite() && *d > 0.0 {
                    error += (d - truth).abs() as f64;
                    count += 1;
                }
            }
            let low = a_opt * 250.0 / 18_000.0;
            let well_saturated = sample.amplitude.data.iter().filter(|a| **a >= low && **a <= a_opt).count();
            let frame =
                LoopFrame { integration_us: t, mean_error: (error / count.max(1) as f64) as f32, well_saturated };
            t = controller.next(&sample);
            frame
        })
        .collect()
}

/// The first frame from which the integration time stays within 5 % of the last frame's.
pub fn frames_to_converge(run: &[LoopFrame]) -> usize {
    let last = run.last().map_or(0.0, |f| f.integration_us);
    let settled = |f: &LoopFrame| (f.integration_us - last).abs() <= 0.05 * last;
    run.iter().rposition(|f| !settled(f)).map_or(0, |k| k + 1)
}
