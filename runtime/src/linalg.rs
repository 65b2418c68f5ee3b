//! Small dense least squares: the Cholesky solve of a symmetric positive definite system (the
//! 6×6 ICP step, the normal equations of a fit), least squares on any basis, and polynomial
//! fitting and evaluation.

/// Solves `a x = b` for symmetric positive definite `a` by Cholesky; `None` when a pivot is tiny
/// next to the largest diagonal entry (a direction the data does not fix).
#[allow(clippy::needless_range_loop)] // matrix code reads best with indices
pub fn cholesky_solve<const N: usize>(a: &[[f64; N]; N], b: &[f64; N]) -> Option<[f64; N]> {
    let scale = (0..N).map(|r| a[r][r]).fold(0.0f64, f64::max);
    let mut l = [[0.0f64; N]; N];
    for r in 0..N {
        for c in 0..=r {
            let s: f64 = a[r][c] - (0..c).map(|m| l[r][m] * l[c][m]).sum::<f64>();
            if r == c {
                if s <= 1e-9 * scale || scale == 0.0 {
                    return None;
                }
                l[r][c] = s.sqrt();
            } else {
                l[r][c] = s / l[c][c];
            }
        }
    }
    let mut y = [0.0f64; N];
    for r in 0..N {
        y[r] = (b[r] - (0..r).map(|m| l[r][m] * y[m]).sum::<f64>()) / l[r][r];
    }
    let mut x = [0.0f64; N];
    for r in (0..N).rev() {
        x[r] = (y[r] - (r + 1..N).map(|m| l[m][r] * x[m]).sum::<f64>()) / l[r][r];
    }
    Some(x)
}

/// The least-squares `x` minimising `Σ (basis · x − y)²` over `rows` of `(basis, y)`, through the
/// normal equations; `None` where the data does not fix it (see [`cholesky_solve`]). Scale the
/// basis functions to about 1 for conditioning.
#[allow(clippy::needless_range_loop)] // matrix code reads best with indices
pub fn least_squares<const N: usize>(rows: impl IntoIterator<Item = ([f64; N], f64)>) -> Option<[f64; N]> {
    let mut a = [[0.0f64; N]; N];
    let mut b = [0.0f64; N];
    for (basis, y) in rows {
        for r in 0..N {
            for c in 0..N {
                a[r][c] += basis[r] * basis[c];
            }
            b[r] += basis[r] * y;
        }
    }
    cholesky_solve(&a, &b)
}

/// The least-squares polynomial of degree `N − 1` through `(x, y)` points, coefficients highest
/// degree first (as Table 5.1 prints them). `x` is scaled to about 1 inside, for conditioning.
pub fn polyfit<const N: usize>(points: &[(f64, f64)]) -> Option<[f64; N]> {
    let scale = points.iter().map(|p| p.0.abs()).fold(0.0f64, f64::max).max(f64::MIN_POSITIVE);
    // Powers of the scaled x, lowest first.
    let powers = |x: f64| -> [f64; N] { std::array::from_fn(|k| (x / scale).powi(k as i32)) };
    let scaled = least_squares(points.iter().map(|&(x, y)| (powers(x), y)))?;
    Some(std::array::from_fn(|k| {
        let degree = N - 1 - k;
        scaled[degree] / scale.powi(degree as i32)
    }))
}

/// `p(x)` for coefficients highest degree first (Horner).
pub fn polyval(coefficients: &[f64], x: f64) -> f64 {
    coefficients.iter().fold(0.0, |value, c| value * x + c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_table_5_1s_cubic_back_from_its_own_samples() {
        let h = [2.2026e-10, 4.417871e-05, 0.4276858, 1100.069];
        let points: Vec<(f64, f64)> =
            (0..=30).map(|k| 10_000.0 + 500.0 * k as f64).map(|x| (x, polyval(&h, x))).collect();
        let fit = polyfit::<4>(&points).unwrap();
        for (f, e) in fit.iter().zip(&h) {
            assert!((f - e).abs() <= 1e-6 * e.abs(), "{fit:?} vs {h:?}");
        }
    }

    #[test]
    fn a_system_the_data_does_not_fix_has_no_solution() {
        // Every point at the same x: the slope is free.
        assert_eq!(polyfit::<2>(&[(3.0, 1.0), (3.0, 2.0), (3.0, 1.5)]), None);
        assert_eq!(cholesky_solve(&[[0.0; 2]; 2], &[1.0, 1.0]), None);
    }
}
