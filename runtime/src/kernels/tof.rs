//! CPU references of the PMD kernels (dissertation sec. 2.1.1 and 2.1.2.2). A raw frame has 8
//! planes: `A0 B0 A1 B1 A2 B2 A3 B3`, the A and B channels of the phase images at 0°, 90°,
//! 180° and 270°; `P_i = A_i − B_i`.

use std::f32::consts::PI;

use crate::Image;

/// Speed of light, m/s.
pub const SPEED_OF_LIGHT: f32 = 299_792_458.0;

/// The unambiguous range `δ = c / 2f` in metres.
pub fn unambiguous_range(modulation_hz: f32) -> f32 {
    SPEED_OF_LIGHT / (2.0 * modulation_hz)
}

/// Phase, amplitude, intensity and distance of one pixel from its eight raw samples:
/// `φ = atan2(P3 − P1, P0 − P2)` wrapped into [0, 2π), `A = ½·√((P3 − P1)² + (P0 − P2)²)`,
/// `I = Σ(A_i + B_i)/4` (the channel sums: Σ P_i is 0 by construction), `D = δ·φ/2π`.
pub fn demodulate_pixel(raw: [f32; 8], modulation_hz: f32) -> [f32; 4] {
    let p = |i: usize| raw[2 * i] - raw[2 * i + 1];
    let (y, x) = (p(3) - p(1), p(0) - p(2));
    let mut phase = y.atan2(x);
    if phase < 0.0 {
        phase += 2.0 * PI;
    }
    let amplitude = 0.5 * (y * y + x * x).sqrt();
    let intensity = raw.iter().sum::<f32>() / 4.0;
    let distance = unambiguous_range(modulation_hz) * phase / (2.0 * PI);
    [phase, amplitude, intensity, distance]
}

/// Demodulates a raw frame into phase, amplitude, intensity and distance images.
pub fn demodulate(raw: &Image, modulation_hz: f32) -> [Image; 4] {
    let n = raw.pixels();
    let mut out: [Image; 4] = std::array::from_fn(|_| Image::zeros(raw.width, raw.height, 1));
    for i in 0..n {
        let samples: [f32; 8] = std::array::from_fn(|p| raw.data[p * n + i]);
        for (image, value) in out.iter_mut().zip(demodulate_pixel(samples, modulation_hz)) {
            image.data[i] = value;
        }
    }
    out
}

/// Fixed-pattern-noise removal (sec. 2.1.2): the chip's black image subtracted from every raw
/// plane, clamped at 0.
pub fn subtract_black(raw: &Image, black: &Image) -> Image {
    let data = raw.data.iter().zip(&black.data).map(|(r, b)| (r - b).max(0.0)).collect();
    Image { data, ..raw.clone() }
}

/// Intensity-related distance correction (sec. 2.1.2.2):
/// `D_c = D_m − δ_calib(I_m · intT_calib / intT)`, `δ_calib(x) = q2·x² + q1·x + q0`.
pub fn correct_intensity(
    distance: &Image,
    intensity: &Image,
    q: [f32; 3],
    int_time_calib: f32,
    int_time: f32,
) -> Image {
    let data = distance
        .data
        .iter()
        .zip(&intensity.data)
        .map(|(d, i)| {
            let x = i * int_time_calib / int_time;
            d - (q[2] * x * x + q[1] * x + q[0])
        })
        .collect();
    Image { data, ..distance.clone() }
}
