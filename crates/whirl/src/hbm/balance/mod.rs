//! The harmonic balance residual, its exact Jacobian and Newton-Raphson at one frequency.
//!
//! Unknowns x hold the Fourier coefficients of every coordinate, slot by slot
//! (x[slot * n + dof], slots as in [`super::fourier`]). With D = C + w G and
//! Z_r = K - (r w)^2 M, the linear part per harmonic (thesis eqs. 4.15-4.19) is
//!
//! ```text
//! constant:  K a_0
//! cos r:     Z_r a_r + r w D b_r
//! sin r:     Z_r b_r - r w D a_r
//! ```
//!
//! and the residual R(x, w) = L(w) x - F_ext(w) - F_nl(x, w). F_nl comes by AFT: the
//! coordinates that carry nonlinear forces are sampled over one period, the forces evaluated
//! at every sample and transformed back. Its Jacobian is -(G[dF/dq] + G[dF/dv] Nabla), with
//! G[.] the Galerkin matrix of a sampled tangent and Nabla the derivative in the Fourier
//! basis (cos r -> -r w sin r, sin r -> r w cos r).

mod aft;
mod linear;

use aft::ForceSamples;

use faer::Mat;

use super::fourier::{cos_slot, sin_slot, Aft};
use super::newton::{line_search, relative, GiveUp, Residual, FULL_STEPS, LINE_SEARCH_HALVINGS};
use super::HbOptions;
use crate::error::{Error, Result};
use crate::linalg::{norm, solve_dense};
use crate::system::System;

/// A converged periodic solution.
#[derive(Debug, Clone, serde::Serialize)]
pub struct HbSolution {
    /// Excitation frequency w (and spin speed), rad/s.
    pub frequency: f64,
    /// Fourier coefficients x[slot * n + dof]: slot 0 constant, 2r - 1 cos(r w t), 2r
    /// sin(r w t); m or rad.
    pub coefficients: Vec<f64>,
    /// Newton iterations taken.
    pub iterations: usize,
    /// |R| / (|L x| + |F_ext| + |F_nl|) at the solution.
    pub relative_residual: f64,
}

/// The residual's derivatives at (x, w).
pub struct Linearisation {
    /// dR/dx.
    pub jacobian: Mat<f64>,
    /// dR/dw at fixed x.
    pub frequency_derivative: Vec<f64>,
    /// G[dF_nl/dv]: the Galerkin matrix of the velocity tangent, which Hill's method needs
    /// apart from the rest (an independent check of the Floquet stability).
    pub velocity_galerkin: Mat<f64>,
}

/// Tangents of the nonlinear forces sampled over one period: entry (a, c) of dF/dq at
/// sample j in `dq[(a * m + c) * samples + j]`, a and c indexing `dofs` (m of them), likewise
/// dF/dv in `dv`.
pub(crate) struct SampledTangents {
    /// The coordinates the forces act on, ascending.
    pub dofs: Vec<usize>,
    /// Samples per period, at phases 2 pi j / samples.
    pub samples: usize,
    pub dq: Vec<f64>,
    pub dv: Vec<f64>,
}

/// Residual, Jacobian and Newton-Raphson for one problem and discretisation, with the work
/// buffers of the AFT made once.
pub struct HarmonicBalance {
    problem: System,
    options: HbOptions,
    aft: Aft,
    /// The coordinates some nonlinear force acts on, ascending.
    nl_dofs: Vec<usize>,
    /// For each force, the positions of its coordinates in `nl_dofs`.
    local: Vec<Vec<usize>>,
    /// Samples per nonlinear coordinate, `nl_dofs.len()` rows of N.
    q_t: Vec<f64>,
    v_t: Vec<f64>,
    f_t: Vec<f64>,
    /// Tangent samples per pair of nonlinear coordinates, (a * m + c) rows of N.
    jq_t: Vec<f64>,
    jv_t: Vec<f64>,
    /// The orbit and frequency `jq_t` and `jv_t` were sampled at: a path point's tangent
    /// and then its Floquet problem ask for the same samples.
    tangents_at: Option<(Vec<f64>, f64)>,
    /// Each force's arguments, values and tangents over one period.
    per_force: Vec<ForceSamples>,
    /// Coefficients of one coordinate, and a Galerkin block.
    slots_buf: Vec<f64>,
    block: Vec<f64>,
}

impl HarmonicBalance {
    /// Sets up harmonic balance for `problem`.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] from [`System::check`] (sizes that differ, a nonlinear
    /// force on a coordinate outside the problem) and from the set-up of the transforms
    /// (`options.samples` not above twice `options.harmonics`).
    pub fn new(problem: System, options: HbOptions) -> Result<HarmonicBalance> {
        problem.check()?;
        let aft = Aft::new(options.harmonics, options.samples)?;
        let nl_dofs = problem.nonlinear_dofs();
        let local = problem
            .nonlinear
            .iter()
            .map(|f| {
                f.dofs()
                    .iter()
                    // `nl_dofs` holds every one of these, sorted: its position is where it sorts.
                    .map(|d| nl_dofs.partition_point(|k| k < d))
                    .collect()
            })
            .collect();
        let (m, n_t) = (nl_dofs.len(), options.samples);
        let per_force = problem
            .nonlinear
            .iter()
            .map(|f| ForceSamples::new(f.dofs().len(), n_t))
            .collect();
        let slots = 2 * options.harmonics + 1;
        Ok(HarmonicBalance {
            problem,
            options,
            aft,
            nl_dofs,
            local,
            q_t: vec![0.0; m * n_t],
            v_t: vec![0.0; m * n_t],
            f_t: vec![0.0; m * n_t],
            jq_t: vec![0.0; m * m * n_t],
            jv_t: vec![0.0; m * m * n_t],
            tangents_at: None,
            per_force,
            slots_buf: vec![0.0; slots],
            block: vec![0.0; slots * slots],
        })
    }

    /// The same problem sampled `samples` times per period (the resolution check of the
    /// bifurcations solves at twice the count).
    ///
    /// # Errors
    /// As [`Self::new`], for a count not above 2H or above the most.
    pub fn with_samples(self, samples: usize) -> Result<HarmonicBalance> {
        let options = HbOptions {
            samples,
            ..self.options
        };
        HarmonicBalance::new(self.problem, options)
    }

    /// The problem.
    pub fn problem(&self) -> &System {
        &self.problem
    }

    /// The discretisation and Newton settings.
    pub fn options(&self) -> &HbOptions {
        &self.options
    }

    /// Number of unknowns, n (2H + 1).
    pub fn unknowns(&self) -> usize {
        self.problem.size() * self.slots()
    }

    fn slots(&self) -> usize {
        2 * self.options.harmonics + 1
    }

    /// Harmonic balance at frequency w (rad/s) by Newton-Raphson from `guess`: plain
    /// Newton, then, should it fail, Newton with a line search (`line_search`), which
    /// converges where full steps cycle between contact states; either stops early once it
    /// shows it cannot converge (`GiveUp`).
    ///
    /// # Errors
    /// [`Error::NotConverged`] when Newton does not converge within `max_iterations`: an
    /// unconverged point is never returned.
    pub fn solve(&mut self, frequency: f64, guess: &[f64]) -> Result<HbSolution> {
        self.check_arguments(frequency, guess)?;
        self.newton(frequency, guess, FULL_STEPS)
            .or_else(|_| self.newton(frequency, guess, LINE_SEARCH_HALVINGS))
    }

    /// Newton-Raphson at w from `guess`, each step shortened up to `halvings` times.
    fn newton(&mut self, frequency: f64, guess: &[f64], halvings: usize) -> Result<HbSolution> {
        let mut x = guess.to_vec();
        let mut last = f64::NAN;
        let mut taken = 0;
        let mut give_up = GiveUp::new(halvings);
        let mut residual = self.residual(&x, frequency);
        for iteration in 0..=self.options.max_iterations {
            last = relative(&residual);
            taken = iteration;
            if last <= self.options.tolerance {
                return Ok(HbSolution {
                    frequency,
                    coefficients: x,
                    iterations: iteration,
                    relative_residual: last,
                });
            }
            if !last.is_finite() || iteration == self.options.max_iterations || give_up.now(last) {
                break;
            }
            let jacobian = self.linearise(&x, frequency).jacobian;
            let step = solve_dense(&jacobian, &residual.values).ok_or_else(|| {
                Error::singular(
                    "Jacobian",
                    format!(
                        "harmonic balance at {frequency} rad/s: singular Jacobian (a turning \
                     point?); use continuation to pass it"
                    ),
                )
            })?;
            (x, residual) = line_search(&x, &step, &residual, halvings, |trial| {
                self.residual(trial, frequency)
            });
        }
        Err(Error::not_converged(
            "harmonic balance",
            Some(taken),
            Some(last),
            format!(
                "harmonic balance did not converge at {frequency} rad/s after {taken} Newton \
             iterations (relative residual {last:e}, tolerance {:e}); start nearer the \
             solution (continuation with a smaller step), or use more time samples",
                self.options.tolerance
            ),
        ))
    }

    pub(crate) fn check_arguments(&self, frequency: f64, x: &[f64]) -> Result<()> {
        if !(frequency.is_finite() && frequency > 0.0) {
            return Err(Error::InvalidOption(format!(
                "harmonic balance needs a positive excitation frequency, got {frequency} rad/s"
            )));
        }
        if x.len() != self.unknowns() {
            return Err(Error::InvalidOption(format!(
                "harmonic balance has {} unknowns, the guess {}",
                self.unknowns(),
                x.len()
            )));
        }
        Ok(())
    }

    /// R(x, w) and the size of the terms that cancel in it.
    pub(crate) fn residual(&mut self, x: &[f64], frequency: f64) -> Residual {
        let mut linear = vec![0.0; x.len()];
        self.add_linear(x, frequency, &mut linear);
        let external = self.external_force(frequency);
        let nonlinear = self.nonlinear_force(x, frequency);
        let values: Vec<f64> = (0..x.len())
            .map(|i| linear[i] - external[i] - nonlinear[i])
            .collect();
        Residual {
            values,
            scale: norm(&linear) + norm(&external) + norm(&nonlinear),
        }
    }

    /// dR/dx, dR/dw and the velocity Galerkin matrix at (x, w).
    pub fn linearise(&mut self, x: &[f64], frequency: f64) -> Linearisation {
        let (gq, gv) = self.nonlinear_galerkin(x, frequency);
        let mut jacobian = self.linear_matrix(frequency);
        let gv_nabla = self.times_derivative(&gv, frequency);
        jacobian -= &gq;
        jacobian -= &gv_nabla;
        // d/dw at fixed x: the linear operator's and the forcing's explicit dependence, and
        // the nonlinear force's through the velocities, which scale with w (Nabla = w Nabla_1).
        let mut frequency_derivative = vec![0.0; x.len()];
        self.add_linear_frequency_derivative(x, frequency, &mut frequency_derivative);
        let n = self.problem.size();
        for dof in 0..n {
            frequency_derivative[cos_slot(1) * n + dof] -=
                2.0 * frequency * self.problem.unbalance_re[dof];
            frequency_derivative[sin_slot(1) * n + dof] +=
                2.0 * frequency * self.problem.unbalance_im[dof];
        }
        for i in 0..x.len() {
            let through_velocity: f64 = (0..x.len()).map(|j| gv_nabla[(i, j)] * x[j]).sum();
            frequency_derivative[i] -= through_velocity / frequency;
        }
        Linearisation {
            jacobian,
            frequency_derivative,
            velocity_galerkin: gv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::SystemMatrices;
    use crate::force::{Kinematics, NonlinearForce};

    /// A force coupling two coordinates through displacements and velocities, so every
    /// term of the Jacobian (G[dF/dq], G[dF/dv] Nabla, the frequency derivative) is
    /// exercised: F = -(q0^3 + q0^2 v1, q0 q1 v1 + v0^3).
    struct Coupled;

    impl NonlinearForce for Coupled {
        fn name(&self) -> String {
            "coupled test force".into()
        }
        fn dofs(&self) -> &[usize] {
            &[2, 0]
        }
        fn force(&mut self, _: &Kinematics, q: &[f64], v: &[f64], out: &mut [f64]) {
            out[0] = -(q[0].powi(3) + q[0] * q[0] * v[1]);
            out[1] = -(q[0] * q[1] * v[1] + v[0].powi(3));
        }
        fn jacobian(
            &mut self,
            _: &Kinematics,
            q: &[f64],
            v: &[f64],
            dfdq: &mut [f64],
            dfdv: &mut [f64],
        ) {
            dfdq.copy_from_slice(&[
                -(3.0 * q[0] * q[0] + 2.0 * q[0] * v[1]),
                0.0,
                -q[1] * v[1],
                -q[0] * v[1],
            ]);
            dfdv.copy_from_slice(&[0.0, -q[0] * q[0], -3.0 * v[0] * v[0], -q[0] * q[1]]);
        }
        fn stiffness_bound(&self) -> Vec<f64> {
            vec![0.0; 4]
        }
    }

    fn entry(i: usize, j: usize) -> f64 {
        ((i * 7 + j * 13) as f64 * 0.618).sin()
    }

    fn three_dof_problem() -> System {
        let n = 3;
        let symmetric = |scale: f64, diagonal: f64| {
            Mat::from_fn(n, n, |i, j| {
                scale * (entry(i, j) + entry(j, i)) + if i == j { diagonal } else { 0.0 }
            })
        };
        System {
            matrices: SystemMatrices {
                mass: symmetric(0.05, 1.0),
                stiffness: symmetric(0.3, 4.0),
                damping: symmetric(0.02, 0.1),
                gyroscopic: Mat::from_fn(n, n, |i, j| 0.1 * (entry(i, j) - entry(j, i))),
            },
            constant_force: vec![0.1, -0.2, 0.05],
            unbalance_re: vec![0.01, 0.0, 0.02],
            unbalance_im: vec![0.0, 0.03, -0.01],
            harmonic_re: vec![0.3, 0.0, 0.0],
            harmonic_im: vec![0.0, 0.1, 0.0],
            nonlinear: vec![Box::new(Coupled)],
        }
    }

    #[test]
    fn jacobian_matches_central_differences_of_the_residual() {
        // N = 8 < 4H + 1 aliases the cubic terms: the Jacobian must be exact for the
        // sampled residual all the same.
        let options = HbOptions {
            samples: 8,
            ..HbOptions::new(3)
        };
        let mut hb = HarmonicBalance::new(three_dof_problem(), options).unwrap();
        let x: Vec<f64> = (0..hb.unknowns()).map(|i| 0.3 * entry(i, 5)).collect();
        let w = 1.7;
        let lin = hb.linearise(&x, w);
        let h = 1e-6;
        let mut worst: f64 = 0.0;
        for j in 0..x.len() + 1 {
            let at = |sign: f64| {
                let mut x = x.clone();
                let mut w = w;
                match x.get_mut(j) {
                    Some(v) => *v += sign * h,
                    None => w += sign * h,
                }
                (x, w)
            };
            let (xp, wp) = at(1.0);
            let (xm, wm) = at(-1.0);
            let (rp, rm) = (hb.residual(&xp, wp).values, hb.residual(&xm, wm).values);
            for i in 0..x.len() {
                let difference = (rp[i] - rm[i]) / (2.0 * h);
                let exact = match j {
                    j if j < x.len() => lin.jacobian[(i, j)],
                    _ => lin.frequency_derivative[i],
                };
                worst = worst.max((difference - exact).abs());
            }
        }
        // Central differences with h = 1e-6 on O(1) entries: truncation h^2 and round-off
        // 1e-16 / h, both near 1e-10.
        assert!(worst < 1e-8, "worst difference {worst:e}");
    }

    /// A restoring force that saturates, F = -atan(q): far from q = 0 its tangent is so
    /// soft that a full Newton step overshoots to the other side by more than it started
    /// (q = 3 -> -9.5 -> 124 ...), as a step that overshoots a contact's state does.
    struct Saturating;

    impl NonlinearForce for Saturating {
        fn name(&self) -> String {
            "saturating test force".into()
        }
        fn dofs(&self) -> &[usize] {
            &[0]
        }
        fn force(&mut self, _: &Kinematics, q: &[f64], _: &[f64], out: &mut [f64]) {
            out[0] = -q[0].atan();
        }
        fn jacobian(
            &mut self,
            _: &Kinematics,
            q: &[f64],
            _: &[f64],
            dfdq: &mut [f64],
            dfdv: &mut [f64],
        ) {
            dfdq[0] = -1.0 / (1.0 + q[0] * q[0]);
            dfdv[0] = 0.0;
        }
        fn stiffness_bound(&self) -> Vec<f64> {
            vec![1.0]
        }
    }

    #[test]
    fn the_line_search_converges_where_full_newton_steps_run_away() {
        // One coordinate held by the saturating force alone (no linear spring), unforced:
        // the periodic solution is q = 0. The damping keeps the harmonic blocks regular
        // (w c = 0.5) wherever Newton goes.
        let one = |v: f64| Mat::from_fn(1, 1, |_, _| v);
        let problem = System {
            matrices: SystemMatrices {
                mass: one(1.0),
                stiffness: one(0.0),
                damping: one(1.0),
                gyroscopic: one(0.0),
            },
            constant_force: vec![0.0],
            unbalance_re: vec![0.0],
            unbalance_im: vec![0.0],
            harmonic_re: vec![0.0],
            harmonic_im: vec![0.0],
            nonlinear: vec![Box::new(Saturating)],
        };
        let mut hb = HarmonicBalance::new(problem, HbOptions::new(1)).unwrap();
        let mut guess = vec![0.0; hb.unknowns()];
        guess[0] = 3.0;
        let plain = hb.newton(0.5, &guess, FULL_STEPS);
        assert!(plain.is_err(), "{plain:?}");
        let solution = hb.solve(0.5, &guess).unwrap();
        // Converged to the tolerance 1e-10 of |F_nl| ~ |q| near the root, whose only root
        // is q = 0 (atan is monotone): |q| is of the order of the tolerance.
        assert!(
            solution.coefficients.iter().all(|c| c.abs() < 1e-9),
            "{solution:?}"
        );
    }

    #[test]
    fn newton_refuses_to_return_an_unconverged_point() {
        let options = HbOptions {
            max_iterations: 2,
            ..HbOptions::new(3)
        };
        let mut hb = HarmonicBalance::new(three_dof_problem(), options).unwrap();
        let far = vec![3.0; hb.unknowns()];
        let error = hb.solve(1.7, &far).unwrap_err().to_string();
        assert!(error.contains("did not converge"), "{error}");
        let options = HbOptions::new(3);
        let mut hb = HarmonicBalance::new(three_dof_problem(), options).unwrap();
        let zero = vec![0.0; hb.unknowns()];
        let solution = hb.solve(1.7, &zero).unwrap();
        assert!(solution.relative_residual <= options.tolerance);
    }
}
