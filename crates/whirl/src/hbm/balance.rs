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

use faer::Mat;
use rayon::prelude::*;

use super::fourier::{cos_slot, sin_slot, slot_basis, Aft};
use super::HbOptions;
use crate::error::{Error, Result};
use crate::force::{Kinematics, NonlinearForce};
use crate::linalg::{add_product, norm, solve_dense};
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

/// The residual and its size.
pub(crate) struct Residual {
    pub values: Vec<f64>,
    /// |L x| + |F_ext| + |F_nl|.
    pub scale: f64,
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

    /// The damping operator D = C + w G.
    pub(crate) fn damping_operator(&self, frequency: f64) -> Mat<f64> {
        &self.problem.matrices.damping + &self.problem.matrices.gyroscopic * faer::Scale(frequency)
    }

    /// L(w) as a matrix.
    pub(crate) fn linear_matrix(&self, frequency: f64) -> Mat<f64> {
        let n = self.problem.size();
        let p = &self.problem;
        let d = self.damping_operator(frequency);
        let mut l = Mat::zeros(self.unknowns(), self.unknowns());
        for i in 0..n {
            for j in 0..n {
                l[(i, j)] = p.matrices.stiffness[(i, j)];
                for r in 1..=self.options.harmonics {
                    let rw = r as f64 * frequency;
                    let z = p.matrices.stiffness[(i, j)] - rw * rw * p.matrices.mass[(i, j)];
                    let (c, s) = (cos_slot(r) * n, sin_slot(r) * n);
                    l[(c + i, c + j)] = z;
                    l[(s + i, s + j)] = z;
                    l[(c + i, s + j)] = rw * d[(i, j)];
                    l[(s + i, c + j)] = -rw * d[(i, j)];
                }
            }
        }
        l
    }

    /// A Nabla, with Nabla the derivative in the Fourier basis, by moving and scaling
    /// columns: Nabla maps b_r to r w on a_r and a_r to -r w on b_r, so column a_r of the
    /// product is -r w times column b_r of A and column b_r is r w times column a_r. A
    /// dense product would cost (n (2H + 1))^3.
    pub(crate) fn times_derivative(&self, a: &Mat<f64>, frequency: f64) -> Mat<f64> {
        let n = self.problem.size();
        let mut product = Mat::zeros(a.nrows(), a.ncols());
        for r in 1..=self.options.harmonics {
            let rw = r as f64 * frequency;
            for dof in 0..n {
                let (c, s) = (cos_slot(r) * n + dof, sin_slot(r) * n + dof);
                for i in 0..a.nrows() {
                    product[(i, c)] = -rw * a[(i, s)];
                    product[(i, s)] = rw * a[(i, c)];
                }
            }
        }
        product
    }

    /// out += L(w) x, block by block.
    fn add_linear(&self, x: &[f64], frequency: f64, out: &mut [f64]) {
        let n = self.problem.size();
        let p = &self.problem;
        let d = self.damping_operator(frequency);
        let block = |slot: usize| &x[slot * n..(slot + 1) * n];
        add_product(&p.matrices.stiffness, 1.0, block(0), &mut out[..n]);
        for r in 1..=self.options.harmonics {
            let rw = r as f64 * frequency;
            let (c, s) = (cos_slot(r), sin_slot(r));
            for (row, own, other, sign) in [(c, c, s, 1.0), (s, s, c, -1.0)] {
                let out = &mut out[row * n..(row + 1) * n];
                add_product(&p.matrices.stiffness, 1.0, block(own), out);
                add_product(&p.matrices.mass, -rw * rw, block(own), out);
                add_product(&d, sign * rw, block(other), out);
            }
        }
    }

    /// out += dL/dw x.
    fn add_linear_frequency_derivative(&self, x: &[f64], frequency: f64, out: &mut [f64]) {
        let n = self.problem.size();
        let p = &self.problem;
        // d(r w D(w))/dw = r (D + w G) = r (C + 2 w G).
        let d_rwd = &p.matrices.damping + &p.matrices.gyroscopic * faer::Scale(2.0 * frequency);
        let block = |slot: usize| &x[slot * n..(slot + 1) * n];
        for r in 1..=self.options.harmonics {
            let rf = r as f64;
            let (c, s) = (cos_slot(r), sin_slot(r));
            for (row, own, other, sign) in [(c, c, s, 1.0), (s, s, c, -1.0)] {
                let out = &mut out[row * n..(row + 1) * n];
                add_product(
                    &p.matrices.mass,
                    -2.0 * rf * rf * frequency,
                    block(own),
                    out,
                );
                add_product(&d_rwd, sign * rf, block(other), out);
            }
        }
    }

    /// F_ext(w): constant force and the first harmonic of unbalance and fixed forcing;
    /// Re((u + i v) e^{i w t}) = u cos(w t) - v sin(w t).
    fn external_force(&self, frequency: f64) -> Vec<f64> {
        let n = self.problem.size();
        let p = &self.problem;
        let w2 = frequency * frequency;
        let mut f = vec![0.0; self.unknowns()];
        for dof in 0..n {
            f[dof] = p.constant_force[dof];
            f[cos_slot(1) * n + dof] = w2 * p.unbalance_re[dof] + p.harmonic_re[dof];
            f[sin_slot(1) * n + dof] = -(w2 * p.unbalance_im[dof] + p.harmonic_im[dof]);
        }
        f
    }

    /// Samples displacements and velocities of the nonlinear coordinates over one period.
    fn sample_motion(&mut self, x: &[f64], frequency: f64) {
        let n = self.problem.size();
        let n_t = self.aft.samples();
        for (a, &dof) in self.nl_dofs.iter().enumerate() {
            let at = |slot: usize| x[slot * n + dof];
            self.aft
                .synthesise(at, &mut self.q_t[a * n_t..(a + 1) * n_t]);
            // q' = w dq/dtheta: cos r -> r w sin r coefficient -r w a_r, and so on.
            let velocity = |slot: usize| derivative_coefficient(slot, frequency, at);
            self.aft
                .synthesise(velocity, &mut self.v_t[a * n_t..(a + 1) * n_t]);
        }
    }

    /// F_nl(x, w) by AFT, in the unknowns' layout. The tangents at the samples are made in
    /// the same pass and kept for the orbit ([`Self::sample_tangents`]): Newton asks for the
    /// Jacobian at each iterate whose residual it has, and the rollers' law is then
    /// evaluated once for both.
    fn nonlinear_force(&mut self, x: &[f64], frequency: f64) -> Vec<f64> {
        let mut out = vec![0.0; x.len()];
        if self.nl_dofs.is_empty() {
            return out;
        }
        self.sample_motion(x, frequency);
        let n_t = self.aft.samples();
        self.each_sample(frequency, |force, at, j, work| {
            let k = work.q.len();
            let (dq, dv) = (
                &mut work.dq[j * k * k..(j + 1) * k * k],
                &mut work.dv[j * k * k..(j + 1) * k * k],
            );
            let values = &mut work.values[j * k..(j + 1) * k];
            force.force_and_jacobian(at, &work.q, &work.v, values, dq, dv);
        });
        self.gather_tangents(x, frequency);
        // Added sample by sample in the forces' order, as one thread would.
        self.f_t.fill(0.0);
        for j in 0..n_t {
            for (local, work) in self.local.iter().zip(&self.per_force) {
                let k = local.len();
                for (b, &a) in local.iter().enumerate() {
                    self.f_t[a * n_t + j] += work.values[j * k + b];
                }
            }
        }
        let n = self.problem.size();
        for (a, &dof) in self.nl_dofs.iter().enumerate() {
            self.aft
                .analyse(&self.f_t[a * n_t..(a + 1) * n_t], &mut self.slots_buf);
            for (slot, value) in self.slots_buf.iter().enumerate() {
                out[slot * n + dof] = *value;
            }
        }
        out
    }

    /// The tangents dF/dq and dF/dv of the nonlinear forces at the AFT samples of the
    /// orbit x at w, which the Floquet stability integrates over the period.
    pub(crate) fn sampled_tangents(&mut self, x: &[f64], frequency: f64) -> SampledTangents {
        self.sample_tangents(x, frequency);
        SampledTangents {
            dofs: self.nl_dofs.clone(),
            samples: self.aft.samples(),
            dq: self.jq_t.clone(),
            dv: self.jv_t.clone(),
        }
    }

    /// Fills `jq_t` and `jv_t` with the tangents of the nonlinear forces at the AFT samples,
    /// unless the last residual or Jacobian was made at the same orbit and speed.
    fn sample_tangents(&mut self, x: &[f64], frequency: f64) {
        if self
            .tangents_at
            .as_ref()
            .is_some_and(|(at, w)| w.to_bits() == frequency.to_bits() && same_bits(at, x))
        {
            return;
        }
        if self.nl_dofs.is_empty() {
            self.gather_tangents(x, frequency);
            return;
        }
        self.sample_motion(x, frequency);
        self.each_sample(frequency, |force, at, j, work| {
            let kk = work.q.len() * work.q.len();
            let dq = &mut work.dq[j * kk..(j + 1) * kk];
            let dv = &mut work.dv[j * kk..(j + 1) * kk];
            force.jacobian(at, &work.q, &work.v, dq, dv);
        });
        self.gather_tangents(x, frequency);
    }

    /// Adds the forces' tangents at each sample, as the last pass over the samples left
    /// them in the forces' buffers, into `jq_t` and `jv_t`, kept as those of the orbit x at
    /// w.
    fn gather_tangents(&mut self, x: &[f64], frequency: f64) {
        self.tangents_at = Some((x.to_vec(), frequency));
        self.jq_t.fill(0.0);
        self.jv_t.fill(0.0);
        let (n_t, m) = (self.aft.samples(), self.nl_dofs.len());
        // Added sample by sample in the forces' order, as one thread would.
        for j in 0..n_t {
            for (local, work) in self.local.iter().zip(&self.per_force) {
                let k = local.len();
                let (dq, dv) = (&work.dq[j * k * k..], &work.dv[j * k * k..]);
                for (b, &a) in local.iter().enumerate() {
                    for (e, &c) in local.iter().enumerate() {
                        self.jq_t[(a * m + c) * n_t + j] += dq[b * k + e];
                        self.jv_t[(a * m + c) * n_t + j] += dv[b * k + e];
                    }
                }
            }
        }
    }

    /// Runs `evaluate(force, kinematics, j, buffers)` for every force at every sample j of
    /// the motion in `q_t` and `v_t`, the force's motion at j in its buffers' `q` and `v`.
    /// The forces run at once on rayon's threads when there are several (a caged roller
    /// bearing over one period is N samples of 8 cage positions of all its rollers, a
    /// coarse task), else on this thread.
    fn each_sample(
        &mut self,
        frequency: f64,
        evaluate: impl Fn(&mut Box<dyn NonlinearForce>, &Kinematics, usize, &mut ForceSamples) + Sync,
    ) {
        let (q_t, v_t, n_t) = (&self.q_t, &self.v_t, self.aft.samples());
        let run = |((force, local), work): (
            (&mut Box<dyn NonlinearForce>, &Vec<usize>),
            &mut ForceSamples,
        )| {
            for j in 0..n_t {
                work.gather(local, q_t, v_t, n_t, j);
                evaluate(force, &kinematics(j, n_t, frequency), j, work);
            }
        };
        let forces = &mut self.problem.nonlinear;
        if forces.len() > 1 {
            forces
                .par_iter_mut()
                .zip(&self.local)
                .zip(&mut self.per_force)
                .for_each(run);
        } else {
            forces
                .iter_mut()
                .zip(&self.local)
                .zip(&mut self.per_force)
                .for_each(run);
        }
    }

    /// G[dF/dq] and G[dF/dv] in the unknowns' layout.
    fn nonlinear_galerkin(&mut self, x: &[f64], frequency: f64) -> (Mat<f64>, Mat<f64>) {
        let size = self.unknowns();
        let (mut gq, mut gv) = (Mat::zeros(size, size), Mat::zeros(size, size));
        if self.nl_dofs.is_empty() {
            return (gq, gv);
        }
        self.sample_tangents(x, frequency);
        let (n_t, m) = (self.aft.samples(), self.nl_dofs.len());
        let n = self.problem.size();
        let slots = self.slots();
        for a in 0..m {
            for c in 0..m {
                let (row_dof, col_dof) = (self.nl_dofs[a], self.nl_dofs[c]);
                let pair = (a * m + c) * n_t..(a * m + c + 1) * n_t;
                for (samples, target) in [(&self.jq_t, &mut gq), (&self.jv_t, &mut gv)] {
                    if samples[pair.clone()].iter().all(|&v| v == 0.0) {
                        continue;
                    }
                    self.aft.galerkin(&samples[pair.clone()], &mut self.block);
                    for row in 0..slots {
                        for col in 0..slots {
                            target[(row * n + row_dof, col * n + col_dof)] =
                                self.block[row * slots + col];
                        }
                    }
                }
            }
        }
        (gq, gv)
    }
}

/// One nonlinear force's part of an AFT: its coordinates' motion at the sample in hand, and
/// its values (k per sample) or tangents (k x k per sample, row-major) at every sample, so
/// that the forces are evaluated on several threads and then added in their order.
struct ForceSamples {
    q: Vec<f64>,
    v: Vec<f64>,
    values: Vec<f64>,
    dq: Vec<f64>,
    dv: Vec<f64>,
}

impl ForceSamples {
    /// Buffers for a force on `k` coordinates over `samples` samples.
    fn new(k: usize, samples: usize) -> ForceSamples {
        ForceSamples {
            q: vec![0.0; k],
            v: vec![0.0; k],
            values: vec![0.0; k * samples],
            dq: vec![0.0; k * k * samples],
            dv: vec![0.0; k * k * samples],
        }
    }

    /// Takes the motion of the force's coordinates (`local`, positions among the sampled
    /// ones) at sample j from `q_t` and `v_t`, rows of `samples` per coordinate.
    fn gather(&mut self, local: &[usize], q_t: &[f64], v_t: &[f64], samples: usize, j: usize) {
        for (b, &a) in local.iter().enumerate() {
            self.q[b] = q_t[a * samples + j];
            self.v[b] = v_t[a * samples + j];
        }
    }
}

/// Kinematics of sample j of N: phase theta_j = 2 pi j / N, time theta_j / w.
fn kinematics(j: usize, samples: usize, frequency: f64) -> Kinematics {
    let angle = std::f64::consts::TAU * j as f64 / samples as f64;
    Kinematics {
        time: angle / frequency,
        speed: frequency,
        angle,
    }
}

/// Slot `slot` of the derivative d/dt of the series with coefficients `at(slot)`.
fn derivative_coefficient(slot: usize, frequency: f64, at: impl Fn(usize) -> f64) -> f64 {
    match slot_basis(slot) {
        (0, _) => 0.0,
        (r, false) => r as f64 * frequency * at(sin_slot(r)),
        (r, true) => -(r as f64) * frequency * at(cos_slot(r)),
    }
}

/// |R| / scale; zero when every term vanishes (no load, no motion).
pub(crate) fn relative(residual: &Residual) -> f64 {
    let r = norm(&residual.values);
    if r == 0.0 {
        0.0
    } else {
        r / residual.scale
    }
}

/// Halvings of a Newton step before the line search takes the best length it tried: down
/// to 1/256 of the step, short enough to leave a contact state the full step overshoots.
pub(crate) const LINE_SEARCH_HALVINGS: usize = 8;

/// Plain Newton (every step taken whole): no halving.
pub(crate) const FULL_STEPS: usize = 0;

/// When a Newton run that has not converged gives up before `max_iterations`: only once it
/// has shown it cannot converge, so a run that converges takes every iteration it took
/// before and ends where it ended; only the failing runs get cheaper. Counted on the
/// reference rotor's 1-750 Hz sweeps (20 um with stability, 60 and 120 um without; every
/// corrector run of the path and of the fold and bifurcation locators, every Newton run at
/// fixed speed), the runs that failed spent 57-66 % of all condensations (a corrector
/// iteration, and each trial length of its line search, lies at its own speed), and failed
/// in two ways:
///
/// - plain Newton cycles between two contact states: most of the failing runs alternate
///   between two residuals that repeat to round-off from about the sixth iteration to the
///   thirtieth ([`GiveUp::two_cycle`]), the rest wander or run out of the range;
/// - with the line search, the residual creeps down by fractions of a percent, or cycles
///   with a period of 5-10 iterations, never near the tolerance ([`GiveUp::stalled`]).
///
/// Plain runs that converged did so after up to 25 iterations, with excursions up to 1800
/// times their first residual, so no rule on the residual's progress stops plain runs
/// early with a margin: only the cycle does (124 of the 203 failing plain runs, most at
/// the sixth or seventh iteration).
pub(crate) struct GiveUp {
    /// Whether the run shortens its steps (a line search): only then is it stopped
    /// for stalling (plain runs that converged had excursions of up to 20 iterations above
    /// their first residual).
    line_search: bool,
    /// Relative residuals of the iterates so far.
    residuals: Vec<f64>,
}

/// Two residuals closer than this, relative, are the same value repeated: the two-cycles
/// measured end repeating to round-off (44 of the 61 failing plain runs of the 20 and
/// 120 um sweeps) or to 1e-7-3e-6 while still settling onto the cycle; no run that
/// converged, on the three sweeps or in the tests, had two such repeats in a row.
const REPEATS: f64 = 1e-6;

/// Iterations over which a line-search run whose smallest residual has not fallen by
/// [`STALL_GAIN`] gives up. Of the 13 line-search runs that converged on the three sweeps,
/// 12 never went more than 2 iterations without a 10 % gain, one (60 um, 46.04 Hz, 21
/// iterations, creeping by 1-3 % an iteration before converging) went 5; 8 leaves that
/// margin and still stops the failing corrector runs (80-270 condensations each, a median
/// of 161) after a median of 13 iterations instead of 30.
const STALL_WINDOW: usize = 8;

/// The fall of the smallest residual that counts as progress over [`STALL_WINDOW`].
const STALL_GAIN: f64 = 0.9;

impl GiveUp {
    /// For a run whose steps are shortened up to `halvings` times.
    pub(crate) fn new(halvings: usize) -> GiveUp {
        GiveUp {
            line_search: halvings > 0,
            residuals: Vec::new(),
        }
    }

    /// Records the relative residual of the newest iterate, not converged, and says
    /// whether the run should stop there.
    pub(crate) fn now(&mut self, relative: f64) -> bool {
        self.residuals.push(relative);
        self.two_cycle() || (self.line_search && self.stalled())
    }

    /// The last four residuals alternate between two different values: Newton cycles. (A
    /// residual that stays the same is no cycle: where one term dominates the others, the
    /// relative residual stays at 1 while Newton walks to the root.)
    fn two_cycle(&self) -> bool {
        let r = &self.residuals;
        let n = r.len();
        let same = |a: f64, b: f64| (a - b).abs() <= REPEATS * a.abs();
        n >= 4 && same(r[n - 1], r[n - 3]) && same(r[n - 2], r[n - 4]) && !same(r[n - 1], r[n - 2])
    }

    /// The smallest residual has not fallen below [`STALL_GAIN`] of what it was
    /// [`STALL_WINDOW`] iterations before.
    fn stalled(&self) -> bool {
        let n = self.residuals.len();
        let smallest = |r: &[f64]| r.iter().copied().fold(f64::INFINITY, f64::min);
        n > STALL_WINDOW
            && smallest(&self.residuals)
                > STALL_GAIN * smallest(&self.residuals[..n - STALL_WINDOW])
    }
}

/// Armijo's sufficient decrease: the residual must fall by this fraction of what the
/// linear model promises, a weak condition that the full Newton step meets wherever Newton
/// converges quadratically (so converging iterations are unchanged by the search).
const SUFFICIENT_DECREASE: f64 = 1e-4;

/// The next Newton iterate x - lambda d and its residual, by backtracking on |R|: the full
/// step when it lowers |R| enough ([`SUFFICIENT_DECREASE`]), else the step halved, up to
/// `halvings` times, until it does, else the tried length with the smallest finite |R|
/// (with no halving, the full step: plain Newton). Newton on a contact force that switches
/// on and off can cycle between contact states with full steps (each step's linearisation
/// holds in one state only); a shorter step that lowers |R| breaks the cycle. `residual_at`
/// gives R at a trial point (not finite where it cannot be evaluated).
pub(crate) fn line_search(
    x: &[f64],
    d: &[f64],
    current: &Residual,
    halvings: usize,
    mut residual_at: impl FnMut(&[f64]) -> Residual,
) -> (Vec<f64>, Residual) {
    let size = norm(&current.values);
    let mut at = |lambda: f64| {
        let trial: Vec<f64> = x.iter().zip(d).map(|(xi, di)| xi - lambda * di).collect();
        let residual = residual_at(&trial);
        let trial_size = norm(&residual.values);
        let sufficient = trial_size <= (1.0 - SUFFICIENT_DECREASE * lambda) * size;
        (trial, residual, trial_size, sufficient)
    };
    let (trial, residual, trial_size, sufficient) = at(1.0);
    if sufficient {
        return (trial, residual);
    }
    // The full step is kept when no length gives a finite residual (the caller then stops
    // on it); a finite one replaces it, and a smaller one that.
    let mut best = (trial, residual, trial_size);
    let mut lambda = 1.0;
    for _ in 0..halvings {
        lambda /= 2.0;
        let (trial, residual, trial_size, sufficient) = at(lambda);
        if sufficient {
            return (trial, residual);
        }
        if trial_size < best.2 || (trial_size.is_finite() && !best.2.is_finite()) {
            best = (trial, residual, trial_size);
        }
    }
    (best.0, best.1)
}

/// Whether `a` and `b` hold the same values to the bit.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::SystemMatrices;
    use crate::force::NonlinearForce;

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

    /// The iteration (index of the residual) at which [`GiveUp`] stops a run with these
    /// relative residuals, none of them converged; None if it runs them all.
    fn gives_up_at(halvings: usize, residuals: &[f64]) -> Option<usize> {
        let mut give_up = GiveUp::new(halvings);
        residuals.iter().position(|&r| give_up.now(r))
    }

    #[test]
    fn newton_gives_up_on_a_two_cycle_or_a_stalled_line_search_and_never_on_a_slow_convergence() {
        // Relative residuals of corrector runs on the reference rotor's sweeps (the
        // counts in GiveUp's documentation). Plain Newton at 185.03 Hz, 20 um, cycling
        // between two contact states from the fourth iteration: it stops at the seventh,
        // where the last four residuals alternate.
        let (a, b) = (9.463898e-6, 9.420180e-6);
        let mut cycle = vec![6.121659e-3, 6.646233e-5, 9.463291e-6, 9.420219e-6];
        cycle.extend([a, b].repeat(13));
        assert_eq!(gives_up_at(FULL_STEPS, &cycle), Some(7));
        // The line-search run that followed it: a cycle of period 4-5 over 4.2e-6 to
        // 5.2e-6, stopped once its best has not fallen by 10 % in 8 iterations.
        let stalled = [
            6.121659e-3,
            6.646233e-5,
            9.463291e-6,
            9.420219e-6,
            4.733734e-6,
            4.437923e-6,
            4.299261e-6,
            4.265677e-6,
            4.249016e-6,
            5.209792e-6,
            4.885783e-6,
            4.275254e-6,
            4.241860e-6,
            5.216907e-6,
            4.879535e-6,
            4.269790e-6,
        ];
        assert_eq!(gives_up_at(LINE_SEARCH_HALVINGS, &stalled), Some(13));
        // The slowest that converged: plain Newton at 151.86 Hz, 60 um, 25 iterations up
        // and down by up to 50 times its first residual, and a line search at 46.04 Hz,
        // 60 um, creeping by 1-3 % an iteration for 16 iterations (the last residual of
        // each, converged, left out).
        let wandering = [
            5.547826e-3,
            2.445871e-2,
            1.755266e-3,
            2.552512e-2,
            2.326325e-1,
            4.424150e-2,
            7.612341e-3,
            1.756591e-2,
            2.688398e-3,
            9.744496e-3,
            2.939257e-2,
            2.181356e-3,
            1.193341e-2,
            1.651289e-2,
            1.472694e-3,
            8.770716e-3,
            4.911663e-3,
            5.856507e-3,
            3.089925e-3,
            2.935656e-1,
            6.993161e-2,
            1.437615e-2,
            2.009592e-3,
            1.170507e-4,
            3.171623e-7,
        ];
        assert_eq!(gives_up_at(FULL_STEPS, &wandering), None);
        let creeping = [
            3.752332e-3,
            3.717771e-3,
            3.450466e-3,
            3.532954e-3,
            3.536239e-3,
            3.416188e-3,
            3.246943e-3,
            3.200607e-3,
            3.104589e-3,
            3.085152e-3,
            2.370957e-3,
            2.366700e-3,
            2.333748e-3,
            2.230596e-3,
            2.164513e-3,
            2.000171e-3,
            1.971801e-3,
            1.196965e-3,
            1.798222e-4,
            3.981347e-5,
            3.455877e-7,
        ];
        assert_eq!(gives_up_at(LINE_SEARCH_HALVINGS, &creeping), None);
        // A residual that stays put is no cycle (the saturating force below keeps the
        // relative residual at 1 while Newton walks to the root).
        assert_eq!(gives_up_at(FULL_STEPS, &[1.0; 30]), None);
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
