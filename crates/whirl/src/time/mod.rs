//! Time marching (thesis 4.1-4.2, docs/theory.md section 6).
//!
//! - [`central_difference`]: explicit, conditionally stable; refuses an unstable step.
//! - [`newmark`]: implicit Newmark (average acceleration, or HHT-alpha) with Newton
//!   iterations on the nonlinear forces, a line search, and steps halved where the forces
//!   jump; unconditionally stable for the linear part.
//! - [`runge_kutta`]: adaptive Dormand-Prince 5(4) on the first-order form, the accuracy
//!   reference (thesis table 4.1).
//! - [`static_equilibrium`]: Newton on the nonlinear forces under gravity, condensed onto
//!   the coordinates they act on.
//!
//! Every integrator works on a [`crate::system::System`] (matrices in the integrator's
//! coordinates, full or Craig-Bampton reduced, built by [`crate::system::build`]) and sees nonlinear forces only through
//! [`crate::force::NonlinearForce`], so contact laws plug in without changing the
//! integrators. Each
//! calls an observer with (t, q, q') at every step; [`simulate`] builds the problem from a
//! model as one [`SimulationOptions`] says and records named channels.

mod central;
#[cfg(test)]
mod fixtures;
pub mod forcing_fit;
mod newmark;
mod rk;
mod rollers;
mod settled;
mod simulate;
pub(crate) mod statics;

use crate::system::SpeedProfile;
pub use central::{central_difference, central_difference_constrained, central_difference_limit};
pub use forcing_fit::{
    fit_forcing, FitForcingRequest, ForcingFit, ForcingFitOptions, ForcingFitReport, SpeedFit,
    DEFAULT_FIT_DURATION, DEFAULT_FIT_SETTLE, MAX_SAMPLES_PER_SPEED,
};
pub use newmark::{newmark, NewmarkScheme};
pub use rk::{runge_kutta, RkStats, RkTolerances};
pub use rollers::{peak_near, ContactSummary, RollerRecord};
pub use settled::{SettledChannel, MAX_ORDER, MAX_PEAKS, MIN_PEAK_RELATIVE, ORDER_TOLERANCE_BINS};
pub use simulate::{
    order_label, simulate, simulate_with, stable_step, stable_step_of, BearingReport, Channel,
    FrequencyCheck, Hooks, Initial, Integrator, Method, RunStatus, SimulationOptions,
    SimulationReport, SimulationRequest, SimulationResult, SimulationSummary, Until,
    CONTACT_LINE_CAGE_TURNS, DEFAULT_DIVERGENCE_BOUND, DEFAULT_DURATION, DEFAULT_INITIAL,
    DEFAULT_SAMPLE_INTERVAL, DEFAULT_STEP, DIVERGENCE_NET, MATCH_BINS, SIMULATE_OPTIONS,
};
pub use statics::static_equilibrium;

use std::ops::ControlFlow;

use crate::error::{Error, Result};
use crate::system::System;

/// The system's checks, and a refusal of the fixed-amplitude force h, which only harmonic
/// balance (where it turns at the solution's frequency) includes.
pub(crate) fn check_marchable(system: &System) -> Result<()> {
    system.check()?;
    if system.has_harmonic_force() {
        return Err(Error::Unsupported(
            "time marching has no fixed-amplitude harmonic force h: set `harmonic_re` and \
             `harmonic_im` to zero, or solve by harmonic balance"
                .into(),
        ));
    }
    Ok(())
}

/// The central difference runs at this fraction of its stability limit by default
/// ([`stable_step`]): close enough to be cheap, far enough that round-off in the limit
/// does not matter. The one default of `whirl simulate`, the cascade, the forcing-function
/// fit and the harmonic-balance comparison.
pub const STABLE_FRACTION: f64 = 0.9;

/// The most time steps one run may take: 5e8 steps of the reduced reference rotor are about
/// 11 minutes of computing (1.3 us a step), and a mistyped step would otherwise run for days.
pub const MAX_STEPS: f64 = 5e8;

/// The most values (samples times series) one run records, held in memory whole: 2^28
/// values are 2.1 GB. The reduced reference rotor with its rollers records 55 series
/// (time, u_x and u_y of 3 nodes, angle, approach and force of 16 rollers), so this is 4.9
/// million samples: about 170 s of rotor time at its stable step, or 49 s at the default
/// sample interval of 10 us.
pub const MAX_RECORDED_VALUES: usize = 1 << 28;

/// Default number of fixed-interface modes of a run's reduced model.
pub use crate::reduce::DEFAULT_MODES;

/// Spin speed, step size and length of a run.
#[derive(Debug, Clone, Copy)]
pub struct MarchOptions {
    /// Spin speed over time.
    pub speed: SpeedProfile,
    /// Time step (output interval for Runge-Kutta), s.
    pub step: f64,
    /// Number of steps.
    pub steps: usize,
    /// A coordinate larger than this (m or rad) means the run diverged.
    pub divergence_bound: f64,
}

/// Called with (t, q, q') at every step; `ControlFlow::Break(())` ends the march there (the
/// integrator returns as if the run were complete), e.g. once a caller has seen enough.
pub type Observer<'a> = &'a mut dyn FnMut(f64, &[f64], &[f64]) -> ControlFlow<()>;

/// Stops a run that has diverged: a non-finite coordinate or one beyond `bound`.
pub(crate) fn check_state(t: f64, q: &[f64], bound: f64) -> Result<()> {
    if let Some((i, v)) = q
        .iter()
        .enumerate()
        .find(|(_, v)| !v.is_finite() || v.abs() > bound)
    {
        return Err(Error::Diverged {
            time: t,
            coordinate: i,
            message: format!(
                "the solution diverged at t = {t:.6} s: coordinate {i} is {v:e} (bound {bound:e}); \
                 reduce the time step, check the model's supports, or raise the bound if \
                 such motion is expected"
            ),
        });
    }
    Ok(())
}
