//! A time simulation of a model: build the problem (full or Craig-Bampton reduced), find
//! the initial state, march, and record named channels.
//!
//! With one roller at the bottom the horizontal static position inside the clearance is not
//! unique; the static solve starts from u = 0, so it keeps u_x = 0 (SPEC section 7).
//!
//! [`stable_step`] gives the central difference's stability limit of the model exactly as
//! [`simulate`] will integrate it, so a caller can choose a step before running.

use std::fmt;
use std::sync::Arc;
use std::time::Instant;

use serde::Serialize;

use super::central::{central_difference, central_difference_limit};
use super::newmark::{newmark, NewmarkScheme};
use super::problem::{SpeedProfile, TimeProblem};
use super::rk::{runge_kutta, RkStats, RkTolerances};
use super::statics::static_equilibrium;
use super::{MarchOptions, NonlinearForce};
use crate::error::{Error, Result};
use crate::fe::{
    assemble, dof, dof_name, gravity_force, unbalance_force, Bearings, Direction, SystemMatrices,
};
use crate::model::Model;
use crate::reduce::{boundary_dofs, CraigBampton};

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
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Initial {
    /// Static equilibrium under gravity.
    StaticEquilibrium,
    /// Zero displacement and velocity.
    Rest,
}

/// Builds the nonlinear forces of a model, given how physical DOFs map to coordinates.
pub type ForceBuilder<'a> =
    &'a dyn Fn(&Model, &dyn Fn(usize) -> usize) -> Result<Vec<Box<dyn NonlinearForce>>>;

/// Reports how far a run has got: called with the fraction of the simulated time done,
/// from 0 to 1, at most a thousand times per run (so a display costs nothing measurable;
/// the caller decides how often to draw).
#[derive(Clone)]
pub struct Progress(Arc<dyn Fn(f64) + Send + Sync>);

/// Most calls of a [`Progress`] per run.
const PROGRESS_REPORTS: usize = 1000;

impl Progress {
    /// A progress report that calls `report` with the fraction done.
    pub fn new(report: impl Fn(f64) + Send + Sync + 'static) -> Self {
        Progress(Arc::new(report))
    }
}

impl fmt::Debug for Progress {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Progress(..)")
    }
}

/// What to simulate.
#[derive(Debug, Clone)]
pub struct SimulationOptions {
    /// Spin speed over time.
    pub speed: SpeedProfile,
    /// Simulated time, s.
    pub duration: f64,
    /// Time step (sampling interval for Runge-Kutta), s.
    pub step: f64,
    /// Integrator.
    pub method: Method,
    /// Craig-Bampton with this many fixed-interface modes; `None` for the full model.
    pub reduction: Option<usize>,
    /// Time discarded before steady-state post-processing, s.
    pub settle: f64,
    /// Nodes whose ux and uy are recorded.
    pub nodes: Vec<usize>,
    /// Initial state.
    pub initial: Initial,
    /// A displacement beyond this (m) means divergence.
    pub divergence_bound: f64,
    /// Told how far the run has got, e.g. for a progress display; `None` for none.
    pub progress: Option<Progress>,
}

/// One recorded signal.
#[derive(Debug, Clone, Serialize)]
pub struct Channel {
    /// `n<node>.<dir>`.
    pub name: String,
    /// Node.
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
}

impl SimulationResult {
    /// The result if the run completed, else the divergence as an error.
    pub fn completed(self) -> Result<SimulationResult> {
        match &self.status {
            RunStatus::Completed => Ok(self),
            RunStatus::Diverged { message, time } => Err(Error::Diverged {
                time: *time,
                coordinate: 0,
                message: message.clone(),
            }),
        }
    }

    /// Index of the first sample after the settling time.
    pub fn settled_start(&self) -> usize {
        self.time
            .partition_point(|&t| t < self.settle - 1e-12 * self.step)
    }
}

/// The integrated system and how it maps to physical DOFs.
struct Coordinates {
    system: SystemMatrices,
    reduction: Option<CraigBampton>,
}

impl Coordinates {
    fn coordinate_of(&self, physical: usize) -> Option<usize> {
        match &self.reduction {
            None => Some(physical),
            Some(cb) => cb.reduced_index(physical),
        }
    }

    fn vector(&self, physical: &[f64]) -> Vec<f64> {
        match &self.reduction {
            None => physical.to_vec(),
            Some(cb) => cb.reduce_vector(physical),
        }
    }

    fn recovery_row(&self, physical: usize) -> Vec<f64> {
        match &self.reduction {
            None => (0..self.system.dofs())
                .map(|j| f64::from(u8::from(j == physical)))
                .collect(),
            Some(cb) => cb.recovery_row(physical),
        }
    }
}

fn check_options(model: &Model, o: &SimulationOptions) -> Result<()> {
    let bad = |m: String| Err(Error::Numerical(m));
    if !(o.step.is_finite() && o.step > 0.0) {
        return bad(format!("the time step must be positive, got {} s", o.step));
    }
    if !(o.duration.is_finite() && o.duration > o.step) {
        return bad(format!(
            "the duration ({} s) must exceed one time step ({} s)",
            o.duration, o.step
        ));
    }
    if !(o.settle >= 0.0 && o.settle < o.duration) {
        return bad(format!(
            "the settling time ({} s) must lie in [0, duration = {} s)",
            o.settle, o.duration
        ));
    }
    if o.duration / o.step > 5e8 {
        return bad(format!(
            "{:.0} steps is too many; raise the step or shorten the run",
            o.duration / o.step
        ));
    }
    if let Some(&n) = o.nodes.iter().find(|&&n| n >= model.node_count()) {
        return bad(format!(
            "node {n} is not on the shaft (nodes 0 to {})",
            model.node_count() - 1
        ));
    }
    if let SpeedProfile::Ramp { duration, .. } = o.speed {
        if duration.is_nan() || duration <= 0.0 {
            return bad("a speed ramp needs a positive duration".into());
        }
    }
    Ok(())
}

/// Simulates `model` with its linear bearings in the matrices, roller bearings linearised
/// (their `linear_stiffness`), and no further nonlinear forces.
pub fn simulate(model: &Model, options: &SimulationOptions) -> Result<SimulationResult> {
    simulate_with(model, options, Bearings::Linearised, &no_forces)
}

/// The central difference's stability limit (s) of `model` as [`simulate`] integrates it:
/// full, or reduced with `reduction` fixed-interface modes.
pub fn stable_step(model: &Model, reduction: Option<usize>) -> Result<f64> {
    stable_step_with(model, reduction, Bearings::Linearised, &no_forces)
}

/// The central difference's stability limit (s) of `model` as [`simulate_with`] integrates
/// it with these bearings and forces (their largest tangent stiffness included).
pub fn stable_step_with(
    model: &Model,
    reduction: Option<usize>,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<f64> {
    // The limit depends on neither speed nor loads: any speed builds the same matrices.
    let (_, problem) = integrated(
        model,
        reduction,
        SpeedProfile::Constant(0.0),
        bearings,
        forces,
    )?;
    central_difference_limit(&problem)
}

/// The force builder of a model without nonlinear forces.
fn no_forces(_: &Model, _: &dyn Fn(usize) -> usize) -> Result<Vec<Box<dyn NonlinearForce>>> {
    Ok(Vec::new())
}

/// The coordinates integrated and the problem in them.
fn integrated(
    model: &Model,
    reduction: Option<usize>,
    speed: SpeedProfile,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<(Coordinates, TimeProblem)> {
    let full = assemble(model, bearings);
    let coords = match reduction {
        None => Coordinates {
            system: full.clone(),
            reduction: None,
        },
        Some(modes) => {
            let cb = CraigBampton::new(&full, &boundary_dofs(model, &[]), modes)?;
            Coordinates {
                system: cb.reduced.clone(),
                reduction: Some(cb),
            }
        }
    };
    let unbalance = unbalance_force(model, full.dofs());
    let ub_re: Vec<f64> = unbalance.iter().map(|c| c.re).collect();
    let ub_im: Vec<f64> = unbalance.iter().map(|c| c.im).collect();
    let map = |physical: usize| coords.coordinate_of(physical).unwrap_or(usize::MAX);
    let nonlinear = forces(model, &map)?;
    let problem = TimeProblem {
        mass: coords.system.mass.clone(),
        stiffness: coords.system.stiffness.clone(),
        damping: coords.system.damping.clone(),
        gyroscopic: coords.system.gyroscopic.clone(),
        constant_force: coords.vector(&gravity_force(model, &full)),
        unbalance_re: coords.vector(&ub_re),
        unbalance_im: coords.vector(&ub_im),
        nonlinear,
        speed,
    };
    problem.check()?;
    Ok((coords, problem))
}

/// Calls a [`Progress`] each time another 1/[`PROGRESS_REPORTS`] of the run is done.
struct ProgressTicker<'a> {
    progress: Option<&'a Progress>,
    duration: f64,
    next: f64,
}

impl ProgressTicker<'_> {
    fn tick(&mut self, t: f64) {
        if let Some(Progress(report)) = self.progress {
            let fraction = t / self.duration;
            if fraction >= self.next {
                report(fraction.min(1.0));
                self.next = fraction + 1.0 / PROGRESS_REPORTS as f64;
            }
        }
    }
}

/// Simulates `model` with nonlinear forces from `forces`, which receives a map from
/// physical DOFs to integrator coordinates. `bearings` says whether the roller bearings'
/// linear stiffness is in the matrices.
pub fn simulate_with(
    model: &Model,
    options: &SimulationOptions,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<SimulationResult> {
    check_options(model, options)?;
    let (coords, mut problem) =
        integrated(model, options.reduction, options.speed, bearings, forces)?;
    let n = problem.size();
    let q0 = match options.initial {
        Initial::Rest => vec![0.0; n],
        Initial::StaticEquilibrium => static_equilibrium(&mut problem, &vec![0.0; n])?,
    };
    let v0 = vec![0.0; n];
    let stable_step = central_difference_limit(&problem)?;

    let rows: Vec<(String, usize, Vec<f64>)> = options
        .nodes
        .iter()
        .flat_map(|&node| [Direction::Ux, Direction::Uy].map(|d| (node, dof(node, d))))
        .map(|(node, d)| (dof_name(d), node, coords.recovery_row(d)))
        .collect();
    let steps = (options.duration / options.step).round() as usize;
    let mut time = Vec::with_capacity(steps);
    let mut values: Vec<Vec<f64>> = rows.iter().map(|_| Vec::with_capacity(steps)).collect();
    let mut ticker = ProgressTicker {
        progress: options.progress.as_ref(),
        duration: options.duration,
        next: 0.0,
    };
    let mut observe = |t: f64, q: &[f64], _: &[f64]| {
        time.push(t);
        for ((_, _, row), out) in rows.iter().zip(values.iter_mut()) {
            out.push(row.iter().zip(q).map(|(a, b)| a * b).sum());
        }
        ticker.tick(t);
    };
    let march = MarchOptions {
        step: options.step,
        steps,
        divergence_bound: options.divergence_bound,
    };
    let start = Instant::now();
    let mut rk_stats = None;
    let outcome = match options.method {
        Method::CentralDifference => {
            central_difference(&mut problem, &q0, &v0, &march, &mut observe)
        }
        Method::Newmark(scheme) => newmark(&mut problem, &q0, &v0, scheme, &march, &mut observe),
        Method::RungeKutta(tol) => runge_kutta(&mut problem, &q0, &v0, &tol, &march, &mut observe)
            .map(|s| {
                rk_stats = Some(s);
            }),
    };
    let wall_time_s = start.elapsed().as_secs_f64();
    let status = match outcome {
        Ok(()) => RunStatus::Completed,
        Err(Error::Diverged { time, message, .. }) => RunStatus::Diverged { time, message },
        Err(e) => return Err(e),
    };
    let channels = rows
        .into_iter()
        .zip(values)
        .map(|((name, node, _), values)| Channel { name, node, values })
        .collect();
    Ok(SimulationResult {
        time,
        channels,
        coordinates: n,
        step: options.step,
        settle: options.settle,
        stable_step,
        wall_time_s,
        rk_stats,
        method: options.method.name().to_string(),
        status,
    })
}
