//! The folds (turning points) between the path's points: located on the branch by regula
//! falsi on the tangent's frequency component, or estimated from a Hermite interpolant,
//! and judged against the stability verdicts either side.

use crate::error::Result;
use crate::hbm::arclength::{arclength_frame, correct, unit_tangent, Scaling};
use crate::hbm::balance::HbSolution;
use crate::hbm::branch::{BranchPoint, Fold};
use crate::hbm::parallel::on_threads;
use crate::hbm::periodic::Periodic;
use crate::hbm::stability::outside_circle;
use crate::linalg::{difference, norm};

/// The speeds of the folds in `folds` across which the parity of the number of real
/// Floquet multipliers above 1 does not change as it must: at a fold of an exact periodic
/// solution a real multiplier crosses +1 (the Jacobian of the balance and I - Phi are
/// singular together, and det(I - Phi), of the sign of that parity, changes sign).
/// Stability computed about a truncated orbit need not obey this: on the Duffing
/// oscillator (c = 0.1, k3 = 1, F = 0.5, 512 samples) 1 and 2 harmonics put the +1
/// crossing at 1.8787 rad/s, before the fold at 2.2047, and call the middle branch stable,
/// while from 3 harmonics on each fold carries its crossing and the middle branch is
/// unstable.
///
/// The monodromy is a discretisation of its own (N samples), so its crossing lies near the
/// balance's fold, not on it: folds closer together than [`FOLD_CLUSTER`] of their speed
/// (a small overhang: the reference rotor's 20 um branch turns at 52.792 and 52.798 Hz,
/// and three times within 0.04 Hz near 184.35 Hz) are judged together, the parity across
/// the cluster against their count. A fold at a corner (a contact opening, within
/// [`FOLD_CLUSTER`]), where the branch is not smooth and no crossing is owed, is not
/// judged. Judged fold by fold, 7 of that branch's 8 folds were reported.
pub(super) fn stability_contradicts_folds(
    points: &[BranchPoint],
    folds: &[Fold],
    corners: &[f64],
) -> Vec<f64> {
    let parity = |p: &BranchPoint| {
        p.stability.as_ref().map(|s| {
            let above = s
                .multipliers
                .iter()
                .filter(|&&(re, im)| im == 0.0 && re > 0.0 && outside_circle((re, im)));
            above.count() % 2
        })
    };
    let near = |a: f64, b: f64| (a - b).abs() <= FOLD_CLUSTER * a.abs().max(b.abs());
    let mut contradicted = Vec::new();
    let mut k = 0;
    while k < folds.len() {
        let mut end = k + 1;
        while end < folds.len() && near(folds[end].frequency, folds[end - 1].frequency) {
            end += 1;
        }
        let cluster = &folds[k..end];
        k = end;
        let at_corner = cluster
            .iter()
            .any(|f| corners.iter().any(|&c| near(f.frequency, c)));
        let first = cluster.iter().map(|f| f.after).min().unwrap_or(0);
        let last = cluster.iter().map(|f| f.after + 1).max().unwrap_or(0);
        let (Some(a), Some(b)) = (points.get(first), points.get(last)) else {
            continue;
        };
        let owed = cluster.len() % 2;
        let kept = matches!((parity(a), parity(b)), (Some(x), Some(y)) if (x + owed) % 2 != y);
        if kept && !at_corner {
            contradicted.extend(cluster.iter().map(|f| f.frequency));
        }
    }
    contradicted
}

/// Folds within this fraction of their speed of each other are one overhang for
/// [`stability_contradicts_folds`].
const FOLD_CLUSTER: f64 = 1e-3;

/// Folds between successive points whose frequency slopes differ in sign, located on
/// `problems` ([`on_threads`]).
///
/// # Errors
/// None in practice: a fold whose search fails is estimated instead.
pub(super) fn locate_folds<H: Periodic + Send>(
    problems: &mut [&mut H],
    points: &[BranchPoint],
    boundaries: &[usize],
) -> Result<Vec<Fold>> {
    let turning: Vec<usize> = points
        .windows(2)
        .enumerate()
        .filter(|(i, p)| {
            p[0].frequency_slope * p[1].frequency_slope < 0.0 && !boundaries.contains(i)
        })
        .map(|(i, _)| i)
        .collect();
    on_threads(problems, turning.len(), |hb, k| {
        Ok(fold_after(&mut **hb, points, turning[k]))
    })
}

/// The fold between points `i` and `i + 1`: located on the branch, or where its search
/// fails, the extremum of the Hermite interpolant.
fn fold_after(hb: &mut impl Periodic, points: &[BranchPoint], i: usize) -> Fold {
    let (p, q) = (&points[i], &points[i + 1]);
    let (before, after) = (&p.solution, &q.solution);
    match refine_fold(hb, before, after) {
        Ok(frequency) => Fold {
            frequency,
            refined: true,
            after: i,
        },
        Err(_) => {
            let scaling = Scaling::at(before);
            let chord = difference(&scaling.scaled(after), &scaling.scaled(before));
            Fold {
                frequency: hermite_extremum(
                    before.frequency,
                    after.frequency,
                    p.frequency_slope,
                    q.frequency_slope,
                    norm(&chord),
                ),
                refined: false,
                after: i,
            }
        }
    }
}

/// The fold locator's trials stop once the tangent's frequency component t_w is below
/// this: w is stationary at the fold, so its error is of order t_w^2, and 1e-9 leaves it
/// exact to round-off.
const FOLD_SLOPE: f64 = 1e-9;

/// ... or once the bracket is shorter than this fraction of the chord between the two
/// points. Where the fold sits on a corner (a contact opening) t_w jumps sign across it
/// and never falls below [`FOLD_SLOPE`]: on the reference rotor the bracket reaches 1e-6
/// of the chord by about the 20th trial, where the trial's speed is already within 1e-10
/// relative of the 40th's (1e-12 to 6e-11 at the 20 um sweep's corner folds).
const FOLD_BRACKET: f64 = 1e-6;

/// ... or after this many trials.
const FOLD_TRIALS: usize = 40;

/// The fold between `before` and `after`: the root of the tangent's frequency component
/// along the arclength from `before`, by the Illinois regula falsi.
fn refine_fold(hb: &mut impl Periodic, before: &HbSolution, after: &HbSolution) -> Result<f64> {
    let (y0, t0, length, scaling) = arclength_frame(hb, before, after)?;
    let scaling = &scaling;
    let chord = difference(&scaling.scaled(after), &y0);
    let last = t0.len() - 1;
    let (mut a, mut ga) = (0.0, t0[last]);
    // Both tangents are oriented along the chord, the direction of travel.
    let (mut b, mut gb) = (length, unit_tangent(hb, after, scaling, &chord)?[last]);
    let mut frequency = before.frequency;
    let mut kept_side = 0;
    for _ in 0..FOLD_TRIALS {
        let sigma = (a * gb - b * ga) / (gb - ga);
        let point = correct(hb, &y0, &t0, sigma, scaling)?;
        let g = unit_tangent(hb, &point, scaling, &t0)?[last];
        frequency = point.frequency;
        if g.abs() < FOLD_SLOPE {
            break;
        }
        // Illinois: halve the value kept twice in a row, so both ends move.
        if g * ga > 0.0 {
            (a, ga) = (sigma, g);
            if kept_side == 1 {
                gb /= 2.0;
            }
            kept_side = 1;
        } else {
            (b, gb) = (sigma, g);
            if kept_side == -1 {
                ga /= 2.0;
            }
            kept_side = -1;
        }
        if (b - a).abs() < FOLD_BRACKET * length {
            break;
        }
    }
    Ok(frequency)
}

/// The extreme value of the cubic Hermite interpolant on [0, h] with end values w0, w1 and
/// end slopes m0, m1 of opposite signs, where its derivative vanishes.
fn hermite_extremum(w0: f64, w1: f64, m0: f64, m1: f64, h: f64) -> f64 {
    // p(u) = h00 w0 + h h10 m0 + h01 w1 + h h11 m1 on u in [0, 1]; p'(u) = a u^2 + b u + c.
    let a = 6.0 * (w0 - w1) + 3.0 * h * (m0 + m1);
    let b = -6.0 * (w0 - w1) - h * (4.0 * m0 + 2.0 * m1);
    let c = h * m0;
    let u = if a.abs() <= 1e-12 * (b.abs() + c.abs()) {
        -c / b
    } else {
        let root = (b * b - 4.0 * a * c).max(0.0).sqrt();
        let (plus, minus) = ((-b + root) / (2.0 * a), (-b - root) / (2.0 * a));
        // p' changes sign on [0, 1], so one root lies in it; take the nearer to its middle.
        if (plus - 0.5).abs() <= (minus - 0.5).abs() {
            plus
        } else {
            minus
        }
    };
    let (u2, u3) = (u * u, u * u * u);
    (2.0 * u3 - 3.0 * u2 + 1.0) * w0
        + h * (u3 - 2.0 * u2 + u) * m0
        + (-2.0 * u3 + 3.0 * u2) * w1
        + h * (u3 - u2) * m1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hermite_extremum_of_a_parabola_is_its_vertex() {
        // w(s) = 3 - (s - 0.3)^2 on [0, 1]: exact in a cubic interpolant.
        let w = |s: f64| 3.0 - (s - 0.3) * (s - 0.3);
        let slope = |s: f64| -2.0 * (s - 0.3);
        let top = hermite_extremum(w(0.0), w(1.0), slope(0.0), slope(1.0), 1.0);
        assert!((top - 3.0).abs() < 1e-14);
    }
}
