//! Levenberg-Marquardt for small nonlinear least-squares problems: minimise
//! C(p) = 1/2 |r(p)|^2 over a few parameters p.
//!
//! Each iteration solves, in scaled parameters,
//!
//! ```text
//! (H + lambda I) d = -g,   H = D^-1 (J^T J + S) D^-1,   g = D^-1 J^T r,   S = sum r_i d2r_i/dp2
//! ```
//!
//! with D the column norms of the Jacobian J at the start, so that parameters of very
//! different sizes (a coefficient of 1e9 N/m^b beside an exponent near 1) are handled
//! alike (Marquardt's scaling). H is the exact Hessian of C, not only the Gauss-Newton
//! part J^T J: when the residuals stay large at the minimum (scattered data) and the cost
//! valley is long and flat (a coefficient and an exponent that trade off), Gauss-Newton
//! converges only linearly, hundreds of iterations, while Newton converges quadratically.
//! A step that lowers the cost is taken and lambda divided by 10; otherwise lambda grows
//! tenfold (which also makes H + lambda I positive definite far from the minimum) and the
//! step is tried again. The fit has converged when the step is round-off small, or when no
//! step, however short, lowers the cost.

use faer::Mat;

use crate::error::{Error, Result};
use crate::linalg::{dot_in_order, solve_dense};

/// Iterations before giving up.
const MAX_ITERATIONS: usize = 200;
/// A scaled step this small relative to the scaled parameters means convergence: the next
/// digits are round-off.
const STEP_TOLERANCE: f64 = 1e-14;
/// A damping this large means no step lowers the cost any more: the minimum is reached to
/// round-off.
const LAMBDA_LIMIT: f64 = 1e16;

/// A converged fit.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Solution {
    /// The parameters at the minimum.
    pub params: Vec<f64>,
    /// Iterations taken.
    pub iterations: usize,
}

/// The residuals at some parameters with their first and second derivatives.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Evaluation {
    /// Residuals r_i.
    pub residuals: Vec<f64>,
    /// dr_i/dp_j, row-major, one row per residual.
    pub jacobian: Vec<f64>,
    /// S = sum_i r_i d2r_i/(dp_j dp_k), row-major m x m.
    pub curvature: Vec<f64>,
}

/// Evaluates the problem at parameters `p`; `None` where the model is undefined (the step
/// is then rejected).
pub(crate) type Residuals<'a> = &'a dyn Fn(&[f64]) -> Option<Evaluation>;

/// Minimises the sum of squared residuals from `start`.
pub(crate) fn levenberg_marquardt(start: &[f64], residuals: Residuals<'_>) -> Result<Solution> {
    let m = start.len();
    let mut p = start.to_vec();
    let mut at = residuals(&p).ok_or_else(|| {
        Error::InvalidOption("least squares: the model is undefined at the starting values".into())
    })?;
    let scale = column_norms(&at.jacobian, m);
    let mut lambda = 1e-3;
    for iteration in 1..=MAX_ITERATIONS {
        let (hessian, gradient) = scaled_newton_system(&at, &scale);
        let cost = squared_norm(&at.residuals);
        loop {
            let accepted = damped_step(&hessian, &gradient, lambda).and_then(|step| {
                let trial: Vec<f64> = p
                    .iter()
                    .zip(&step)
                    .zip(&scale)
                    .map(|((x, d), s)| x + d / s)
                    .collect();
                let next = residuals(&trial)?;
                (squared_norm(&next.residuals) < cost).then_some((step, trial, next))
            });
            if let Some((step, trial, next)) = accepted {
                let small = step_is_round_off(&step, &p, &scale);
                (p, at) = (trial, next);
                lambda = (lambda / 10.0).max(1e-12);
                if small {
                    return Ok(Solution {
                        params: p,
                        iterations: iteration,
                    });
                }
                break;
            }
            lambda *= 10.0;
            if lambda > LAMBDA_LIMIT {
                return Ok(Solution {
                    params: p,
                    iterations: iteration,
                });
            }
        }
    }
    Err(Error::not_converged(
        "least squares",
        Some(MAX_ITERATIONS),
        None,
        format!("least squares did not converge in {MAX_ITERATIONS} iterations"),
    ))
}

/// True when the scaled step is below [`STEP_TOLERANCE`] of the scaled parameters.
fn step_is_round_off(step: &[f64], p: &[f64], scale: &[f64]) -> bool {
    let size = step.iter().map(|d| d * d).sum::<f64>().sqrt();
    let reach = p
        .iter()
        .zip(scale)
        .map(|(x, s)| (x * s).powi(2))
        .sum::<f64>()
        .sqrt();
    size <= STEP_TOLERANCE * reach
}

/// Euclidean norm of each column of the row-major `jac` with `m` columns; 1 for a zero
/// column, which then simply stays unscaled.
fn column_norms(jac: &[f64], m: usize) -> Vec<f64> {
    (0..m)
        .map(|j| {
            let n = jac
                .iter()
                .skip(j)
                .step_by(m)
                .map(|x| x * x)
                .sum::<f64>()
                .sqrt();
            if n > 0.0 && n.is_finite() {
                n
            } else {
                1.0
            }
        })
        .collect()
}

/// H = D^-1 (J^T J + S) D^-1 and g = D^-1 J^T r.
fn scaled_newton_system(at: &Evaluation, scale: &[f64]) -> (Mat<f64>, Vec<f64>) {
    let m = scale.len();
    let mut hessian = Mat::from_fn(m, m, |a, b| at.curvature[a * m + b] / (scale[a] * scale[b]));
    let mut gradient = vec![0.0; m];
    for (ri, row) in at.residuals.iter().zip(at.jacobian.chunks_exact(m)) {
        for a in 0..m {
            let ja = row[a] / scale[a];
            gradient[a] += ja * ri;
            for b in 0..m {
                hessian[(a, b)] += ja * row[b] / scale[b];
            }
        }
    }
    (hessian, gradient)
}

/// Solves (H + lambda I) d = -g; `None` when that has no finite solution.
fn damped_step(hessian: &Mat<f64>, gradient: &[f64], lambda: f64) -> Option<Vec<f64>> {
    let m = gradient.len();
    let damped = Mat::from_fn(m, m, |a, b| {
        hessian[(a, b)] + if a == b { lambda } else { 0.0 }
    });
    let descent: Vec<f64> = gradient.iter().map(|g| -g).collect();
    solve_dense(&damped, &descent)
}

/// |r|^2.
fn squared_norm(r: &[f64]) -> f64 {
    dot_in_order(r, r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fits_an_exponential_decay_from_a_poor_start() {
        // y = 3 e^(-0.7 t) exactly; start 3x off in amplitude and 2x in rate.
        let t: Vec<f64> = (0..40).map(|i| 0.1 * i as f64).collect();
        let y: Vec<f64> = t.iter().map(|t| 3.0 * (-0.7 * t).exp()).collect();
        let model = |p: &[f64]| {
            let mut at = Evaluation {
                residuals: Vec::new(),
                jacobian: Vec::new(),
                curvature: vec![0.0; 4],
            };
            for (t, y) in t.iter().zip(&y) {
                let e = (-p[1] * t).exp();
                let r = y - p[0] * e;
                at.residuals.push(r);
                at.jacobian.extend([-e, p[0] * t * e]);
                let second = [0.0, t * e, t * e, -p[0] * t * t * e];
                at.curvature
                    .iter_mut()
                    .zip(second)
                    .for_each(|(c, h)| *c += r * h);
            }
            Some(at)
        };
        let s = levenberg_marquardt(&[1.0, 1.4], &model).unwrap();
        // Zero-residual problem: the minimum is recovered to round-off.
        assert!((s.params[0] - 3.0).abs() < 1e-12, "{s:?}");
        assert!((s.params[1] - 0.7).abs() < 1e-12, "{s:?}");
    }
}
