//! The nonlinear forces by the alternating frequency-time transform: the motion sampled
//! over one period, the forces and their tangents evaluated at every sample (on several
//! threads, added in their order), and their Galerkin projections back onto the harmonics.

use super::{HarmonicBalance, SampledTangents};
use crate::force::{Kinematics, NonlinearForce};
use crate::hbm::fourier::{cos_slot, sin_slot, slot_basis};
use faer::Mat;
use rayon::prelude::*;

/// One nonlinear force's part of an AFT: its coordinates' motion at the sample in hand, and
/// its values (k per sample) or tangents (k x k per sample, row-major) at every sample, so
/// that the forces are evaluated on several threads and then added in their order.
pub(super) struct ForceSamples {
    q: Vec<f64>,
    v: Vec<f64>,
    values: Vec<f64>,
    dq: Vec<f64>,
    dv: Vec<f64>,
}

impl ForceSamples {
    /// Buffers for a force on `k` coordinates over `samples` samples.
    pub(super) fn new(k: usize, samples: usize) -> ForceSamples {
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

/// Whether `a` and `b` hold the same values to the bit.
fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

impl HarmonicBalance {
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
    pub(super) fn nonlinear_force(&mut self, x: &[f64], frequency: f64) -> Vec<f64> {
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
    pub(super) fn nonlinear_galerkin(&mut self, x: &[f64], frequency: f64) -> (Mat<f64>, Mat<f64>) {
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
