//! The PMD kernels of sec. 2.1.1 and 2.1.2.2, one module each with its CPU reference. A raw
//! frame has 8 planes: `A0 B0 A1 B1 A2 B2 A3 B3`, the A and B channels of the phase images at
//! 0°, 90°, 180° and 270°; `P_i = A_i − B_i`.

pub mod correct_intensity;
pub mod demodulate;
pub mod grey_image;
pub mod subtract_black;

pub use correct_intensity::correct_intensity;
pub(crate) use correct_intensity::CorrectIntensity;
pub use demodulate::{demodulate, demodulate_pixel};
pub(crate) use demodulate::{Demodulate, SubtractBlackDemodulate};
pub use grey_image::grey_image;
pub(crate) use grey_image::GreyImage;
pub use subtract_black::subtract_black;
pub(crate) use subtract_black::SubtractBlack;

/// Speed of light, m/s.
pub const SPEED_OF_LIGHT: f32 = 299_792_458.0;

/// The unambiguous range `δ = c / 2f` in metres.
pub fn unambiguous_range(modulation_hz: f32) -> f32 {
    SPEED_OF_LIGHT / (2.0 * modulation_hz)
}
