//! Static equilibrium under the constant load (gravity): K q - F_0 - F_nl(q, 0) = 0,
//! solved by Newton's method with the nonlinear forces' tangent stiffness and a
//! backtracking line search (contacts make the residual only piecewise smooth).

use faer::Mat;

use super::problem::TimeProblem;
use crate::error::{Error, Result};

/// Static equilibrium of `problem` at its initial speed, starting from `guess`.
pub fn static_equilibrium(problem: &mut TimeProblem, guess: &[f64]) -> Result<Vec<f64>> {
    problem.check()?;
    let n = problem.size();
    let (at, _) = problem.speed.at(0.0);
    let at = super::Kinematics {
        time: 0.0,
        speed: at.speed,
        angle: 0.0,
    };
    let zero = vec![0.0; n];
    let mut scratch = problem.scratch();
    let residual = |p: &mut TimeProblem, q: &[f64], s: &mut super::NlScratch| -> Vec<f64> {
        let mut r: Vec<f64> = (0..n)
            .map(|i| -p.constant_force[i] + (0..n).map(|j| p.stiffness[(i, j)] * q[j]).sum::<f64>())
            .collect();
        let mut f = vec![0.0; n];
        p.add_nonlinear(&at, q, &zero, &mut f, s);
        r.iter_mut().zip(&f).for_each(|(ri, fi)| *ri -= fi);
        r
    };
    let norm = |r: &[f64]| r.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = norm(&problem.constant_force).max(1e-12);
    let mut q = guess.to_vec();
    let mut r = residual(problem, &q, &mut scratch);
    for _ in 0..200 {
        if norm(&r) <= 1e-10 * scale {
            return Ok(q);
        }
        let mut kt = problem.stiffness.clone();
        let mut ct = Mat::<f64>::zeros(n, n);
        problem.add_nonlinear_tangent(&at, &q, &zero, &mut kt, &mut ct, &mut scratch);
        let mut dq = Mat::<f64>::from_fn(n, 1, |i, _| -r[i]);
        faer::linalg::solvers::Solve::solve_in_place(&kt.partial_piv_lu(), dq.as_mut());
        if dq.col(0).iter().any(|v| !v.is_finite()) {
            return Err(Error::Numerical(
                "the static stiffness is singular: the rotor is not held in some direction \
                 (add a bearing, or start from rest)"
                    .into(),
            ));
        }
        // Backtracking: halve the step until the residual falls.
        let mut t = 1.0;
        let current = norm(&r);
        loop {
            let trial: Vec<f64> = (0..n).map(|i| q[i] + t * dq[(i, 0)]).collect();
            let rt = residual(problem, &trial, &mut scratch);
            if norm(&rt) < current || t < 1e-6 {
                q = trial;
                r = rt;
                break;
            }
            t *= 0.5;
        }
    }
    if norm(&r) <= 1e-8 * scale {
        return Ok(q);
    }
    Err(Error::Numerical(format!(
        "the static equilibrium did not converge (residual {:.3e} N against a load of {scale:.3e} N); \
         start from rest instead",
        norm(&r)
    )))
}
