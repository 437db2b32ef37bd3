//! Implicit Newmark integration with Newton iterations on the nonlinear forces.
//!
//! HHT-alpha form (Hilber, Hughes & Taylor 1977), alpha in [-1/3, 0], gamma = (1 - 2 alpha)/2,
//! beta = (1 - alpha)^2 / 4; alpha = 0 is the average-acceleration (trapezoidal) rule,
//! unconditionally stable and without numerical damping; alpha < 0 damps the highest
//! frequencies. The balance at step n+1 is
//!
//! ```text
//! M a1 + (1+alpha)(D1 v1 + K q1 - F_nl(q1, v1) - F1) - alpha (D0 v0 + K q0 - F_nl(q0, v0) - F0) = 0
//! a1 = (q1 - q0 - h v0) / (beta h^2) - (1/(2 beta) - 1) a0,   v1 = v0 + h ((1 - gamma) a0 + gamma a1)
//! ```
//!
//! solved for q1 by Newton with the Jacobian
//! M/(beta h^2) + (1+alpha)((D + C_t) gamma/(beta h) + K + K_t). A linear problem at
//! constant speed factorises once and converges in one iteration.

use faer::Mat;

use super::problem::TimeProblem;
use super::{check_state, MarchOptions, Observer};
use crate::error::{Error, Result};

/// Which member of the Newmark family.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NewmarkScheme {
    /// gamma = 1/2, beta = 1/4.
    AverageAcceleration,
    /// HHT-alpha with the given alpha in [-1/3, 0].
    Hht(f64),
}

impl NewmarkScheme {
    fn alpha(self) -> f64 {
        match self {
            NewmarkScheme::AverageAcceleration => 0.0,
            NewmarkScheme::Hht(a) => a,
        }
    }
}

/// Residual of the step, without allocation: everything but the unknown's own terms is in
/// `known`, so r = M a1 + (1+alpha)(D1 v1 + K q1 - F_nl1) - known.
struct Workspace {
    force: Vec<f64>,
    force_prev: Vec<f64>,
    known: Vec<f64>,
    residual: Vec<f64>,
    nl: Vec<f64>,
    a1: Vec<f64>,
    v1: Vec<f64>,
}

/// Marches `problem` from (q0, v0) with implicit Newmark; `observe` sees every step.
pub fn newmark(
    problem: &mut TimeProblem,
    q0: &[f64],
    v0: &[f64],
    scheme: NewmarkScheme,
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<()> {
    problem.check()?;
    let alpha = scheme.alpha();
    if !(-1.0 / 3.0..=0.0).contains(&alpha) {
        return Err(Error::Numerical(format!(
            "HHT alpha must lie in [-1/3, 0], got {alpha}"
        )));
    }
    let gamma = (1.0 - 2.0 * alpha) / 2.0;
    let beta = (1.0 - alpha).powi(2) / 4.0;
    let h = options.step;
    let n = problem.size();
    let mut scratch = problem.scratch();
    let mut w = Workspace {
        force: vec![0.0; n],
        force_prev: vec![0.0; n],
        known: vec![0.0; n],
        residual: vec![0.0; n],
        nl: vec![0.0; n],
        a1: vec![0.0; n],
        v1: vec![0.0; n],
    };
    let (mut q, mut v) = (q0.to_vec(), v0.to_vec());
    let mut at = problem.external_force(0.0, &mut w.force_prev);
    w.nl.iter_mut().for_each(|x| *x = 0.0);
    problem.add_nonlinear(&at, &q, &v, &mut w.nl, &mut scratch);
    let mut a = acceleration(problem, &q, &v, &w.force_prev, &w.nl, at.speed);
    let linear = problem.nonlinear.is_empty() && problem.speed.is_constant();
    let mut cached: Option<faer::linalg::solvers::PartialPivLu<f64>> = None;
    let mut q1 = vec![0.0; n];
    let mut dq = Mat::<f64>::zeros(n, 1);

    observe(0.0, &q, &v);
    for step in 1..options.steps {
        let t1 = step as f64 * h;
        let at1 = problem.external_force(t1, &mut w.force);
        // known = (1+alpha) F1 - alpha (F0 + F_nl0 - D0 v0 - K q0)
        for i in 0..n {
            let mut lin0 = 0.0;
            for j in 0..n {
                lin0 += (problem.damping[(i, j)] + at.speed * problem.gyroscopic[(i, j)]) * v[j]
                    + problem.stiffness[(i, j)] * q[j];
            }
            w.known[i] = (1.0 + alpha) * w.force[i] - alpha * (w.force_prev[i] + w.nl[i] - lin0);
        }
        // Predictor: constant acceleration.
        for i in 0..n {
            q1[i] = q[i] + h * v[i] + 0.5 * h * h * a[i];
        }
        let mut converged = false;
        for _ in 0..30 {
            for i in 0..n {
                w.a1[i] = (q1[i] - q[i] - h * v[i]) / (beta * h * h) - (0.5 / beta - 1.0) * a[i];
                w.v1[i] = v[i] + h * ((1.0 - gamma) * a[i] + gamma * w.a1[i]);
            }
            w.nl.iter_mut().for_each(|x| *x = 0.0);
            problem.add_nonlinear(&at1, &q1, &w.v1, &mut w.nl, &mut scratch);
            let mut norm_r = 0.0f64;
            for i in 0..n {
                let mut r = -w.known[i] - (1.0 + alpha) * w.nl[i];
                for j in 0..n {
                    r += problem.mass[(i, j)] * w.a1[j]
                        + (1.0 + alpha)
                            * ((problem.damping[(i, j)] + at1.speed * problem.gyroscopic[(i, j)])
                                * w.v1[j]
                                + problem.stiffness[(i, j)] * q1[j]);
                }
                w.residual[i] = r;
                norm_r = norm_r.max(r.abs());
            }
            if !(linear && cached.is_some()) {
                let j = jacobian(
                    problem,
                    &at1,
                    &q1,
                    &w.v1,
                    alpha,
                    gamma,
                    beta,
                    h,
                    &mut scratch,
                );
                cached = Some(j.partial_piv_lu());
            }
            let Some(lu) = cached.as_ref() else {
                break;
            };
            for i in 0..n {
                dq[(i, 0)] = -w.residual[i];
            }
            faer::linalg::solvers::Solve::solve_in_place(lu, dq.as_mut());
            let mut norm_dq = 0.0f64;
            let mut norm_q = 0.0f64;
            for i in 0..n {
                q1[i] += dq[(i, 0)];
                norm_dq = norm_dq.max(dq[(i, 0)].abs());
                norm_q = norm_q.max(q1[i].abs());
            }
            if !norm_dq.is_finite() || !norm_r.is_finite() {
                break;
            }
            // A linear step is solved exactly by its first Newton iteration.
            if linear || norm_dq <= 1e-10 * norm_q + 1e-15 {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(Error::Numerical(format!(
                "Newmark's Newton iterations did not converge at t = {t1:.6} s; reduce the time step"
            )));
        }
        for i in 0..n {
            w.a1[i] = (q1[i] - q[i] - h * v[i]) / (beta * h * h) - (0.5 / beta - 1.0) * a[i];
            v[i] += h * ((1.0 - gamma) * a[i] + gamma * w.a1[i]);
        }
        q.copy_from_slice(&q1);
        a.copy_from_slice(&w.a1);
        w.nl.iter_mut().for_each(|x| *x = 0.0);
        problem.add_nonlinear(&at1, &q, &v, &mut w.nl, &mut scratch);
        std::mem::swap(&mut w.force, &mut w.force_prev);
        at = at1;
        if step % 64 == 0 {
            check_state(t1, &q, options.divergence_bound)?;
        }
        observe(t1, &q, &v);
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn jacobian(
    problem: &mut TimeProblem,
    at: &super::Kinematics,
    q: &[f64],
    v: &[f64],
    alpha: f64,
    gamma: f64,
    beta: f64,
    h: f64,
    scratch: &mut super::NlScratch,
) -> Mat<f64> {
    let n = problem.size();
    let mut kt = Mat::<f64>::zeros(n, n);
    let mut ct = Mat::<f64>::zeros(n, n);
    problem.add_nonlinear_tangent(at, q, v, &mut kt, &mut ct, scratch);
    Mat::from_fn(n, n, |i, j| {
        problem.mass[(i, j)] / (beta * h * h)
            + (1.0 + alpha)
                * ((problem.damping[(i, j)] + at.speed * problem.gyroscopic[(i, j)] + ct[(i, j)])
                    * gamma
                    / (beta * h)
                    + problem.stiffness[(i, j)]
                    + kt[(i, j)])
    })
}

/// a = M^-1 (F + F_nl - D v - K q).
fn acceleration(
    problem: &TimeProblem,
    q: &[f64],
    v: &[f64],
    f: &[f64],
    nl: &[f64],
    speed: f64,
) -> Vec<f64> {
    let n = problem.size();
    let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
        f[i] + nl[i]
            - (0..n)
                .map(|j| {
                    (problem.damping[(i, j)] + speed * problem.gyroscopic[(i, j)]) * v[j]
                        + problem.stiffness[(i, j)] * q[j]
                })
                .sum::<f64>()
    });
    let lu = problem.mass.partial_piv_lu();
    faer::linalg::solvers::Solve::solve_in_place(&lu, rhs.as_mut());
    (0..n).map(|i| rhs[(i, 0)]).collect()
}
