//! Harmonic balance (thesis 4.3, docs/theory.md section 7): periodic responses of
//!
//! ```text
//! M q'' + (C + w G) q' + K q = F_0 + Re((f w^2 + h) e^{i w t}) + F_nl(q, q', t)
//! ```
//!
//! at the excitation frequency w, which is also the spin speed (synchronous response). f is
//! the unbalance phasor per w^2 (as in [`crate::system::System`], which holds both) and h a force phasor of
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
//! - [`sweep()`]: a model's periodic response over a speed range, as `whirl hbm` runs it;
//!   [`SweepReport`]: what it reports (summary and tables); [`SweepSettings`]: its settings
//!   as a request gives them, each with its default; [`HbmRequest`]: the whole `whirl hbm`
//!   run (sweep, time-marching comparisons, harmonic-count study) as one request.
//! - [`stability`]: the Floquet multipliers of each periodic solution, from its monodromy
//!   matrix; [`bifurcation`]: where and how stability changes, named by the crossing
//!   multiplier (fold or symmetry breaking, period doubling, Neimark-Sacker);
//!   [`resolution`]: whether each holds at twice the AFT samples.
//!
//! Nonlinear forces are seen only through [`crate::force::NonlinearForce`], the interface the
//! time integrators use, so every contact law works in both.
//!
//! Inside, one concept a file, each importing only [`fourier`] and those listed before it:
//! `newton` (when a Newton run gives up, the line search); `balance/` (the problem and
//! Newton at one frequency; `linear`: the linear part per harmonic; `aft`: the nonlinear
//! forces); [`stability`]; `condensation/` (the problem and its condensations; `block`: one
//! harmonic's block condensed; `residual`: residual, Jacobian, Newton, recovery;
//! `matrices`); `periodic` (the [`Periodic`] trait both problems answer); `arclength`
//! (scales, tangent, corrector); `branch` (what a path gives: [`Branch`], [`Bifurcation`],
//! [`Resolution`]); `parallel` (jobs over copies of a problem); [`bifurcation`],
//! [`resolution`]; and [`continuation`](mod@continuation)`/` (`path`: the path follower, a
//! state advanced by named steps; `restart`: corners and restarts; `fold`; `crossing`: the
//! solutions at one speed).

mod arclength;
mod balance;
pub mod bearings;
pub mod bifurcation;
mod branch;
pub mod compare;
mod condensation;
pub mod continuation;
pub mod fourier;
mod newton;
mod parallel;
mod periodic;
pub mod report;
pub mod request;
pub mod resolution;
pub mod settings;
pub mod stability;
pub mod sweep;

pub use balance::{HarmonicBalance, HbSolution, Linearisation};
pub use bearings::{CageKind, CageModel, CagedBearing, DEFAULT_CAGE_POSITIONS};
pub use bifurcation::{Bifurcation, BifurcationKind};
pub use compare::{settled_response, MarchSettings, SettledResponse};
pub use condensation::{Condensed, CondensedBalance, DEFAULT_STABILITY_MODES};
pub use continuation::{
    continuation, resume, solutions_at, Branch, BranchEnd, BranchPoint, ContinuationOptions,
    Crossing, Derivatives, Fold, Periodic, SolutionsAt,
};
pub use fourier::{aliasing_free_samples, check_counts, MAX_HARMONICS, MAX_SAMPLES};
pub use report::SweepReport;
pub use request::{HbmRequest, DEFAULT_LOW_SPEED, HBM_OPTIONS};
pub use resolution::{Resolution, RESOLUTION_TOLERANCE};
pub use settings::{SweepSettings, DEFAULT_HARMONICS};
pub use stability::{FloquetProblem, OrbitMode, Stability};
pub use sweep::{
    sweep, sweep_with_progress, AtSpeed, Sweep, SweepOptions, DEFAULT_CONTACT,
    DEFAULT_CONTACT_SMOOTHING,
};

/// Discretisation and Newton-Raphson settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct HbOptions {
    /// Number of harmonics H of the excitation frequency.
    pub harmonics: usize,
    /// Time samples per period N of the AFT; must exceed 2H ([`default_samples`]).
    pub samples: usize,
    /// Convergence: |residual| <= tolerance (|L x| + |F_ext| + |F_nl|), the size of the
    /// terms that must cancel.
    pub tolerance: f64,
    /// Newton iterations before giving up.
    pub max_iterations: usize,
}

impl HbOptions {
    /// H harmonics on [`default_samples`]. The tolerance, 1e-10, is a few hundred times the
    /// round-off of the residual's sums.
    pub fn new(harmonics: usize) -> HbOptions {
        HbOptions {
            harmonics,
            samples: default_samples(harmonics),
            tolerance: 1e-10,
            max_iterations: 30,
        }
    }
}

/// AFT samples per period for H harmonics, the one default of the library, `whirl hbm` and
/// Python: 32 per harmonic and at least 64. Contact forces switch on and off within a
/// period, so their spectra decay slowly and aliasing, not the polynomial rule of
/// [`aliasing_free_samples`], sets the count (which it exceeds for every H: forces up to
/// quintic come out exact). Chosen on the reference rotor (20 um, H = 5, 1-750 Hz, each
/// bifurcation checked at twice the count, docs/theory.md section 7): 80 samples left 5
/// of 19 bifurcations unresolved, 160 left 3 of 19 and 320 left 6 of 19, at 21.1, 24.0
/// and 35.8 s of CPU (BENCHMARKS.md, harmonic balance); the orbits agree within 0.08 % from 80 to
/// 640.
pub fn default_samples(harmonics: usize) -> usize {
    (32 * harmonics).max(64)
}
