//! Harmonic balance (thesis 4.3, docs/theory.md section 7): periodic responses of
//!
//! ```text
//! M q'' + (C + w G) q' + K q = F_0 + Re((f w^2 + h) e^{i w t}) + F_nl(q, q', t)
//! ```
//!
//! at the excitation frequency w, which is also the spin speed (synchronous response). f is
//! the unbalance phasor per w^2 (as in [`crate::time::TimeProblem`]) and h a force phasor of
//! fixed amplitude (a shaker, or the Duffing test's F cos(w t)).
//!
//! - [`fourier`]: the truncated Fourier series of H harmonics (eq. 4.13) and the
//!   alternating frequency-time transforms (eqs. 4.21-4.22).
//! - [`HarmonicBalance`]: the residual per harmonic (eqs. 4.15-4.19), its exact Jacobian
//!   through the same AFT route, and Newton-Raphson at one frequency.
//! - [`CondensedBalance`]: the same on the coordinates that carry nonlinear forces, the
//!   linear rest condensed exactly per harmonic.
//! - [`continuation()`]: pseudo-arclength continuation in w through turning points.
//! - [`bearings`]: roller bearings made periodic in the running speed ([`CageModel`]).
//! - [`compare`]: time marching read in the same terms, to check harmonic balance against.
//! - [`sweep()`]: a model's periodic response over a speed range, as `whirl hbm` runs it.
//! - [`stability`]: Hill's method for each periodic solution; [`bifurcation`]: where and
//!   how it changes, named by the crossing Floquet multiplier (fold or symmetry breaking,
//!   period doubling, Neimark-Sacker).
//!
//! Nonlinear forces are seen only through [`crate::force::NonlinearForce`], the interface the
//! time integrators use, so every contact law works in both.

mod balance;
pub mod bearings;
pub mod bifurcation;
pub mod compare;
mod condensation;
pub mod continuation;
pub mod fourier;
pub mod stability;
pub mod sweep;

pub use balance::{HarmonicBalance, HbSolution, Linearisation};
pub use bearings::{CageModel, CagedBearing};
pub use bifurcation::{Bifurcation, BifurcationKind};
pub use compare::{settled_response, MarchSettings, SettledResponse};
pub use condensation::{Condensed, CondensedBalance, DEFAULT_STABILITY_MODES};
pub use continuation::{
    continuation, resume, solutions_at, Branch, BranchEnd, BranchPoint, ContinuationOptions,
    Crossing, Derivatives, Fold, Periodic,
};
pub use fourier::aliasing_free_samples;
pub use stability::{hill_stability, HillProblem, Stability};
pub use sweep::{sweep, sweep_with_progress, AtSpeed, Sweep, SweepOptions};

use faer::Mat;

use crate::error::{Error, Result};
use crate::force::NonlinearForce;
use crate::time::TimeProblem;

/// The system whose periodic response is sought, in the solver's coordinates.
pub struct HbProblem {
    /// Mass matrix M.
    pub mass: Mat<f64>,
    /// Stiffness matrix K (without the nonlinear forces).
    pub stiffness: Mat<f64>,
    /// Damping matrix C.
    pub damping: Mat<f64>,
    /// Gyroscopic matrix G (times the spin speed w).
    pub gyroscopic: Mat<f64>,
    /// Constant force F_0 (gravity), N.
    pub constant_force: Vec<f64>,
    /// Real part of the unbalance phasor per w^2, kg m.
    pub unbalance_re: Vec<f64>,
    /// Imaginary part of the unbalance phasor per w^2, kg m.
    pub unbalance_im: Vec<f64>,
    /// Real part of the fixed-amplitude force phasor h, N.
    pub harmonic_re: Vec<f64>,
    /// Imaginary part of the fixed-amplitude force phasor h, N.
    pub harmonic_im: Vec<f64>,
    /// Nonlinear forces.
    pub nonlinear: Vec<Box<dyn NonlinearForce>>,
}

impl HbProblem {
    /// The problem of a time integrator (its speed profile is dropped: harmonic balance sets
    /// the speed), with no fixed-amplitude force.
    pub fn from_time_problem(problem: TimeProblem) -> HbProblem {
        let n = problem.size();
        HbProblem {
            mass: problem.mass,
            stiffness: problem.stiffness,
            damping: problem.damping,
            gyroscopic: problem.gyroscopic,
            constant_force: problem.constant_force,
            unbalance_re: problem.unbalance_re,
            unbalance_im: problem.unbalance_im,
            harmonic_re: vec![0.0; n],
            harmonic_im: vec![0.0; n],
            nonlinear: problem.nonlinear,
        }
    }

    /// Number of coordinates.
    pub fn size(&self) -> usize {
        self.mass.nrows()
    }

    /// Checks sizes and the nonlinear forces' coordinates.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when a matrix is not square of the mass matrix's size, a force
    /// vector has another length, or a nonlinear force acts on a coordinate outside the
    /// problem.
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
        if !(square(&self.mass)
            && square(&self.stiffness)
            && square(&self.damping)
            && square(&self.gyroscopic))
            || vectors.iter().any(|v| v.len() != n)
        {
            return Err(Error::InvalidOption(
                "harmonic balance problem matrices and vectors differ in size".into(),
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
}

/// Discretisation and Newton-Raphson settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HbOptions {
    /// Number of harmonics H of the excitation frequency.
    pub harmonics: usize,
    /// Time samples per period N of the AFT; must exceed 2H.
    pub samples: usize,
    /// Convergence: |residual| <= tolerance (|L x| + |F_ext| + |F_nl|), the size of the
    /// terms that must cancel.
    pub tolerance: f64,
    /// Newton iterations before giving up.
    pub max_iterations: usize,
}

impl HbOptions {
    /// H harmonics, sampled free of aliasing for forces up to cubic
    /// ([`aliasing_free_samples`]); non-smooth forces (contact) have harmonics of every
    /// order and need `samples` chosen by a convergence study. The tolerance, 1e-10, is a
    /// few hundred times the round-off of the residual's sums.
    pub fn new(harmonics: usize) -> HbOptions {
        HbOptions {
            harmonics,
            samples: aliasing_free_samples(harmonics, 3),
            tolerance: 1e-10,
            max_iterations: 30,
        }
    }
}
