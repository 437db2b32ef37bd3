//! The linear system every solver works on, with its loads and nonlinear forces:
//!
//! ```text
//! M q'' + (C + Omega G) q' + K q = F_0 + Re((f (Omega^2 - i Omega') + h) e^{i phi}) + sum F_nl(q, q', t)
//! ```
//!
//! in the solver's coordinates (physical DOFs, or Craig-Bampton reduced). F_0 is constant
//! (gravity), f the unbalance phasor per Omega^2 (see [`crate::fe::unbalance_force`]) and h a
//! force phasor of fixed amplitude (a shaker, or the Duffing test's F cos(w t)); the Omega'
//! term is the tangential force of an unbalance on a shaft that speeds up. The gyroscopic
//! effect of angular acceleration (a stiffness proportional to Omega') is neglected, as is
//! usual for run-ups.
//!
//! [`build`] makes the [`System`] of a model (full or reduced, with the contact forces);
//! time marching ([`crate::time`]) and harmonic balance ([`crate::hbm`]) both start from it.
//! Data flows one way: [`crate::model::Model`] -> [`crate::fe::assemble`] -> [`build`] ->
//! [`System`] -> solver.

mod build;
mod speed;

pub(crate) use build::{banded, RecoveryRow};
pub use build::{build, linear, Built, Coordinates, Linear};
pub use speed::SpeedProfile;

use faer::Mat;

use crate::error::{Error, Result};
use crate::fe::SystemMatrices;
use crate::force::{Kinematics, NonlinearForce};

/// The linear system M, C, G, K with its loads and nonlinear forces (see the module
/// documentation), in the solver's coordinates.
pub struct System {
    /// M, K, G and C (without the nonlinear forces).
    pub matrices: SystemMatrices,
    /// Constant force F_0 (gravity), N.
    pub constant_force: Vec<f64>,
    /// Real part of the unbalance phasor f per Omega^2, kg m.
    pub unbalance_re: Vec<f64>,
    /// Imaginary part of the unbalance phasor f per Omega^2, kg m.
    pub unbalance_im: Vec<f64>,
    /// Real part of the fixed-amplitude force phasor h, N (harmonic balance only: time
    /// marching refuses a nonzero h).
    pub harmonic_re: Vec<f64>,
    /// Imaginary part of the fixed-amplitude force phasor h, N.
    pub harmonic_im: Vec<f64>,
    /// Nonlinear forces.
    pub nonlinear: Vec<Box<dyn NonlinearForce>>,
}

impl System {
    /// The system of `matrices` with no loads and no nonlinear forces.
    pub fn unloaded(matrices: SystemMatrices) -> System {
        let n = matrices.dofs();
        System {
            matrices,
            constant_force: vec![0.0; n],
            unbalance_re: vec![0.0; n],
            unbalance_im: vec![0.0; n],
            harmonic_re: vec![0.0; n],
            harmonic_im: vec![0.0; n],
            nonlinear: Vec::new(),
        }
    }

    /// True when the fixed-amplitude force h is nonzero somewhere.
    pub fn has_harmonic_force(&self) -> bool {
        self.harmonic_re
            .iter()
            .chain(&self.harmonic_im)
            .any(|&h| h != 0.0)
    }

    /// The acceleration M^-1 (F - (C + Omega G) v - K q) under the total force `force`
    /// (external and nonlinear), used to start the integrators.
    pub(crate) fn acceleration(&self, q: &[f64], v: &[f64], force: &[f64], speed: f64) -> Vec<f64> {
        let n = self.size();
        let m = &self.matrices;
        let mut rhs = Mat::<f64>::from_fn(n, 1, |i, _| {
            force[i]
                - (0..n)
                    .map(|j| {
                        m.stiffness[(i, j)] * q[j]
                            + (m.damping[(i, j)] + speed * m.gyroscopic[(i, j)]) * v[j]
                    })
                    .sum::<f64>()
        });
        faer::linalg::solvers::Solve::solve_in_place(&m.mass.partial_piv_lu(), rhs.as_mut());
        (0..n).map(|i| rhs[(i, 0)]).collect()
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.matrices.dofs()
    }

    /// Checks sizes and the nonlinear forces' coordinates.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when a matrix is not square of the mass matrix's size, a force
    /// vector has another length, or a nonlinear force acts on a coordinate outside the
    /// system.
    pub fn check(&self) -> Result<()> {
        let n = self.size();
        let square = |m: &Mat<f64>| m.nrows() == n && m.ncols() == n;
        let vectors = [
            &self.constant_force,
            &self.unbalance_re,
            &self.unbalance_im,
            &self.harmonic_re,
            &self.harmonic_im,
        ];
        if !self.matrices.all().into_iter().all(square) || vectors.iter().any(|v| v.len() != n) {
            return Err(Error::InvalidOption(
                "the system's matrices and vectors differ in size".into(),
            ));
        }
        for f in &self.nonlinear {
            if let Some(&d) = f.dofs().iter().find(|&&d| d >= n) {
                return Err(Error::InvalidOption(format!(
                    "{} acts on coordinate {d} of {n}",
                    f.name()
                )));
            }
        }
        Ok(())
    }

    /// Linear external force at time t (gravity and unbalance) under the spin `speed`, into
    /// `out`. The fixed-amplitude force h is left out: only harmonic balance, which sets the
    /// frequency it turns at, includes it.
    pub fn external_force(&self, speed: &SpeedProfile, t: f64, out: &mut [f64]) -> Kinematics {
        let (k, [c_re, c_im]) = speed.unbalance_coefficients(t);
        for i in 0..out.len() {
            out[i] =
                self.constant_force[i] + c_re * self.unbalance_re[i] + c_im * self.unbalance_im[i];
        }
        k
    }

    /// The coordinates some nonlinear force acts on, ascending and without repeats.
    pub fn nonlinear_dofs(&self) -> Vec<usize> {
        forces_dofs(&self.nonlinear)
    }

    /// Adds the nonlinear forces at (q, v) into `out`; `scratch_*` hold one force's values.
    pub fn add_nonlinear(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        out: &mut [f64],
        scratch: &mut NlScratch,
    ) {
        add_forces(&mut self.nonlinear, at, q, v, out, scratch);
    }

    /// Total tangent stiffness bound of the nonlinear forces, as a dense matrix.
    pub fn nonlinear_stiffness_bound(&self) -> Mat<f64> {
        let n = self.size();
        let mut k = Mat::<f64>::zeros(n, n);
        for f in &self.nonlinear {
            let dofs = f.dofs();
            let b = f.stiffness_bound();
            let m = dofs.len();
            for a in 0..m {
                for c in 0..m {
                    k[(dofs[a], dofs[c])] += b[a * m + c];
                }
            }
        }
        k
    }

    /// The nonlinear forces' tangents at (q, v) into `block` (see [`TangentBlock`]).
    pub fn nonlinear_tangent(
        &mut self,
        at: &Kinematics,
        q: &[f64],
        v: &[f64],
        block: &mut TangentBlock,
        scratch: &mut NlScratch,
    ) {
        forces_tangent(&mut self.nonlinear, at, q, v, block, scratch);
    }

    /// Work buffers sized for the largest nonlinear force.
    pub fn scratch(&self) -> NlScratch {
        NlScratch::new(&self.nonlinear)
    }

    /// A [`TangentBlock`] for this system's nonlinear forces.
    pub fn tangent_block(&self) -> TangentBlock {
        TangentBlock::new(&self.nonlinear)
    }
}

/// The tangent stiffness -dF/dq and damping -dF/dv of the nonlinear forces, on the only
/// coordinates where they are nonzero: the k that some force acts on (a bearing node's,
/// a housing's). k x k each whatever the model's size, where the full n x n tangents of a
/// 10,000-element rotor would take 12.8 GB each.
#[derive(Debug, Clone)]
pub struct TangentBlock {
    /// The coordinates, ascending (those of [`System::nonlinear_dofs`]).
    pub dofs: Vec<usize>,
    /// -dF/dq, row-major k x k: entry (a, b) couples `dofs[a]` and `dofs[b]`.
    pub stiffness: Vec<f64>,
    /// -dF/dv, row-major k x k.
    pub damping: Vec<f64>,
    /// Per force, the position in `dofs` of each of its coordinates.
    positions: Vec<Vec<usize>>,
}

impl TangentBlock {
    /// The block of `forces`, zero.
    pub(crate) fn new(forces: &[Box<dyn NonlinearForce>]) -> TangentBlock {
        let dofs = forces_dofs(forces);
        let positions = forces
            .iter()
            .map(|f| {
                f.dofs()
                    .iter()
                    .map(|d| dofs.binary_search(d).unwrap_or_default())
                    .collect()
            })
            .collect();
        let k = dofs.len();
        TangentBlock {
            dofs,
            stiffness: vec![0.0; k * k],
            damping: vec![0.0; k * k],
            positions,
        }
    }

    /// k, the number of coordinates.
    pub fn size(&self) -> usize {
        self.dofs.len()
    }
}

/// The coordinates some of `forces` acts on, ascending and without repeats.
pub(crate) fn forces_dofs(forces: &[Box<dyn NonlinearForce>]) -> Vec<usize> {
    let mut dofs: Vec<usize> = forces
        .iter()
        .flat_map(|f| f.dofs().iter().copied())
        .collect();
    dofs.sort_unstable();
    dofs.dedup();
    dofs
}

/// Adds `forces` at (q, v) into `out` (full-size vectors of the coordinates).
pub(crate) fn add_forces(
    forces: &mut [Box<dyn NonlinearForce>],
    at: &Kinematics,
    q: &[f64],
    v: &[f64],
    out: &mut [f64],
    scratch: &mut NlScratch,
) {
    for f in forces.iter_mut() {
        let m = scratch.gather(f.dofs(), q, v);
        f.force(at, &scratch.q[..m], &scratch.v[..m], &mut scratch.f[..m]);
        for a in 0..m {
            out[scratch.idx[a]] += scratch.f[a];
        }
    }
}

/// The tangents of `forces` at (q, v) into `block`, made for them ([`TangentBlock::new`]).
pub(crate) fn forces_tangent(
    forces: &mut [Box<dyn NonlinearForce>],
    at: &Kinematics,
    q: &[f64],
    v: &[f64],
    block: &mut TangentBlock,
    scratch: &mut NlScratch,
) {
    block.stiffness.iter_mut().for_each(|x| *x = 0.0);
    block.damping.iter_mut().for_each(|x| *x = 0.0);
    let k = block.size();
    for (f, positions) in forces.iter_mut().zip(&block.positions) {
        let m = scratch.gather(f.dofs(), q, v);
        f.jacobian(
            at,
            &scratch.q[..m],
            &scratch.v[..m],
            &mut scratch.jq[..m * m],
            &mut scratch.jv[..m * m],
        );
        for a in 0..m {
            for c in 0..m {
                let at = positions[a] * k + positions[c];
                block.stiffness[at] -= scratch.jq[a * m + c];
                block.damping[at] -= scratch.jv[a * m + c];
            }
        }
    }
}

/// Work buffers for evaluating nonlinear forces without allocating.
#[derive(Debug, Clone)]
pub struct NlScratch {
    idx: Vec<usize>,
    q: Vec<f64>,
    v: Vec<f64>,
    f: Vec<f64>,
    jq: Vec<f64>,
    jv: Vec<f64>,
}

impl NlScratch {
    /// Buffers sized for the largest of `forces`.
    pub(crate) fn new(forces: &[Box<dyn NonlinearForce>]) -> NlScratch {
        let m = forces.iter().map(|f| f.dofs().len()).max().unwrap_or(0);
        NlScratch {
            idx: vec![0; m],
            q: vec![0.0; m],
            v: vec![0.0; m],
            f: vec![0.0; m],
            jq: vec![0.0; m * m],
            jv: vec![0.0; m * m],
        }
    }

    /// Copies a force's coordinates and their displacements and velocities; returns the count.
    fn gather(&mut self, dofs: &[usize], q: &[f64], v: &[f64]) -> usize {
        for (a, &d) in dofs.iter().enumerate() {
            self.idx[a] = d;
            self.q[a] = q[d];
            self.v[a] = v[d];
        }
        dofs.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unbalance_coefficients_give_the_complex_force() {
        let problem = System {
            constant_force: vec![1.0, -2.0],
            unbalance_re: vec![0.3, -0.1],
            unbalance_im: vec![0.2, 0.5],
            ..System::unloaded(SystemMatrices {
                mass: Mat::identity(2, 2),
                stiffness: Mat::zeros(2, 2),
                damping: Mat::zeros(2, 2),
                gyroscopic: Mat::zeros(2, 2),
            })
        };
        let speed = SpeedProfile::Ramp {
            from: 10.0,
            to: 300.0,
            start: 0.0,
            duration: 2.0,
        };
        let mut out = [0.0; 2];
        for t in [0.0, 0.7, 1.9, 2.5] {
            let (k, accel) = speed.at(t);
            problem.external_force(&speed, t, &mut out);
            let spin = num_complex::Complex64::new(k.speed * k.speed, -accel)
                * num_complex::Complex64::from_polar(1.0, k.angle);
            for i in 0..2 {
                let f =
                    num_complex::Complex64::new(problem.unbalance_re[i], problem.unbalance_im[i]);
                let expected = problem.constant_force[i] + (f * spin).re;
                // A few roundings of numbers up to 1e5 (Omega^2).
                assert!((out[i] - expected).abs() < 1e-10 * expected.abs().max(1.0));
            }
        }
    }
}
