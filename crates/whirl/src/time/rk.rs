//! Adaptive Runge-Kutta: Dormand-Prince 5(4) with error control (Dormand & Prince 1980;
//! Hairer, Norsett & Wanner, "Solving ODEs I", II.5), on the first-order form
//!
//! ```text
//! q' = v,   v' = M^-1 (F(t) + F_nl(q, v, t) - K q - (C + Omega(t) G) v)
//! ```
//!
//! It is the accuracy reference for the other integrators (thesis table 4.1). Steps adapt
//! to the error estimate of the embedded 4th-order solution and are clipped to land on
//! every output time, where the observer is called; the 5th-order solution is propagated
//! (local extrapolation) and the last stage is reused as the next first one (FSAL).

use faer::Mat;

use super::{check_marchable, check_state, MarchOptions, Observer};
use crate::error::{Error, Result};
use crate::linalg::Dense;
use crate::system::{NlScratch, SpeedProfile, System};

/// Error tolerances: a component passes when |error| <= atol + rtol |y|.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RkTolerances {
    /// Relative tolerance.
    pub relative: f64,
    /// Absolute tolerance on displacements, m (or rad).
    pub displacement: f64,
    /// Absolute tolerance on velocities, m/s (or rad/s).
    pub velocity: f64,
}

impl Default for RkTolerances {
    /// 1e-8 relative; 1e-12 m and 1e-9 m/s absolute (rotor motions are micrometres).
    fn default() -> Self {
        RkTolerances {
            relative: 1e-8,
            displacement: 1e-12,
            velocity: 1e-9,
        }
    }
}

/// What a Runge-Kutta run cost.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct RkStats {
    /// Accepted steps.
    pub accepted: usize,
    /// Rejected steps.
    pub rejected: usize,
    /// Right-hand-side evaluations.
    pub evaluations: usize,
}

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus embedded 4th-order weights.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

struct Rhs {
    minv: Dense,
    minv_k: Dense,
    minv_c: Dense,
    minv_g: Dense,
    force: Vec<f64>,
    scratch: NlScratch,
    speed: SpeedProfile,
    evaluations: usize,
}

impl Rhs {
    fn new(problem: &System, speed: SpeedProfile) -> Result<Rhs> {
        let n = problem.size();
        let lu = problem.matrices.mass.partial_piv_lu();
        let mut minv = Mat::<f64>::identity(n, n);
        faer::linalg::solvers::Solve::solve_in_place(&lu, minv.as_mut());
        if minv.col_iter().any(|c| c.iter().any(|v| !v.is_finite())) {
            return Err(Error::singular(
                "mass matrix",
                "the mass matrix is singular".into(),
            ));
        }
        Ok(Rhs {
            minv_k: Dense::from_mat(&(&minv * &problem.matrices.stiffness)),
            minv_c: Dense::from_mat(&(&minv * &problem.matrices.damping)),
            minv_g: Dense::from_mat(&(&minv * &problem.matrices.gyroscopic)),
            minv: Dense::from_mat(&minv),
            force: vec![0.0; n],
            scratch: problem.scratch(),
            speed,
            evaluations: 0,
        })
    }

    /// dy = f(t, y) for y = (q, v).
    fn eval(&mut self, problem: &mut System, t: f64, y: &[f64], dy: &mut [f64]) {
        self.evaluations += 1;
        let n = problem.size();
        let (q, v) = y.split_at(n);
        let (dq, dv) = dy.split_at_mut(n);
        dq.copy_from_slice(v);
        let at = problem.external_force(&self.speed, t, &mut self.force);
        problem.add_nonlinear(&at, q, v, &mut self.force, &mut self.scratch);
        dv.iter_mut().for_each(|x| *x = 0.0);
        self.minv.mul_add(&self.force, dv);
        // dv -= M^-1 K q + (M^-1 C + Omega M^-1 G) v
        for (i, o) in dv.iter_mut().enumerate() {
            let rk = &self.minv_k.data[i * n..(i + 1) * n];
            let rc = &self.minv_c.data[i * n..(i + 1) * n];
            let rg = &self.minv_g.data[i * n..(i + 1) * n];
            let mut s = 0.0;
            for j in 0..n {
                s += rk[j] * q[j] + (rc[j] + at.speed * rg[j]) * v[j];
            }
            *o -= s;
        }
    }
}

/// Integrates `problem` from (q0, v0), calling `observe` at t = k * options.step.
///
/// # Errors
/// [`Error::InvalidOption`] from [`System::check`] (sizes that differ, a nonlinear
/// force on a coordinate outside the problem); [`Error::Singular`] for a singular mass
/// matrix; [`Error::Diverged`] when the error estimate is not finite or a coordinate leaves
/// `options.divergence_bound` (checked every 64 outputs); [`Error::NotConverged`] when the
/// step falls below round-off (a problem too stiff for an explicit method).
pub fn runge_kutta(
    problem: &mut System,
    q0: &[f64],
    v0: &[f64],
    tolerances: &RkTolerances,
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<RkStats> {
    check_marchable(problem)?;
    let n = problem.size();
    let m = 2 * n;
    let mut rhs = Rhs::new(problem, options.speed)?;
    let mut y: Vec<f64> = q0.iter().chain(v0).copied().collect();
    let mut k: Vec<Vec<f64>> = vec![vec![0.0; m]; 7];
    let mut stage = vec![0.0; m];
    let mut y_new = vec![0.0; m];
    let mut stats = RkStats::default();
    let mut t = 0.0;
    let mut h = options.step.min(1e-6);
    rhs.eval(problem, t, &y, &mut k[0]);
    let scale = |i: usize| {
        if i < n {
            tolerances.displacement
        } else {
            tolerances.velocity
        }
    };

    if observe(0.0, &y[..n], &y[n..]).is_break() {
        stats.evaluations = rhs.evaluations;
        return Ok(stats);
    }
    for out in 1..options.steps {
        let t_out = out as f64 * options.step;
        while t < t_out {
            let last = t + h >= t_out * (1.0 - 1e-14);
            let h_step = if last { t_out - t } else { h };
            for s in 1..7 {
                for i in 0..m {
                    let mut acc = y[i];
                    for (j, kj) in k.iter().enumerate().take(s) {
                        acc += h_step * A[s][j] * kj[i];
                    }
                    stage[i] = acc;
                }
                let rest = &mut k[s..];
                if s < 6 {
                    rhs.eval(problem, t + C[s] * h_step, &stage, &mut rest[0]);
                } else {
                    y_new.copy_from_slice(&stage);
                    rhs.eval(problem, t + h_step, &y_new, &mut rest[0]);
                }
            }
            let mut err = 0.0;
            for i in 0..m {
                let e: f64 = (0..7).map(|s| E[s] * k[s][i]).sum::<f64>() * h_step;
                let sc = scale(i) + tolerances.relative * y[i].abs().max(y_new[i].abs());
                err += (e / sc).powi(2);
            }
            let err = (err / m as f64).sqrt();
            if !err.is_finite() {
                return Err(Error::Diverged {
                    time: t,
                    coordinate: 0,
                    message: format!("the Runge-Kutta solution diverged at t = {t:.6} s"),
                });
            }
            let factor = (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0);
            if err <= 1.0 {
                stats.accepted += 1;
                t += h_step;
                if last {
                    t = t_out;
                }
                std::mem::swap(&mut y, &mut y_new);
                k.swap(0, 6);
                if !last || h_step >= h {
                    h = h_step * factor;
                }
            } else {
                stats.rejected += 1;
                h = h_step * factor.min(1.0);
            }
            if h < 1e-15 * t_out.max(1.0) {
                return Err(Error::not_converged(
                    "Runge-Kutta step control",
                    None,
                    None,
                    format!(
                    "the Runge-Kutta step fell below round-off at t = {t:.6} s: the problem is \
                     too stiff or discontinuous for an explicit method; use Newmark"
                ),
                ));
            }
        }
        if out % 64 == 0 {
            check_state(t, &y[..n], options.divergence_bound)?;
        }
        if observe(t, &y[..n], &y[n..]).is_break() {
            break;
        }
    }
    stats.evaluations = rhs.evaluations;
    Ok(stats)
}
