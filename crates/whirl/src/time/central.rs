//! Explicit central difference (the thesis' "explicit Newmark", eqs. 4.1-4.3):
//!
//! ```text
//! (M/h^2 + D/2h) q_{n+1} = F_n - (K - 2M/h^2) q_n - (M/h^2 - D/2h) q_{n-1},  D = C + Omega G
//! q_{-1} = q_0 - h q'_0 + h^2/2 q''_0                                         (eq. 4.2)
//! ```
//!
//! The left-hand matrix is factorised once per speed and the step is written as
//! q_{n+1} = P q_n + Q q_{n-1} + S F_n with P, Q, S formed once, so a step costs two small
//! matrix-vector products and allocates nothing. Nonlinear forces are evaluated at q_n with
//! the backward-difference velocity (q_n - q_{n-1}) / h, which keeps the method explicit.
//!
//! Stability: h < 2 / w_max, w_max the highest natural frequency of (K + K_nl, M) with the
//! nonlinear forces' largest tangent stiffness. A larger step is refused with the limit in
//! the message (SPEC section 7). During a speed ramp the change of Omega G since the last
//! factorisation acts as an explicit force, and the matrices are rebuilt whenever the speed
//! has moved by 1 % of the top speed.

use faer::Mat;

use super::problem::{Dense, TimeProblem};
use super::{check_state, MarchOptions, Observer};
use crate::error::{Error, Result};
use crate::reduce::explicit_stability_limit;

/// The step matrices at one speed.
struct StepMatrices {
    speed: f64,
    p: Dense,
    q: Dense,
    s: Dense,
}

fn step_matrices(problem: &TimeProblem, speed: f64, h: f64) -> Result<StepMatrices> {
    let n = problem.size();
    let (m, k) = (&problem.mass, &problem.stiffness);
    let d = |i: usize, j: usize| problem.damping[(i, j)] + speed * problem.gyroscopic[(i, j)];
    let lhs = Mat::<f64>::from_fn(n, n, |i, j| m[(i, j)] / (h * h) + d(i, j) / (2.0 * h));
    let lu = lhs.partial_piv_lu();
    let solve = |rhs: Mat<f64>| {
        let mut x = rhs;
        faer::linalg::solvers::Solve::solve_in_place(&lu, x.as_mut());
        x
    };
    let s = solve(Mat::<f64>::identity(n, n));
    if s.col_iter().any(|c| c.iter().any(|v| !v.is_finite())) {
        return Err(Error::Numerical(
            "the central-difference matrix M/h^2 + D/2h is singular".into(),
        ));
    }
    let p = &s * Mat::<f64>::from_fn(n, n, |i, j| 2.0 * m[(i, j)] / (h * h) - k[(i, j)]);
    let q = &s * Mat::<f64>::from_fn(n, n, |i, j| d(i, j) / (2.0 * h) - m[(i, j)] / (h * h));
    Ok(StepMatrices {
        speed,
        p: Dense::from_mat(&p),
        q: Dense::from_mat(&q),
        s: Dense::from_mat(&s),
    })
}

/// The largest stable step for this problem, s.
pub fn central_difference_limit(problem: &TimeProblem) -> Result<f64> {
    let n = problem.size();
    let all: Vec<usize> = (0..n).collect();
    let bound = problem.nonlinear_stiffness_bound();
    let system = crate::fe::SystemMatrices {
        mass: problem.mass.clone(),
        stiffness: problem.stiffness.clone(),
        gyroscopic: problem.gyroscopic.clone(),
        damping: problem.damping.clone(),
    };
    explicit_stability_limit(&system, Some((&all, &bound)))
}

/// Marches `problem` from (q0, v0) with the central difference; `observe` sees every step.
pub fn central_difference(
    problem: &mut TimeProblem,
    q0: &[f64],
    v0: &[f64],
    options: &MarchOptions,
    observe: Observer<'_>,
) -> Result<()> {
    problem.check()?;
    let h = options.step;
    let limit = central_difference_limit(problem)?;
    if h >= limit {
        return Err(Error::Numerical(format!(
            "the time step {h:.3e} s is above the central difference's stability limit \
             {limit:.3e} s (2 / w_max, w_max = {:.4e} rad/s with the contacts' tangent \
             stiffness): use a step below {limit:.3e} s, reduce the model (Craig-Bampton \
             removes the highest frequencies), or use the implicit Newmark method",
            2.0 / limit
        )));
    }
    let n = problem.size();
    let mut scratch = problem.scratch();
    let mut force = vec![0.0; n];
    let mut q_prev = vec![0.0; n];
    let mut q_cur = q0.to_vec();
    let mut q_next = vec![0.0; n];
    let mut v_back = v0.to_vec();
    let mut v_central = vec![0.0; n];

    // q_{-1} from eq. 4.2 with the initial acceleration from the equation of motion.
    let at0 = problem.external_force(0.0, &mut force);
    problem.add_nonlinear(&at0, q0, v0, &mut force, &mut scratch);
    let a0 = initial_acceleration(problem, q0, v0, &force, at0.speed)?;
    for i in 0..n {
        q_prev[i] = q0[i] - h * v0[i] + 0.5 * h * h * a0[i];
    }

    let top = problem.speed.max_speed().max(1.0);
    let mut mats = step_matrices(problem, at0.speed, h)?;
    for step in 0..options.steps {
        let t = step as f64 * h;
        let at = problem.external_force(t, &mut force);
        if step > 0 {
            for i in 0..n {
                v_back[i] = (q_cur[i] - q_prev[i]) / h;
            }
        }
        problem.add_nonlinear(&at, &q_cur, &v_back, &mut force, &mut scratch);
        if !problem.speed.is_constant() {
            if (at.speed - mats.speed).abs() > 0.01 * top {
                mats = step_matrices(problem, at.speed, h)?;
            }
            let dw = at.speed - mats.speed;
            for i in 0..n {
                let gv: f64 = (0..n).map(|j| problem.gyroscopic[(i, j)] * v_back[j]).sum();
                force[i] -= dw * gv;
            }
        }
        q_next.iter_mut().for_each(|x| *x = 0.0);
        mats.p.mul_add(&q_cur, &mut q_next);
        mats.q.mul_add(&q_prev, &mut q_next);
        mats.s.mul_add(&force, &mut q_next);
        for i in 0..n {
            v_central[i] = (q_next[i] - q_prev[i]) / (2.0 * h);
        }
        if step % 64 == 0 {
            check_state(t, &q_cur, options.divergence_bound)?;
        }
        observe(t, &q_cur, &v_central);
        std::mem::swap(&mut q_prev, &mut q_cur);
        std::mem::swap(&mut q_cur, &mut q_next);
    }
    Ok(())
}

/// q''_0 = M^-1 (F_0 - K q_0 - D v_0).
fn initial_acceleration(
    problem: &TimeProblem,
    q0: &[f64],
    v0: &[f64],
    force: &[f64],
    speed: f64,
) -> Result<Vec<f64>> {
    let n = problem.size();
    let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
        force[i]
            - (0..n)
                .map(|j| {
                    problem.stiffness[(i, j)] * q0[j]
                        + (problem.damping[(i, j)] + speed * problem.gyroscopic[(i, j)]) * v0[j]
                })
                .sum::<f64>()
    });
    let lu = problem.mass.partial_piv_lu();
    faer::linalg::solvers::Solve::solve_in_place(&lu, rhs.as_mut());
    Ok((0..n).map(|i| rhs[(i, 0)]).collect())
}
