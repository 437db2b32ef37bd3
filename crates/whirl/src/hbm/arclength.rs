//! Scaled arclength along a branch of periodic solutions: the scales of a point
//! ([`Scaling`]), the unit tangent, the pseudo-arclength corrector, and Newton at a fixed
//! frequency between two points. The path follower
//! ([`continuation`](mod@super::continuation)) and the searches between its points (folds,
//! [`bifurcation`](super::bifurcation)) share them.

use super::balance::HbSolution;
use super::newton::{line_search, relative, GiveUp, Residual, FULL_STEPS, LINE_SEARCH_HALVINGS};
use super::periodic::Periodic;
use crate::error::{Error, Result};
use crate::linalg::{difference, dot_in_order as dot, norm, solve_dense};
use faer::Mat;

/// Scales of the coefficients and of the frequency in the arclength.
#[derive(Debug, Clone, Copy)]
pub(super) struct Scaling {
    pub(super) coefficients: f64,
    pub(super) frequency: f64,
}

impl Scaling {
    /// The scales at `s`: its largest coefficient (1 for the zero solution) and its
    /// frequency. Neither depends on the first point or on the range, so a step is the
    /// same relative change of the orbit and of the speed anywhere on the branch.
    pub(super) fn at(s: &HbSolution) -> Scaling {
        let largest = s.coefficients.iter().fold(0.0f64, |m, c| m.max(c.abs()));
        Scaling {
            coefficients: if largest > 0.0 { largest } else { 1.0 },
            frequency: s.frequency.abs(),
        }
    }

    pub(super) fn scaled(&self, s: &HbSolution) -> Vec<f64> {
        let mut y: Vec<f64> = s
            .coefficients
            .iter()
            .map(|c| c / self.coefficients)
            .collect();
        y.push(s.frequency / self.frequency);
        y
    }

    /// (coefficients, frequency) of a scaled point.
    pub(super) fn unscaled(&self, y: &[f64]) -> (Vec<f64>, f64) {
        let (x, w) = y.split_at(y.len() - 1);
        (
            x.iter().map(|c| c * self.coefficients).collect(),
            w[0] * self.frequency,
        )
    }
}

/// The scaling at the newly accepted point `s`, and the tangent `t` (unit in `scaling`)
/// expressed as a unit vector in it: the same direction in (x, w).
pub(super) fn rescaled(scaling: &Scaling, t: &[f64], s: &HbSolution) -> (Scaling, Vec<f64>) {
    let next = Scaling::at(s);
    let last = t.len() - 1;
    let mut direction: Vec<f64> = t[..last]
        .iter()
        .map(|v| v * scaling.coefficients / next.coefficients)
        .collect();
    direction.push(t[last] * scaling.frequency / next.frequency);
    let length = norm(&direction);
    (next, direction.iter().map(|v| v / length).collect())
}

/// The augmented Jacobian [dR/dx s_x, dR/dw s_w; c^T] in scaled variables at `s`.
pub(super) fn augmented(
    hb: &mut impl Periodic,
    s: &HbSolution,
    scaling: &Scaling,
    c: &[f64],
) -> Mat<f64> {
    let lin = hb.derivatives(&s.coefficients, s.frequency);
    let size = s.coefficients.len();
    Mat::from_fn(size + 1, size + 1, |i, j| {
        if i == size {
            c[j]
        } else if j == size {
            lin.frequency_derivative[i] * scaling.frequency
        } else {
            lin.jacobian[(i, j)] * scaling.coefficients
        }
    })
}

/// The unit tangent at `s` oriented along `previous` (positive projection on it).
pub(super) fn unit_tangent(
    hb: &mut impl Periodic,
    s: &HbSolution,
    scaling: &Scaling,
    previous: &[f64],
) -> Result<Vec<f64>> {
    let a = augmented(hb, s, scaling, previous);
    let mut rhs = vec![0.0; previous.len()];
    rhs[previous.len() - 1] = 1.0;
    let t = solve_dense(&a, &rhs).ok_or_else(|| {
        Error::singular(
            "continuation Jacobian",
            format!(
                "the branch's tangent is undefined at {} rad/s (a branch point?)",
                s.frequency
            ),
        )
    })?;
    let length = norm(&t);
    Ok(t.iter().map(|v| v / length).collect())
}

/// Pseudo-arclength corrector from the predictor y_0 + h t_0: plain Newton, then, should
/// it fail, Newton with a line search ([`line_search`]), which converges where full steps
/// cycle between contact states. Plain Newton first keeps every point it reaches as it was
/// and costs no extra residuals where it converges; either run stops early once it shows
/// it cannot converge ([`GiveUp`]).
pub(super) fn correct(
    hb: &mut impl Periodic,
    y0: &[f64],
    t0: &[f64],
    step: f64,
    scaling: &Scaling,
) -> Result<HbSolution> {
    newton_on_arclength(hb, y0, t0, step, scaling, FULL_STEPS)
        .or_else(|_| newton_on_arclength(hb, y0, t0, step, scaling, LINE_SEARCH_HALVINGS))
}

/// Newton on the residual and the arclength equation from y_0 + h t_0, each step
/// shortened up to `halvings` times.
pub(super) fn newton_on_arclength(
    hb: &mut impl Periodic,
    y0: &[f64],
    t0: &[f64],
    step: f64,
    scaling: &Scaling,
    halvings: usize,
) -> Result<HbSolution> {
    let mut y: Vec<f64> = y0.iter().zip(t0).map(|(a, t)| a + step * t).collect();
    let max_iterations = hb.options().max_iterations;
    let tolerance = hb.options().tolerance;
    let mut give_up = GiveUp::new(halvings);
    let mut residual = scaled_residual(hb, &y, scaling);
    for iteration in 0..=max_iterations {
        let r = relative(&residual);
        // The arclength equation is linear: the predictor and every Newton step (whole or
        // shortened) satisfy it.
        if r <= tolerance {
            let (x, w) = scaling.unscaled(&y);
            return Ok(HbSolution {
                frequency: w,
                coefficients: x,
                iterations: iteration,
                relative_residual: r,
            });
        }
        if !r.is_finite() || iteration == max_iterations || give_up.now(r) {
            break;
        }
        let (x, w) = scaling.unscaled(&y);
        let current = HbSolution {
            frequency: w,
            coefficients: x,
            iterations: iteration,
            relative_residual: r,
        };
        let a = augmented(hb, &current, scaling, t0);
        let mut rhs = residual.values.clone();
        rhs.push(0.0);
        let Some(delta) = solve_dense(&a, &rhs) else {
            break;
        };
        (y, residual) = line_search(&y, &delta, &residual, halvings, |trial| {
            scaled_residual(hb, trial, scaling)
        });
    }
    Err(Error::not_converged(
        "continuation corrector",
        None,
        None,
        format!(
            "the continuation corrector did not converge with step {step:e} from {} rad/s",
            y0[y0.len() - 1] * scaling.frequency
        ),
    ))
}

/// R at the scaled point y (its arclength row, satisfied by every corrector iterate, left
/// out); not finite where the frequency is not positive.
fn scaled_residual(hb: &mut impl Periodic, y: &[f64], scaling: &Scaling) -> Residual {
    let (x, w) = scaling.unscaled(y);
    if !(w.is_finite() && w > 0.0) {
        return Residual {
            values: vec![f64::NAN; x.len()],
            scale: f64::NAN,
        };
    }
    let (values, scale) = hb.residual_at(&x, w);
    Residual { values, scale }
}

/// The solution at exactly `to`, between `before` and `after`, by Newton at fixed
/// frequency from their linear interpolation.
pub(super) fn land_on(
    hb: &mut impl Periodic,
    before: &HbSolution,
    after: &HbSolution,
    to: f64,
) -> Result<HbSolution> {
    hb.solve(to, &interpolated_orbit(before, after, to))
}

/// The coefficients at frequency `to` linearly interpolated (or extrapolated) between the
/// orbits `before` and `after`: Newton's start at a fixed frequency between two points.
pub(super) fn interpolated_orbit(before: &HbSolution, after: &HbSolution, to: f64) -> Vec<f64> {
    let u = (to - before.frequency) / (after.frequency - before.frequency);
    before
        .coefficients
        .iter()
        .zip(&after.coefficients)
        .map(|(a, b)| a + u * (b - a))
        .collect()
}

/// What a search between two successive points `before` and `after` works in: the scaled
/// `before` y_0, its unit tangent t_0 oriented along the chord to `after` (the direction
/// of travel), the arclength of `after` along t_0, and the scaling (at `before`). Trial
/// points at arclength sigma are `correct(hb, y_0, t_0, sigma, scaling)`.
pub(super) fn arclength_frame(
    hb: &mut impl Periodic,
    before: &HbSolution,
    after: &HbSolution,
) -> Result<(Vec<f64>, Vec<f64>, f64, Scaling)> {
    let scaling = Scaling::at(before);
    let y0 = scaling.scaled(before);
    let chord = difference(&scaling.scaled(after), &y0);
    let t0 = unit_tangent(hb, before, &scaling, &chord)?;
    let length = dot(&t0, &chord);
    Ok((y0, t0, length, scaling))
}
