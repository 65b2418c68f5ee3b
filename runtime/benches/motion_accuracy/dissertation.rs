//! The dissertation's figures (Tables 4.1–4.3, [HLK13a]): the parameter grid of Tables 4.2 and
//! 4.3 and, per row, mean and σ of the error (cm) and the time (ms, GTX 680 with CUDA) of the
//! buddha (1 cm lateral translation per phase image) and dragon (1° rotation about the line of
//! sight) scenes.

/// One row of the grid: MWS, NH, θ (% of 65535), ρ (degrees).
#[derive(Debug, Clone, Copy)]
pub struct Row {
    pub window: u32,
    pub smooth: bool,
    pub theta_percent: f32,
    pub rho: Option<f32>,
}

const fn row(window: u32, smooth: bool, theta_percent: f32, rho: Option<f32>) -> Row {
    Row { window, smooth, theta_percent, rho }
}

/// Tables 4.2 and 4.3's rows, in their order.
pub const GRID: [Row; 16] = [
    row(5, false, 0.0, None),
    row(5, false, 1.0, None),
    row(5, false, 5.0, None),
    row(5, false, 8.0, None),
    row(5, true, 1.0, None),
    row(5, false, 1.0, Some(90.0)),
    row(5, true, 1.0, Some(90.0)),
    row(5, false, 1.0, Some(180.0)),
    row(5, true, 1.0, Some(180.0)),
    row(7, false, 0.0, None),
    row(7, false, 1.0, None),
    row(7, true, 1.0, None),
    row(7, false, 1.0, Some(90.0)),
    row(7, true, 1.0, Some(90.0)),
    row(7, false, 1.0, Some(180.0)),
    row(7, true, 1.0, Some(180.0)),
];

/// The row of the default parameters (sec. 4.3.1: "a good default parameter set is θ = 1 % and
/// MWS = 5").
pub const DEFAULT: usize = 1;

/// The row of the default parameters with the NH filter.
pub const DEFAULT_WITH_NH: usize = 4;

/// The row of the widest search without restriction (MWS 7, θ 0, no NH, no ρ): the buddha's
/// best.
pub const UNRESTRICTED: usize = 9;

/// A scene of the dissertation: Table 4.1 (static and dynamic, mean and σ) and its column of
/// Table 4.2 or 4.3 (mean, σ, time) row by row.
pub struct Reference {
    pub name: &'static str,
    pub static_error: (f64, f64),
    pub dynamic_error: (f64, f64),
    pub rows: [(f64, f64, f64); 16],
}

/// Table 4.2: the buddha, translated.
pub const BUDDHA: Reference = Reference {
    name: "buddha",
    static_error: (0.64, 3.12),
    dynamic_error: (5.96, 9.32),
    rows: [
        (1.15, 3.10, 12.58),
        (1.70, 3.54, 11.57),
        (3.49, 4.70, 10.59),
        (4.22, 5.18, 10.13),
        (1.38, 3.05, 16.13),
        (1.34, 3.33, 9.79),
        (1.46, 3.24, 13.18),
        (1.34, 3.38, 11.08),
        (1.27, 3.04, 13.49),
        (1.14, 3.02, 25.04),
        (1.16, 3.08, 23.54),
        (1.34, 3.03, 31.86),
        (1.35, 3.35, 12.15),
        (1.35, 3.13, 21.16),
        (1.35, 3.37, 15.18),
        (1.37, 3.04, 23.53),
    ],
};

/// Table 4.3: the dragon, rotated.
pub const DRAGON: Reference = Reference {
    name: "dragon",
    static_error: (1.25, 4.62),
    dynamic_error: (7.75, 14.37),
    rows: [
        (2.08, 5.70, 12.09),
        (2.09, 5.71, 11.97),
        (2.43, 6.04, 11.57),
        (2.62, 6.01, 10.89),
        (2.22, 5.51, 14.31),
        (2.12, 5.49, 9.40),
        (2.37, 5.75, 11.89),
        (2.16, 5.68, 9.83),
        (2.33, 5.70, 13.13),
        (2.07, 5.65, 21.44),
        (2.07, 5.65, 20.55),
        (2.35, 5.48, 26.45),
        (2.44, 5.63, 11.30),
        (2.17, 5.66, 17.61),
        (2.18, 5.77, 14.28),
        (2.42, 5.64, 20.67),
    ],
};
