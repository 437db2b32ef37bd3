//! A time simulation of a model: build the problem (full or Craig-Bampton reduced), find
//! the initial state, march, and record named channels.
//!
//! With one roller at the bottom the horizontal static position inside the clearance is not
//! unique; the static solve starts from u = 0, so it keeps u_x = 0 (docs/theory.md section 6).
//!
//! One run is described by one [`SimulationOptions`], whose [`SimulationOptions::new`]
//! holds every default; [`simulate`] runs it, and [`simulate_with`] also takes [`Hooks`]: a
//! caller's own nonlinear forces, or a rule that ends the run once it has recorded enough.
//! [`stable_step`] gives the central difference's stability limit of the model exactly as
//! [`simulate`] will integrate it, so a caller can choose a step before running.
//!
//! [`simulate`] models the roller bearings by a [`ContactLaw`] and records, besides the
//! channels, what each roller did ([`RollerRecord`]; [`SimulationOptions::record_rollers`]):
//! its angle, its approach and its force, evaluated from the bearing node's recorded
//! displacement and velocity with the bearing's own kinematics (for the Hertz law exactly
//! the force the integrator applied, up to the velocity: the integrator uses the backward
//! difference, the record the central one). It records every `record_every`-th step only,
//! so long runs of the full model stay small.
//!
//! With [`ContactLaw::Lagrange`] the rollers are rigid constraints on the central
//! difference ([`central_difference_constrained`]) and the recorded forces are the
//! multipliers. The explicit stability limit is the unconstrained rotor's. The static
//! start on rigid rollers is approached by the Hertz equilibrium with contacts
//! `RIGID_STIFFENING` (1e4) times stiffer (its sub-nanometre penetration is removed by the
//! first correction).
//!
//! # Divergence
//!
//! A run has diverged when a recorded translation (u_x or u_y of a recorded node; a
//! contact run always records its bearing nodes) leaves +-`divergence_bound`, checked at
//! the start and at every recorded sample, and the message names that DOF (`n0.uy`). Only
//! physical translations are held to the bound: rotations (rad) and a reduced model's
//! modal coordinates (m kg^1/2) have other units and sizes. As a safety net for motion that
//! grows away from the recorded nodes, any integrated coordinate beyond
//! [`DIVERGENCE_NET`] times the bound, or not finite, also stops the run (the integrators
//! check that every 64 steps or so), and the message names the coordinate: a DOF such as
//! `n7.tx`, or a fixed-interface mode of the reduction.

mod contacts;
mod report;
mod request;

pub use report::{
    order_label, BearingReport, FrequencyCheck, SimulationReport, SimulationSummary,
    CONTACT_LINE_CAGE_TURNS, MATCH_BINS,
};
pub use request::{Integrator, SimulationRequest, SIMULATE_OPTIONS};

use std::ops::ControlFlow;
use std::time::Instant;

use serde::Serialize;

use super::central::{
    central_difference, central_difference_constrained, central_difference_limit,
};
use super::newmark::{newmark, NewmarkScheme};
use super::rk::{runge_kutta, RkStats, RkTolerances};
use super::rollers::RollerRecord;
use super::statics::static_equilibrium;
use super::{MarchOptions, STABLE_FRACTION};
use crate::bearing::ContactLaw;
use crate::error::{Error, InputError, Result};
use crate::fe::{dof, Bearings, Direction, DofNames};
use crate::force::ForceBuilder;
use crate::model::Model;
use crate::progress::{tell, Progress};
use crate::system::{build, linear, Built, Linear, RecoveryRow, SpeedProfile, System};
use contacts::{
    fill_multipliers, lagrange_contacts, recorded_nodes, rigid_static_equilibrium, RollerProbe,
};

/// Any integrated coordinate beyond this many times the divergence bound stops a run (the
/// safety net of the module documentation). A mass-normalised modal coordinate is at most
/// about sqrt(rotor mass) times the largest displacement (6 for the reference rotor's
/// 35 kg) and a slope about pi / span times it, so the net never fires before the recorded
/// translations would on a rotor whose recorded nodes move with the rest.
pub const DIVERGENCE_NET: f64 = 1e3;

/// Which integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Explicit central difference.
    CentralDifference,
    /// Implicit Newmark.
    Newmark(NewmarkScheme),
    /// Adaptive Dormand-Prince 5(4).
    RungeKutta(RkTolerances),
}

impl Method {
    /// Short name.
    pub fn name(&self) -> &'static str {
        match self {
            Method::CentralDifference => "central difference",
            Method::Newmark(_) => "newmark",
            Method::RungeKutta(_) => "runge-kutta",
        }
    }
}

/// Where a run starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "kebab-case")]
pub enum Initial {
    /// Static equilibrium under gravity.
    #[cfg_attr(feature = "clap", value(name = "static"))]
    StaticEquilibrium,
    /// Zero displacement and velocity.
    Rest,
}

/// Most progress reports per run.
const PROGRESS_REPORTS: usize = 1000;

/// Ends a run early once what it has recorded is enough: every `every` recorded samples,
/// `decide` sees the values of every channel so far (in the order of the result's
/// channels) and returns `ControlFlow::Break(())` to stop. The run then ends as completed,
/// with the samples recorded up to there.
pub struct Until<'a> {
    /// Recorded samples between two calls of `decide` (at least 1).
    pub every: usize,
    /// Decides from the channels' values so far.
    pub decide: &'a mut dyn FnMut(&[Vec<f64>]) -> ControlFlow<()>,
}

/// What to simulate: every setting of a run, with its default defined once, in
/// [`SimulationOptions::new`]. A setting left `None` is chosen from the model and the other
/// settings when the run starts (each field says how); the result reports what was used.
#[derive(Debug, Clone)]
pub struct SimulationOptions {
    /// Spin speed over time.
    pub speed: SpeedProfile,
    /// Simulated time, s. Default 1 s.
    pub duration: f64,
    /// Time step (sampling interval for Runge-Kutta), s. Default `None`:
    /// [`STABLE_FRACTION`] of the central difference's stability limit of the model as it
    /// is integrated, or [`DEFAULT_STEP`] for the other methods.
    pub step: Option<f64>,
    /// Integrator. Default the central difference.
    pub method: Method,
    /// How the roller bearings act. Default `None`: [`ContactLaw::default_for`] the model
    /// (Hertz contacts when it has roller bearings).
    pub contact: Option<ContactLaw>,
    /// Craig-Bampton with this many fixed-interface modes; `None` (the default) for the
    /// full model.
    pub reduction: Option<usize>,
    /// Time discarded before steady-state post-processing, s. Default `None`: half the
    /// duration.
    pub settle: Option<f64>,
    /// Nodes whose ux and uy are recorded, in this order. Default `None`: every disk and
    /// bearing node, ascending.
    pub nodes: Option<Vec<usize>>,
    /// Initial state. Default the static equilibrium under gravity.
    pub initial: Initial,
    /// A recorded translation beyond this (m) means divergence (see the module
    /// documentation). Default [`DEFAULT_DIVERGENCE_BOUND`].
    pub divergence_bound: f64,
    /// Record every this many steps. Default `None`: as many steps as fit in
    /// [`DEFAULT_SAMPLE_INTERVAL`], at least 1.
    pub record_every: Option<usize>,
    /// Whether to record what each roller did ([`RollerRecord`]) and the channels of every
    /// roller bearing's node (appended when not among `nodes`). Default `true`; a caller
    /// of many runs that needs one response each (a cascade) leaves them out, since
    /// evaluating every roller at every sample costs about as much as the march.
    pub record_rollers: bool,
    /// Told how far the run has got (seconds simulated of the duration), at most a
    /// thousand times, and may stop it ([`RunStatus::Stopped`]); `None` (the default) for
    /// none.
    pub progress: Option<Progress>,
}

/// Default step of Newmark and output interval of Runge-Kutta, s (2000 samples per
/// revolution at 50 Hz): they have no stability limit to scale.
pub const DEFAULT_STEP: f64 = 1e-5;

/// Recorded samples are at most this far apart by default, s: 100 kHz, whose 50 kHz Nyquist
/// frequency lies far above every contact frequency of the speed range (the varying
/// compliance of the reference bearing is 2.7 kHz at 750 Hz) and above the bearing nodes'
/// contact resonances (a few kHz). The full model's modes above 50 kHz, which would alias,
/// are overdamped by the stiffness-proportional damping (zeta = beta w / 2 > 1 there). The
/// full model's stable step is a few microseconds, and recording each would write hundreds
/// of MB for a second of motion.
pub const DEFAULT_SAMPLE_INTERVAL: f64 = 1e-5;

/// Simulated time when none is given, s.
pub const DEFAULT_DURATION: f64 = 1.0;

/// Initial state when none is given: the static equilibrium under gravity, where the rotor
/// runs in service.
pub const DEFAULT_INITIAL: Initial = Initial::StaticEquilibrium;

/// Divergence bound when none is given, m: a centimetre, hundreds of times a bearing's
/// clearance, so only a run that has left the physics reaches it.
pub const DEFAULT_DIVERGENCE_BOUND: f64 = 0.01;

impl SimulationOptions {
    /// A run at `speed` with every other setting at its default (see each field).
    pub fn new(speed: SpeedProfile) -> Self {
        SimulationOptions {
            speed,
            duration: DEFAULT_DURATION,
            step: None,
            method: Method::CentralDifference,
            contact: None,
            reduction: None,
            settle: None,
            nodes: None,
            initial: DEFAULT_INITIAL,
            divergence_bound: DEFAULT_DIVERGENCE_BOUND,
            record_every: None,
            record_rollers: true,
            progress: None,
        }
    }

    /// The settling time of the run: [`SimulationOptions::settle`], or half the duration.
    pub fn settle_time(&self) -> f64 {
        self.settle.unwrap_or(0.5 * self.duration)
    }

    /// The contact law of the run on `model`: [`SimulationOptions::contact`], or
    /// [`ContactLaw::default_for`] the model.
    pub fn contact_law(&self, model: &Model) -> ContactLaw {
        self.contact
            .unwrap_or_else(|| ContactLaw::default_for(model))
    }

    /// The recorded nodes asked for: [`SimulationOptions::nodes`] (each once, in the order
    /// given), or every disk and bearing node, ascending.
    pub fn node_list(&self, model: &Model) -> Vec<usize> {
        match &self.nodes {
            Some(given) => {
                let mut nodes: Vec<usize> = Vec::with_capacity(given.len());
                for &n in given {
                    if !nodes.contains(&n) {
                        nodes.push(n);
                    }
                }
                nodes
            }
            None => {
                let mut nodes: Vec<usize> = model.disks.iter().map(|d| d.station.node).collect();
                nodes.extend(model.bearing_nodes());
                nodes.sort_unstable();
                nodes.dedup();
                nodes
            }
        }
    }

    /// The time step of the run on `model`: [`SimulationOptions::step`], or the default
    /// (which, for the central difference, needs the model's stability limit).
    ///
    /// # Errors
    /// Those of [`stable_step`] when the step is the central difference's default.
    pub fn time_step(&self, model: &Model) -> Result<f64> {
        self.step_by(|| stable_step(model, self.reduction, self.contact_law(model)))
    }

    /// [`Self::time_step`] with the model's linear system already made for this run (see
    /// [`Hooks::linear`]): the stability limit is taken of it instead of a new build.
    ///
    /// # Errors
    /// Those of [`stable_step_of`] when the step is the central difference's default;
    /// [`Error::Internal`] when `linear` was made with another reduction or bearings.
    pub fn time_step_on(&self, model: &Model, linear: &Linear) -> Result<f64> {
        let law = self.contact_law(model);
        if !linear.is_built_with(self.reduction, law.bearings()) {
            return Err(other_linear_system());
        }
        self.step_by(|| stable_step_of(model, linear, law))
    }

    /// The time step, with the stability limit from `limit` when the step is the central
    /// difference's default.
    fn step_by(&self, limit: impl FnOnce() -> Result<f64>) -> Result<f64> {
        match (self.step, self.method) {
            (None, Method::CentralDifference) => Ok(self.step_within(limit()?)),
            _ => Ok(self.step_within(f64::NAN)),
        }
    }

    /// The time step of the run, given the central difference's stability limit `limit`
    /// of the model as it is integrated.
    fn step_within(&self, limit: f64) -> f64 {
        match (self.step, self.method) {
            (Some(h), _) => h,
            (None, Method::CentralDifference) => STABLE_FRACTION * limit,
            (None, _) => DEFAULT_STEP,
        }
    }

    /// Steps per recorded sample at time step `step`: [`SimulationOptions::record_every`],
    /// or as many steps as fit in [`DEFAULT_SAMPLE_INTERVAL`], at least 1.
    pub fn record_interval(&self, step: f64) -> usize {
        // The small allowance keeps a step of exactly 1e-5 / k at k despite round-off.
        self.record_every.unwrap_or_else(|| {
            ((DEFAULT_SAMPLE_INTERVAL / step) * (1.0 + 1e-9))
                .floor()
                .max(1.0) as usize
        })
    }
}

/// What a caller plugs into a run besides its settings.
#[derive(Default)]
pub struct Hooks<'a> {
    /// The caller's own nonlinear forces instead of those of the contact law: whether the
    /// roller bearings' linear stiffness is in the matrices, and the builder, which receives
    /// a map from physical DOFs to integrator coordinates. Nothing is then recorded per
    /// roller, and the contact law is not used.
    pub forces: Option<(Bearings, ForceBuilder<'a>)>,
    /// Ends the run once what it has recorded is enough.
    pub until: Option<Until<'a>>,
    /// The model's linear system already made by [`crate::system::linear`] with this run's
    /// reduction and bearings, so that many runs of one model (a cascade's speeds) assemble
    /// and reduce it once; `None` to make it for this run.
    pub linear: Option<&'a Linear>,
}

/// One recorded signal.
#[derive(Debug, Clone, Serialize)]
pub struct Channel {
    /// `n<node>.<dir>`, or `<housing>.<dir>` for a housing.
    pub name: String,
    /// Node; housing h counts as node N + h after the N shaft nodes.
    pub node: usize,
    /// Values at each recorded time, m.
    pub values: Vec<f64>,
}

/// How a run ended.
#[derive(Debug, Clone, Serialize, PartialEq)]
#[serde(tag = "status", rename_all = "lowercase")]
pub enum RunStatus {
    /// Every step was computed.
    Completed,
    /// Stopped early; what was computed is kept.
    Diverged {
        /// When, s.
        time: f64,
        /// Why.
        message: String,
    },
    /// Stopped by its [`SimulationOptions::progress`]; what was computed is kept.
    Stopped {
        /// When, s.
        time: f64,
    },
}

/// Recorded time histories.
#[derive(Debug, Clone, Serialize)]
pub struct SimulationResult {
    /// Times, s.
    pub time: Vec<f64>,
    /// Recorded channels.
    pub channels: Vec<Channel>,
    /// Coordinates integrated (full DOFs or reduced size).
    pub coordinates: usize,
    /// Time step, s.
    pub step: f64,
    /// Settling time, s.
    pub settle: f64,
    /// Explicit stability limit of the integrated model, s.
    pub stable_step: f64,
    /// Wall-clock time of the march, s.
    pub wall_time_s: f64,
    /// Runge-Kutta cost, when used.
    pub rk_stats: Option<RkStats>,
    /// Integrator name.
    pub method: String,
    /// How the run ended.
    pub status: RunStatus,
    /// Steps per recorded sample.
    pub record_every: usize,
    /// What the rollers of each roller bearing did, at the recorded times (empty for
    /// linear bearings, for a caller's own forces and without
    /// [`SimulationOptions::record_rollers`]).
    pub rollers: Vec<RollerRecord>,
    /// Why the run started from rest although the static equilibrium was asked for
    /// (none was found, e.g. with many rollers and contact damping at speed); `None` when
    /// it started where asked.
    pub start_fallback: Option<String>,
}

impl SimulationResult {
    /// The result if the run completed, else the divergence as an error.
    ///
    /// # Errors
    /// [`Error::Diverged`], with the run's time and message, when the status is
    /// [`RunStatus::Diverged`]; [`Error::Interrupted`] when it is [`RunStatus::Stopped`].
    pub fn completed(self) -> Result<SimulationResult> {
        match &self.status {
            RunStatus::Completed => Ok(self),
            RunStatus::Diverged { message, time } => Err(Error::Diverged {
                time: *time,
                coordinate: 0,
                message: message.clone(),
            }),
            RunStatus::Stopped { time } => Err(Error::Interrupted(format!(
                "the simulation was stopped at t = {time:.6} s"
            ))),
        }
    }

    /// Index of the first sample after the settling time.
    pub fn settled_start(&self) -> usize {
        self.time
            .partition_point(|&t| t < self.settle - 1e-12 * self.step)
    }

    /// Time between recorded samples, s.
    pub fn sample_interval(&self) -> f64 {
        self.step * self.record_every as f64
    }
}

/// The checks of the settings that do not depend on the time step. Each error names the
/// setting as the front ends spell it (the field of [`SimulationOptions`], or `hht_alpha`).
fn check_settings(model: &Model, o: &SimulationOptions, nodes: &[usize]) -> Result<()> {
    let bad = |field: &str, m: String| Err(InputError::field(field, m).into());
    let settle = o.settle_time();
    if !(o.duration.is_finite() && o.duration > 0.0) {
        return bad(
            "duration",
            format!("the duration must be positive, got {} s", o.duration),
        );
    }
    if settle.is_nan() || settle < 0.0 {
        return bad(
            "settle",
            format!("the settling time must be 0 s or more, got {settle} s"),
        );
    }
    if settle >= o.duration {
        return Err(InputError::field(
            "settle",
            format!(
                "the settling time {settle} s is not shorter than the duration {} s",
                o.duration
            ),
        )
        .help(
            "the steady-state numbers come from the time after the settling time: shorten \
             it or lengthen the duration",
        )
        .into());
    }
    if let Some(&n) = nodes.iter().find(|&&n| n >= model.node_count()) {
        return bad(
            "nodes",
            format!(
                "node {n} is not on the shaft (nodes 0 to {})",
                model.node_count() - 1
            ),
        );
    }
    if let SpeedProfile::Ramp { duration, .. } = o.speed {
        if duration.is_nan() || duration <= 0.0 {
            return bad("speed", "a speed ramp needs a positive duration".into());
        }
    }
    if o.divergence_bound.is_nan() || o.divergence_bound <= 0.0 {
        return bad(
            "divergence_bound",
            format!(
                "the divergence bound must be positive, got {} m",
                o.divergence_bound
            ),
        );
    }
    if o.record_every == Some(0) {
        return bad("record_every", "record every 1 step or more, not 0".into());
    }
    if let Method::Newmark(scheme) = o.method {
        scheme.check()?;
    }
    Ok(())
}

/// Refuses a run whose records would not fit in [`super::MAX_RECORDED_VALUES`], before
/// they are allocated: `samples` samples of `series` series, one every `interval` s.
fn check_recorded(
    o: &SimulationOptions,
    interval: f64,
    samples: usize,
    series: usize,
) -> Result<()> {
    let values = samples.saturating_mul(series);
    if values <= super::MAX_RECORDED_VALUES {
        return Ok(());
    }
    Err(InputError::field(
        "record_every",
        format!(
            "{} s recorded every {interval:.3e} s is {samples} samples of {series} series \
             (time, channels, rollers): {values} values ({:.1} GB), at most {} ({:.1} GB)",
            o.duration,
            values as f64 * 8e-9,
            super::MAX_RECORDED_VALUES,
            super::MAX_RECORDED_VALUES as f64 * 8e-9
        ),
    )
    .help("record less often, fewer nodes or no rollers, or shorten the run")
    .into())
}

/// The checks of the time step.
fn check_step(o: &SimulationOptions, step: f64) -> Result<()> {
    let bad = |m: String| Err(InputError::field("step", m).into());
    if !(step.is_finite() && step > 0.0) {
        return bad(format!("the time step must be positive, got {step} s"));
    }
    if o.duration <= step {
        return bad(format!(
            "the duration ({} s) must exceed one time step ({step} s)",
            o.duration
        ));
    }
    if o.duration / step > super::MAX_STEPS {
        return bad(format!(
            "{:.0} steps is too many; raise the step or shorten the run",
            o.duration / step
        ));
    }
    Ok(())
}

/// Simulates `model` as `options` say: the roller bearings modelled by the contact law,
/// recording the channels of the nodes (and, with [`SimulationOptions::record_rollers`],
/// of every roller bearing's node and what each roller did).
///
/// # Errors
/// Those of [`simulate_with`].
pub fn simulate(model: &Model, options: &SimulationOptions) -> Result<SimulationResult> {
    simulate_with(model, options, Hooks::default())
}

/// As [`simulate`], with the caller's [`Hooks`]: its own nonlinear forces instead of the
/// contact law's, and a rule that ends the run once it has recorded enough.
///
/// # Errors
/// [`Error::Input`] naming the setting (`step`, `duration`, `settle`, `nodes`, `speed`,
/// `divergence_bound`, `record_every`, `hht_alpha`) for a step that is not positive, a
/// duration not above one step, a settling time outside [0, duration), more than 5e8
/// steps, records of more than [`super::MAX_RECORDED_VALUES`] values, a node not on the
/// shaft, a speed ramp without a positive duration, a divergence bound that is not
/// positive, a `record_every` of 0 or a Newmark HHT alpha outside [-1/3, 0];
/// [`Error::InvalidOption`] for an [`Until`] that looks every 0 samples.
/// [`Error::Unsupported`] for Lagrange-multiplier contacts with a method other than the
/// central difference. Then the errors of building the problem: those of
/// [`crate::reduce::CraigBampton::new`] with `options.reduction`; [`Error::Unsupported`]
/// when a bearing's DOFs are not kept by the reduction; [`Error::Input`] for a bearing
/// without a `forcing_function` under the forcing law, or with roller tilt or skew under
/// Lagrange contacts; [`Error::Unsupported`] for more bearings than Lagrange contacts can
/// constrain; those of the caller's forces, of [`System::check`] and of
/// [`central_difference_limit`].
/// Then those of the integrator that `options.method` names ([`central_difference`],
/// [`central_difference_constrained`], [`newmark`], [`runge_kutta`]), but not
/// [`Error::Diverged`]: a divergence ends the run with [`RunStatus::Diverged`] in the result
/// (see [`SimulationResult::completed`]). A static equilibrium that is not found does not
/// fail the run, which then starts from rest ([`SimulationResult::start_fallback`]).
pub fn simulate_with(
    model: &Model,
    options: &SimulationOptions,
    hooks: Hooks<'_>,
) -> Result<SimulationResult> {
    let Hooks {
        forces,
        until,
        linear,
    } = hooks;
    let (bearings, forces, rollers) = match forces {
        Some((bearings, forces)) => (bearings, forces, None),
        None => {
            let law = options.contact_law(model);
            // Linear bearings have no rollers to record.
            let rollers = (law != ContactLaw::Linear).then_some(law);
            (law.bearings(), law.forces(), rollers)
        }
    };
    let built = || match linear {
        Some(l) if l.is_built_with(options.reduction, bearings) => l.with_forces(model, forces),
        Some(_) => Err(other_linear_system()),
        None => build(model, options.reduction, bearings, forces),
    };
    march_and_record(model, options, built, rollers, until)
}

/// The central difference's stability limit (s) of `model` with its roller bearings
/// modelled by `law`: full, or reduced with `reduction` fixed-interface modes, exactly as
/// [`simulate`] integrates it. It depends on neither speed nor loads.
///
/// # Errors
/// The errors of [`crate::reduce::CraigBampton::new`] with `reduction`, of the law's
/// forces, of [`System::check`] ([`Error::InvalidOption`]) and of
/// [`central_difference_limit`] ([`Error::Singular`] for a mass that is not positive
/// definite, [`Error::NotConverged`] when the eigen-solver fails).
pub fn stable_step(model: &Model, reduction: Option<usize>, law: ContactLaw) -> Result<f64> {
    stable_step_of(model, &linear(model, reduction, law.bearings())?, law)
}

/// [`stable_step`] of the model's linear system already made with the run's reduction and
/// `law`'s bearings (many runs of one model share one: a cascade's speeds).
///
/// # Errors
/// Those of [`stable_step`] but the reduction's.
pub fn stable_step_of(model: &Model, linear: &Linear, law: ContactLaw) -> Result<f64> {
    // Rigid constraints corrected after each step leave the explicit limit of the
    // unconstrained rotor (Carpenter et al. 1991): the Lagrange law adds no forces.
    central_difference_limit(&linear.with_forces(model, law.forces())?.system)
}

/// A linear system handed to a run that was made for another: a caller's mistake.
fn other_linear_system() -> Error {
    Error::Internal(
        "the linear system handed to the simulation was made with another reduction or \
         bearings than the run's"
            .into(),
    )
}

/// Tells a [`Progress`] each time another 1/[`PROGRESS_REPORTS`] of the run is done.
struct ProgressTicker<'a> {
    progress: Option<&'a Progress>,
    duration: f64,
    next: f64,
}

impl ProgressTicker<'_> {
    /// Whether to go on at time `t`.
    fn tick(&mut self, t: f64) -> ControlFlow<()> {
        if self.progress.is_none() || t < self.next {
            return ControlFlow::Continue(());
        }
        self.next = t + self.duration / PROGRESS_REPORTS as f64;
        let done = t.min(self.duration);
        tell(self.progress, done, self.duration, || {
            format!("{done:.3} s of {} s", self.duration)
        })
    }
}

/// The first recorded translation beyond the bound: (channel, value).
fn beyond<'a>(
    channels: &'a [(String, usize, RecoveryRow)],
    q: &[f64],
    bound: f64,
) -> Option<(&'a str, f64)> {
    channels.iter().find_map(|(name, _, row)| {
        let x = row.dot(q);
        out_of_bound(x, bound).then_some((name.as_str(), x))
    })
}

/// Beyond +-`bound`, or not finite.
fn out_of_bound(x: f64, bound: f64) -> bool {
    x.is_nan() || x.abs() > bound
}

fn divergence_message(t: f64, what: &str, value: String, bound: f64) -> String {
    format!(
        "the solution diverged at t = {t:.6} s: {what} is {value} (bound {bound:e} m); reduce \
         the time step, check the model's supports, or raise the bound if such motion is \
         expected"
    )
}

/// Checks the settings, builds the system by `built`, marches and records; `law` (when
/// given) is the contact law whose rollers [`SimulationOptions::record_rollers`] records.
fn march_and_record(
    model: &Model,
    options: &SimulationOptions,
    built: impl FnOnce() -> Result<Built>,
    law: Option<ContactLaw>,
    mut until: Option<Until<'_>>,
) -> Result<SimulationResult> {
    let nodes = options.node_list(model);
    check_settings(model, options, &nodes)?;
    if until.as_ref().is_some_and(|u| u.every == 0) {
        return Err(Error::InvalidOption(
            "a stop rule must look every 1 recorded sample or more, not 0".into(),
        ));
    }
    let settle = options.settle_time();
    let lagrange = law == Some(ContactLaw::Lagrange);
    if lagrange && options.method != Method::CentralDifference {
        return Err(Error::Unsupported(format!(
            "Lagrange-multiplier contacts work with the central difference only (thesis eqs. \
             4.6-4.9), not with {}",
            options.method.name()
        )));
    }
    let Built {
        system: mut problem,
        coordinates: coords,
    } = built()?;
    let n = problem.size();
    let stable_step = central_difference_limit(&problem)?;
    let step = options.step_within(stable_step);
    check_step(options, step)?;
    let record_every = options.record_interval(step);
    let (q0, start_fallback) = starting_point(model, options, &mut problem, lagrange)?;
    let rollers_law = law.filter(|_| options.record_rollers);
    let mut contacts = if lagrange {
        let mut c = lagrange_contacts(model, &coords)?;
        if rollers_law.is_some() {
            c.keep_history();
        }
        Some(c)
    } else {
        None
    };
    let v0 = vec![0.0; n];

    let bound = options.divergence_bound;
    // The nodes' translations, then every housing's (where the dampers act).
    let shaft_nodes = model.node_count();
    let names = DofNames::of(model);
    let channels: Vec<(String, usize, RecoveryRow)> = recorded_nodes(model, nodes, rollers_law)
        .into_iter()
        .flat_map(|node| [Direction::Ux, Direction::Uy].map(|d| (node, dof(node, d))))
        .chain(
            (0..model.housings.len())
                .flat_map(|h| model.housing_dofs(h).map(|d| (shaft_nodes + h, d))),
        )
        .map(|(node, d)| (names.name(d), node, coords.recovery_row(d)))
        .collect();
    let steps = (options.duration / step).round() as usize;
    let capacity = steps / record_every + 1;
    // Time, the channels and each roller's angle, approach and force, held whole.
    let roller_series: usize = match rollers_law {
        Some(_) => model.roller_bearings.iter().map(|b| 3 * b.rollers).sum(),
        None => 0,
    };
    check_recorded(
        options,
        step * record_every as f64,
        capacity,
        1 + channels.len() + roller_series,
    )?;
    let mut probes = match rollers_law {
        Some(law) => model
            .roller_bearings
            .iter()
            .map(|b| RollerProbe::new(model, b, law, &coords, capacity))
            .collect::<Result<Vec<_>>>()?,
        None => Vec::new(),
    };
    let mut time = Vec::with_capacity(capacity);
    let mut values: Vec<Vec<f64>> = channels
        .iter()
        .map(|_| Vec::with_capacity(capacity))
        .collect();
    let mut ticker = ProgressTicker {
        progress: options.progress.as_ref(),
        duration: options.duration,
        next: 0.0,
    };
    // Divergence at a recorded translation: (time, message); the march stops there.
    let mut diverged: Option<(f64, String)> = beyond(&channels, &q0, bound).map(|(name, x)| {
        (
            0.0,
            divergence_message(0.0, name, format!("{x:.4e} m"), bound),
        )
    });
    let diverged_at_start = diverged.is_some();
    // Calls to skip before the next sample is recorded.
    let mut skip = 0usize;
    let speed = options.speed;
    // When the progress said stop.
    let mut stopped: Option<f64> = None;
    let mut observe = |t: f64, q: &[f64], v: &[f64]| {
        if ticker.tick(t).is_break() {
            stopped = Some(t);
            return ControlFlow::Break(());
        }
        if skip > 0 {
            skip -= 1;
            return ControlFlow::Continue(());
        }
        skip = record_every - 1;
        time.push(t);
        for ((name, _, row), out) in channels.iter().zip(values.iter_mut()) {
            let x = row.dot(q);
            out.push(x);
            if out_of_bound(x, bound) && diverged.is_none() {
                diverged = Some((t, divergence_message(t, name, format!("{x:.4e} m"), bound)));
            }
        }
        if diverged.is_some() {
            return ControlFlow::Break(());
        }
        if !probes.is_empty() {
            let at = speed.at(t).0;
            for p in &mut probes {
                p.record(&at, q, v);
            }
        }
        match until.as_mut() {
            Some(u) if time.len() % u.every == 0 => (u.decide)(&values),
            _ => ControlFlow::Continue(()),
        }
    };
    let march = MarchOptions {
        speed,
        step,
        steps,
        divergence_bound: DIVERGENCE_NET * bound,
    };
    let start = Instant::now();
    let mut rk_stats = None;
    let outcome = if diverged_at_start {
        Ok(())
    } else {
        match (options.method, contacts.as_mut()) {
            (Method::CentralDifference, Some(c)) => {
                central_difference_constrained(&mut problem, &q0, &v0, &march, c, &mut observe)
            }
            (Method::CentralDifference, None) => {
                central_difference(&mut problem, &q0, &v0, &march, &mut observe)
            }
            (Method::Newmark(scheme), _) => {
                newmark(&mut problem, &q0, &v0, scheme, &march, &mut observe)
            }
            (Method::RungeKutta(tol), _) => {
                runge_kutta(&mut problem, &q0, &v0, &tol, &march, &mut observe).map(|s| {
                    rk_stats = Some(s);
                })
            }
        }
    };
    let wall_time_s = start.elapsed().as_secs_f64();
    let status = match (diverged, outcome) {
        (Some((time, message)), _) => RunStatus::Diverged { time, message },
        (None, Ok(())) => match stopped {
            Some(time) => RunStatus::Stopped { time },
            None => RunStatus::Completed,
        },
        (
            None,
            Err(Error::Diverged {
                time, coordinate, ..
            }),
        ) => RunStatus::Diverged {
            time,
            message: divergence_message(
                time,
                &coords.coordinate_name(coordinate),
                format!("beyond {DIVERGENCE_NET} times the bound, or not finite"),
                bound,
            ),
        },
        (None, Err(e)) => return Err(e),
    };
    let channels = channels
        .into_iter()
        .zip(values)
        .map(|((name, node, _), values)| Channel { name, node, values })
        .collect();
    let mut rollers: Vec<RollerRecord> = probes.into_iter().map(|p| p.record).collect();
    if let Some(c) = &contacts {
        fill_multipliers(&mut rollers, c.history(), record_every);
    }
    Ok(SimulationResult {
        time,
        channels,
        coordinates: n,
        step,
        settle,
        stable_step,
        wall_time_s,
        rk_stats,
        method: options.method.name().to_string(),
        status,
        record_every,
        rollers,
        start_fallback,
    })
}

/// The starting displacement: rest, or the static equilibrium when asked for and found.
/// When it is not found the run starts from rest, and the second value says why.
fn starting_point(
    model: &Model,
    options: &SimulationOptions,
    problem: &mut System,
    lagrange: bool,
) -> Result<(Vec<f64>, Option<String>)> {
    let rest = vec![0.0; problem.size()];
    let found = match options.initial {
        Initial::Rest => return Ok((rest, None)),
        Initial::StaticEquilibrium if lagrange => {
            rigid_static_equilibrium(model, options.reduction, &options.speed)
        }
        Initial::StaticEquilibrium => {
            static_equilibrium(problem, &rest, options.speed.at(0.0).0.speed)
        }
    };
    match found {
        Ok(q) => Ok((q, None)),
        Err(
            why @ (Error::InvalidOption(_)
            | Error::Unsupported(_)
            | Error::Singular { .. }
            | Error::NotConverged { .. }),
        ) => Ok((
            rest,
            Some(format!(
                "no static equilibrium was found, so the run started from rest: {why}"
            )),
        )),
        Err(e) => Err(e),
    }
}

crate::given::choice!(Initial { "static" => Initial::StaticEquilibrium, "rest" => Initial::Rest });
