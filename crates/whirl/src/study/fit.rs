//! Polynomial least squares with the coefficient of determination: the largest NSV versus
//! clearance, delta_nsv = P1 gamma^3 + P2 gamma^2 + P3 gamma + P4 (thesis eq. 5.1,
//! table 5.1).
//!
//! The fit minimises sum (y_i - p(x_i))^2 with the project's Levenberg-Marquardt solver
//! (the crate's Levenberg-Marquardt): the residuals are linear in the coefficients, so
//! the curvature term is zero and the Marquardt column scaling takes care of columns as
//! different as gamma^3 (1e-15 m^3) and 1. R^2 = 1 - SS_res / SS_tot with
//! SS_tot = sum (y_i - mean y)^2.

use crate::bearing::least_squares::{levenberg_marquardt, Evaluation};
use crate::error::{Error, Result};

/// A fitted polynomial.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PolynomialFit {
    /// Coefficients from the highest power down (P1 ... P4 of eq. 5.1 for a cubic), in the
    /// SI units of x and y.
    pub coefficients: Vec<f64>,
    /// Coefficient of determination R^2 (1 for a perfect fit).
    pub r_squared: f64,
    /// Root-mean-square residual, in the unit of y.
    pub rms_residual: f64,
}

impl PolynomialFit {
    /// The polynomial at `x`.
    pub fn at(&self, x: f64) -> f64 {
        self.coefficients.iter().fold(0.0, |acc, c| acc * x + c)
    }
}

/// Fits a polynomial of `degree` to the points (x_i, y_i).
///
/// Needs at least `degree + 1` distinct x values and finite data; the error says so.
///
/// # Errors
/// [`Error::InvalidOption`] when `x` and `y` differ in length, a value is not finite, or
/// there are fewer than `degree + 1` distinct x values.
pub fn polynomial_fit(x: &[f64], y: &[f64], degree: usize) -> Result<PolynomialFit> {
    check_data(x, y, degree)?;
    let m = degree + 1;
    // Row i of the Jacobian of r_i = y_i - p(x_i) is -(x_i^degree, ..., x_i, 1).
    let powers: Vec<f64> = x
        .iter()
        .flat_map(|&xi| (0..m).map(move |k| -xi.powi((degree - k) as i32)))
        .collect();
    let residuals = |p: &[f64]| -> Option<Evaluation> {
        let r: Vec<f64> = powers
            .chunks_exact(m)
            .zip(y)
            .map(|(row, yi)| yi + row.iter().zip(p).map(|(a, c)| a * c).sum::<f64>())
            .collect();
        Some(Evaluation {
            residuals: r,
            jacobian: powers.clone(),
            curvature: vec![0.0; m * m],
        })
    };
    let solution = levenberg_marquardt(&vec![0.0; m], &residuals)?;
    let fit = PolynomialFit {
        coefficients: solution.params,
        r_squared: f64::NAN,
        rms_residual: f64::NAN,
    };
    Ok(with_quality(fit, x, y))
}

/// Fills in R^2 and the RMS residual.
fn with_quality(mut fit: PolynomialFit, x: &[f64], y: &[f64]) -> PolynomialFit {
    let n = y.len() as f64;
    let mean = y.iter().sum::<f64>() / n;
    let ss_res: f64 = x
        .iter()
        .zip(y)
        .map(|(&a, &b)| (b - fit.at(a)).powi(2))
        .sum();
    let ss_tot: f64 = y.iter().map(|b| (b - mean).powi(2)).sum();
    // All y equal: a constant fits them exactly, and R^2 is 1 by convention when it does.
    fit.r_squared = if ss_tot > 0.0 {
        1.0 - ss_res / ss_tot
    } else {
        1.0
    };
    fit.rms_residual = (ss_res / n).sqrt();
    fit
}

fn check_data(x: &[f64], y: &[f64], degree: usize) -> Result<()> {
    if x.len() != y.len() {
        return Err(Error::InvalidOption(format!(
            "polynomial fit: {} x values but {} y values",
            x.len(),
            y.len()
        )));
    }
    if x.iter().chain(y).any(|v| !v.is_finite()) {
        return Err(Error::InvalidOption(
            "polynomial fit: every value must be a finite number".into(),
        ));
    }
    let mut distinct = x.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    if distinct.len() <= degree {
        return Err(Error::InvalidOption(format!(
            "a polynomial of degree {degree} needs at least {} different values of the \
             parameter, got {}",
            degree + 1,
            distinct.len()
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_table_5_1_from_exact_cubic_data() {
        // Table 5.1 of the thesis, in SI (gamma in m, delta in m), sampled at 10..120 um.
        let p = [-3.125e8, 7.162e4, -1.956, 4.296e-5];
        let x: Vec<f64> = (1..=12).map(|i| 1e-5 * i as f64).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|g| p.iter().fold(0.0, |a, c| a * g + c))
            .collect();
        let fit = polynomial_fit(&x, &y, 3).unwrap();
        for (got, want) in fit.coefficients.iter().zip(p) {
            // Zero-residual problem: the coefficients come back to round-off; the columns
            // span 15 decades, so allow 1e-7 relative.
            assert!((got / want - 1.0).abs() < 1e-7, "{got} vs {want}");
        }
        assert!((fit.r_squared - 1.0).abs() < 1e-12);
    }

    #[test]
    fn r_squared_of_a_line_through_scattered_points_matches_the_closed_form() {
        // y = (0, 2, 1, 3) at x = (0, 1, 2, 3): the least-squares line is y = 0.8 x + 0.3
        // (normal equations), SS_res = 1.8 and SS_tot = 5, so R^2 = 0.64 exactly.
        let fit = polynomial_fit(&[0.0, 1.0, 2.0, 3.0], &[0.0, 2.0, 1.0, 3.0], 1).unwrap();
        assert!((fit.coefficients[0] - 0.8).abs() < 1e-12);
        assert!((fit.coefficients[1] - 0.3).abs() < 1e-12);
        assert!((fit.r_squared - 0.64).abs() < 1e-12);
    }

    #[test]
    fn too_few_distinct_values_are_refused() {
        let e = polynomial_fit(&[1.0, 1.0, 2.0, 2.0], &[1.0, 2.0, 3.0, 4.0], 3).unwrap_err();
        assert!(e.to_string().contains("at least 4 different values"), "{e}");
    }
}
