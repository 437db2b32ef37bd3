//! Static equilibrium under the constant load (gravity): K q - F_0 - F_nl(q, 0) = 0.
//!
//! Newton's method with the nonlinear forces' tangent stiffness, made robust for contacts
//! with clearance in the Levenberg-Marquardt way: the step solves (K_t + mu diag(M)) dq = -r.
//! With mu = 0 it is Newton; when K_t is singular (a rotor hanging free inside its
//! clearances, before any roller touches) or a step does not lower the residual, mu is
//! raised, which turns the step into a damped fall along the load towards contact. Once in
//! contact mu returns to zero and convergence is quadratic. Directions with neither
//! stiffness nor load (u_x with one roller at the bottom) keep their starting value: from
//! u = 0 the horizontal position stays 0 (docs/theory.md section 6).

use faer::Mat;

use super::problem::{NlScratch, TimeProblem};
use super::Kinematics;
use crate::error::{Error, Result};

/// Scale of mu, a squared circular frequency, (rad/s)^2. The first regularised step uses
/// 1e-6 of it: a free rotor's trial fall g / mu is then far past any clearance and the
/// line search finds the contact on the way.
const FIRST_MU: f64 = 4e3;

/// Static equilibrium of `problem` at its initial speed, starting from `guess`.
pub fn static_equilibrium(problem: &mut TimeProblem, guess: &[f64]) -> Result<Vec<f64>> {
    problem.check()?;
    let n = problem.size();
    let (start, _) = problem.speed.at(0.0);
    let at = Kinematics {
        time: 0.0,
        speed: start.speed,
        angle: 0.0,
    };
    let mut scratch = problem.scratch();
    let scale = norm(&problem.constant_force).max(1e-12);
    let mass_diag: Vec<f64> = (0..n).map(|i| problem.mass[(i, i)]).collect();
    let mut q = guess.to_vec();
    let mut r = residual(problem, &at, &q, &mut scratch);
    let mut mu = 0.0;
    for _ in 0..400 {
        if norm(&r) <= 1e-10 * scale {
            return Ok(q);
        }
        let mut kt = problem.stiffness.clone();
        let mut ct = Mat::<f64>::zeros(n, n);
        let zero = vec![0.0; n];
        problem.add_nonlinear_tangent(&at, &q, &zero, &mut kt, &mut ct, &mut scratch);
        match descend(problem, &at, &kt, &mass_diag, mu, &q, &r, &mut scratch) {
            Some((trial, rt)) => {
                q = trial;
                r = rt;
                mu = if mu < FIRST_MU * 1e-8 { 0.0 } else { mu / 10.0 };
            }
            None => {
                mu = if mu == 0.0 {
                    FIRST_MU * 1e-6
                } else {
                    mu * 10.0
                };
                if mu > FIRST_MU * 1e12 {
                    break;
                }
            }
        }
    }
    if norm(&r) <= 1e-8 * scale {
        return Ok(q);
    }
    Err(Error::Numerical(format!(
        "the static equilibrium did not converge (residual {:.3e} N against a load of {scale:.3e} N); \
         check that every bearing can carry the load, or start from rest",
        norm(&r)
    )))
}

/// One regularised Newton step, its length chosen where the residual's component along
/// the step changes sign (the line minimum of the potential energy when the forces are
/// conservative). Norm-decrease would stall while the rotor falls through its clearance,
/// where the residual does not change at all. `None` when the step is not a descent
/// direction or not finite.
#[allow(clippy::too_many_arguments)]
fn descend(
    problem: &mut TimeProblem,
    at: &Kinematics,
    kt: &Mat<f64>,
    mass_diag: &[f64],
    mu: f64,
    q: &[f64],
    r: &[f64],
    scratch: &mut NlScratch,
) -> Option<(Vec<f64>, Vec<f64>)> {
    let n = q.len();
    let a = Mat::<f64>::from_fn(n, n, |i, j| {
        kt[(i, j)] + if i == j { mu * mass_diag[i] } else { 0.0 }
    });
    let mut step = Mat::<f64>::from_fn(n, 1, |i, _| -r[i]);
    faer::linalg::solvers::Solve::solve_in_place(&a.partial_piv_lu(), step.as_mut());
    let dq: Vec<f64> = (0..n).map(|i| step[(i, 0)]).collect();
    if dq.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let slope0 = dot(r, &dq);
    if slope0 >= 0.0 {
        return None;
    }
    let at_t = |t: f64, p: &mut TimeProblem, s: &mut NlScratch| {
        let trial: Vec<f64> = (0..n).map(|i| q[i] + t * dq[i]).collect();
        let rt = residual(p, at, &trial, s);
        let slope = dot(&rt, &dq);
        (trial, rt, slope)
    };
    let full = at_t(1.0, problem, scratch);
    if full.2 <= 0.0 {
        return Some((full.0, full.1));
    }
    // Bisection for the sign change of the slope on (0, 1).
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut best = full;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        let trial = at_t(mid, problem, scratch);
        if trial.2 <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
        let done = trial.2.abs() <= 1e-3 * slope0.abs();
        best = trial;
        if done {
            break;
        }
    }
    (best.1.iter().all(|x| x.is_finite())).then_some((best.0, best.1))
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// K q - F_0 - F_nl(q, 0).
fn residual(p: &mut TimeProblem, at: &Kinematics, q: &[f64], s: &mut NlScratch) -> Vec<f64> {
    let n = q.len();
    let mut r: Vec<f64> = (0..n)
        .map(|i| -p.constant_force[i] + (0..n).map(|j| p.stiffness[(i, j)] * q[j]).sum::<f64>())
        .collect();
    let mut f = vec![0.0; n];
    p.add_nonlinear(at, q, &vec![0.0; n], &mut f, s);
    r.iter_mut().zip(&f).for_each(|(ri, fi)| *ri -= fi);
    r
}

fn norm(r: &[f64]) -> f64 {
    r.iter().map(|x| x * x).sum::<f64>().sqrt()
}
