//! Fitting the forcing function (thesis eq. 3.12) to samples of a bearing's force.
//!
//! The law is fitted to the samples in contact (s = u_r - gamma > 0, F > 0) by
//! Levenberg-Marquardt with the exact Hessian (a private module beside this one) on
//!
//! ```text
//! log F = log(a0 + a1 W) + (b0 + b1 W) log s
//! ```
//!
//! which weighs relative force errors evenly and is well conditioned. The starting values
//! come from a straight line in log-log at each speed (log F = log A_k + B_k log s), then
//! straight lines of A_k and B_k over W.

use serde::Serialize;

use super::forcing::radial_force;
use super::least_squares::{levenberg_marquardt, Evaluation};
use crate::error::{Error, Result};
use crate::model::{Clearance, ForcingFunction};

/// One sample of a bearing's force and deflection.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ForcingPoint {
    /// Spin speed, rad/s.
    pub speed: f64,
    /// Radial deflection u_r at the bearing node, m.
    pub deflection: f64,
    /// Magnitude of the contact force, N (from the Hertz model: elastic and averaged over
    /// the cage, see [`crate::time::forcing_fit`]).
    pub force: f64,
}

/// The law's force magnitude at a sample, N, as the bearing model applies it.
pub(crate) fn law_force(law: &ForcingFunction, clearance: &Clearance, p: &ForcingPoint) -> f64 {
    radial_force(law, clearance, p.deflection, p.speed).0
}

/// A sample the law can describe: beyond the clearance and carrying a force.
pub(crate) fn in_contact(p: &ForcingPoint, clearance: &Clearance) -> bool {
    p.deflection > clearance.at_speed(p.speed) && p.force > 0.0
}

/// Fits a forcing function to samples in contact (others are ignored); returns it with the
/// iterations taken. With samples at a single speed the law cannot vary with speed, so
/// a1 = b1 = 0 and only a0, b0 are fitted.
///
/// # Errors
/// [`Error::InvalidOption`] when no speed has two distinct deflections in contact (nothing
/// to fit), or when the law is undefined at its starting values; [`Error::NotConverged`]
/// when the Levenberg-Marquardt iteration does not converge.
pub fn fit_forcing_law(
    points: &[ForcingPoint],
    clearance: &Clearance,
) -> Result<(ForcingFunction, usize)> {
    let data: Vec<LogSample> = points
        .iter()
        .filter(|p| in_contact(p, clearance))
        .map(|p| LogSample::new(p, clearance))
        .collect();
    let start = starting_law(&data)?;
    let varies = distinct_speeds(&data).len() > 1;
    let unpack = |p: &[f64]| {
        if varies {
            ForcingFunction {
                a0: p[0],
                a1: p[1],
                b0: p[2],
                b1: p[3],
            }
        } else {
            ForcingFunction {
                a0: p[0],
                a1: 0.0,
                b0: p[1],
                b1: 0.0,
            }
        }
    };
    let initial = if varies {
        vec![start.a0, start.a1, start.b0, start.b1]
    } else {
        vec![start.a0, start.b0]
    };
    let residuals = |p: &[f64]| log_residuals(&data, &unpack(p), varies);
    let solution = levenberg_marquardt(&initial, &residuals)?;
    Ok((unpack(&solution.params), solution.iterations))
}

/// A sample in the fit's variables.
#[derive(Debug, Clone, Copy)]
struct LogSample {
    speed: f64,
    /// log s, s = u_r - gamma in m.
    log_approach: f64,
    /// log F, F in N.
    log_force: f64,
}

impl LogSample {
    fn new(p: &ForcingPoint, clearance: &Clearance) -> Self {
        LogSample {
            speed: p.speed,
            log_approach: (p.deflection - clearance.at_speed(p.speed)).ln(),
            log_force: p.force.ln(),
        }
    }
}

/// Residuals log F - log a(W) - b(W) log s with their derivatives in (a0, a1, b0, b1), or
/// in (a0, b0) when the law does not vary with speed; `None` where a(W) <= 0. Only
/// -log a(W) is curved: d2/da0^2 = 1/a^2, d2/(da0 da1) = W/a^2, d2/da1^2 = W^2/a^2.
fn log_residuals(data: &[LogSample], law: &ForcingFunction, varies: bool) -> Option<Evaluation> {
    let m = if varies { 4 } else { 2 };
    let mut at = Evaluation {
        residuals: Vec::with_capacity(data.len()),
        jacobian: Vec::with_capacity(m * data.len()),
        curvature: vec![0.0; m * m],
    };
    for d in data {
        let (a, b) = law.at_speed(d.speed);
        if a <= 0.0 {
            return None;
        }
        let r = d.log_force - a.ln() - b * d.log_approach;
        at.residuals.push(r);
        let w = d.speed;
        if varies {
            at.jacobian
                .extend([-1.0 / a, -w / a, -d.log_approach, -w * d.log_approach]);
            let c = r / (a * a);
            for (j, k, v) in [(0, 0, c), (0, 1, c * w), (1, 0, c * w), (1, 1, c * w * w)] {
                at.curvature[j * m + k] += v;
            }
        } else {
            at.jacobian.extend([-1.0 / a, -d.log_approach]);
            at.curvature[0] += r / (a * a);
        }
    }
    Some(at)
}

/// The speeds present, ascending, without repeats.
fn distinct_speeds(data: &[LogSample]) -> Vec<f64> {
    let mut w: Vec<f64> = data.iter().map(|d| d.speed).collect();
    w.sort_by(f64::total_cmp);
    w.dedup();
    w
}

/// Starting values: a straight line in log-log at each speed, then straight lines of the
/// coefficient and the exponent over speed.
fn starting_law(data: &[LogSample]) -> Result<ForcingFunction> {
    let per_speed: Vec<(f64, f64, f64)> = distinct_speeds(data)
        .into_iter()
        .filter_map(|w| {
            let at: Vec<(f64, f64)> = data
                .iter()
                .filter(|d| d.speed == w)
                .map(|d| (d.log_approach, d.log_force))
                .collect();
            line(&at).map(|(log_a, b)| (w, log_a.exp(), b))
        })
        .collect();
    if per_speed.is_empty() {
        return Err(Error::InvalidOption(
            "fewer than two distinct deflections in contact at every speed: nothing to fit \
             the forcing function to (run longer, or at speeds where the shaft moves)"
                .into(),
        ));
    }
    let coefficients: Vec<(f64, f64)> = per_speed.iter().map(|&(w, a, _)| (w, a)).collect();
    let exponents: Vec<(f64, f64)> = per_speed.iter().map(|&(w, _, b)| (w, b)).collect();
    let (a0, a1) = positive_line(&coefficients);
    let (b0, b1) = line(&exponents).unwrap_or((exponents[0].1, 0.0));
    Ok(ForcingFunction { a0, a1, b0, b1 })
}

/// Least-squares line y = c0 + c1 x through `xy`; `None` when the x are all equal.
fn line(xy: &[(f64, f64)]) -> Option<(f64, f64)> {
    let n = xy.len() as f64;
    let (mx, my) = xy
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let (sxx, sxy) = xy.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (x - mx), b + (x - mx) * (y - my))
    });
    if sxx > 0.0 {
        let slope = sxy / sxx;
        Some((my - slope * mx, slope))
    } else {
        None
    }
}

/// The line through positive `xy` if it stays positive at every x, else their mean with
/// no slope: the fit's log a(W) must exist at every sample's speed.
fn positive_line(xy: &[(f64, f64)]) -> (f64, f64) {
    match line(xy) {
        Some((c0, c1)) if xy.iter().all(|(x, _)| c0 + c1 * x > 0.0) => (c0, c1),
        _ => (xy.iter().map(|p| p.1).sum::<f64>() / xy.len() as f64, 0.0),
    }
}

/// R^2 of the force and RMS relative force error of `law` over `points`.
pub(crate) fn quality(
    points: &[ForcingPoint],
    law: &ForcingFunction,
    clearance: &Clearance,
) -> (f64, f64) {
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.force).sum::<f64>() / n;
    let (mut residual, mut total, mut relative) = (0.0, 0.0, 0.0);
    for p in points {
        let e = law_force(law, clearance, p) - p.force;
        residual += e * e;
        total += (p.force - mean).powi(2);
        relative += (e / p.force).powi(2);
    }
    (1.0 - residual / total, (relative / n).sqrt())
}

/// The straight line in log-log through `points` in contact: (coefficient, exponent) of
/// F = coefficient s^exponent; NaN when the deflections are all equal.
pub(crate) fn own_power_law(points: &[ForcingPoint], clearance: &Clearance) -> (f64, f64) {
    let log: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| in_contact(p, clearance))
        .map(|p| {
            let s = LogSample::new(p, clearance);
            (s.log_approach, s.log_force)
        })
        .collect();
    line(&log).map_or((f64::NAN, f64::NAN), |(log_a, b)| (log_a.exp(), b))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn synthetic(law: &ForcingFunction, clearance: &Clearance) -> Vec<ForcingPoint> {
        let mut points = Vec::new();
        for k in 0..5 {
            let speed = 2.0 * std::f64::consts::PI * (100.0 + 100.0 * k as f64);
            for i in 0..50 {
                let s = 1e-7 * 1.1f64.powi(i);
                let deflection = clearance.at_speed(speed) + s;
                let mut p = ForcingPoint {
                    speed,
                    deflection,
                    force: 0.0,
                };
                p.force = law_force(law, clearance, &p);
                points.push(p);
            }
        }
        points
    }

    #[test]
    fn levenberg_marquardt_recovers_the_law_from_a_poor_start() {
        let law = ForcingFunction {
            a0: 3e9,
            a1: -2e5,
            b0: 1.2,
            b1: 2e-5,
        };
        let clearance = Clearance::Constant(20e-6);
        let data: Vec<LogSample> = synthetic(&law, &clearance)
            .iter()
            .map(|p| LogSample::new(p, &clearance))
            .collect();
        let residuals = |p: &[f64]| {
            let l = ForcingFunction {
                a0: p[0],
                a1: p[1],
                b0: p[2],
                b1: p[3],
            };
            log_residuals(&data, &l, true)
        };
        // Coefficient 3x too small with no speed trend, exponent 10/9.
        let s = levenberg_marquardt(&[1e9, 0.0, 10.0 / 9.0, 0.0], &residuals).unwrap();
        let expected = [law.a0, law.a1, law.b0, law.b1];
        // Zero-residual problem: recovered to round-off amplified by the conditioning.
        for (got, want) in s.params.iter().zip(expected) {
            assert!((got - want).abs() <= 1e-8 * want.abs(), "{s:?}");
        }
    }
}
