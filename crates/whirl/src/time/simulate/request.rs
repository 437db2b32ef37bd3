//! A run as the front ends ask for it: the command line's flags and the Python keywords, by
//! the same names, turned into [`SimulationOptions`] in one place.
//!
//! The request only maps (an integrator's name and its HHT alpha to a [`Method`], a target
//! speed to a ramp over the settling time) and refuses what only it can know; every other
//! setting is checked when the run starts, by [`simulate`](super::simulate). Errors name the
//! setting as an [`InputError`] field in the front ends' spelling (`hht_alpha`, `ramp_to`,
//! `settle`), so the command line can print `--hht-alpha` and Python `hht_alpha` from one
//! check.

// Options are read once per request; a large error type on this cold path is fine.
#![allow(clippy::result_large_err)]

use super::{Initial, Method, SimulationOptions};
use crate::bearing::ContactLaw;
use crate::error::{InputError, Result};
use crate::given::{unknown_option, Given, SetByName, MAX_MODES};
use crate::system::SpeedProfile;
use crate::time::{NewmarkScheme, RkTolerances};

/// The time integrator, by the name the front ends give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Integrator {
    /// Explicit central difference (thesis eqs. 4.1-4.3); needs a step below 2 / w_max.
    #[default]
    Cd,
    /// Implicit Newmark, average acceleration; any step is stable.
    Newmark,
    /// Adaptive Dormand-Prince 5(4), the accuracy reference; the step is the output
    /// interval.
    Rk,
}

/// The options [`SimulationRequest`] reads by name: the command line's flags with `_` for
/// `-`.
pub const SIMULATE_OPTIONS: [&str; 13] = [
    "speed",
    "duration",
    "method",
    "hht_alpha",
    "step",
    "reduce",
    "settle",
    "nodes",
    "contact",
    "record_every",
    "ramp_to",
    "start",
    "divergence_bound",
];

/// One run's settings as given (`None`: the library's default, see [`SimulationOptions`]).
#[derive(Debug, Clone, Default)]
pub struct SimulationRequest {
    /// Spin speed, rad/s (the start of the ramp with `ramp_to`).
    pub speed: f64,
    /// Speed reached by a linear ramp over the settling time, then held, rad/s.
    pub ramp_to: Option<f64>,
    /// Simulated time, s.
    pub duration: Option<f64>,
    /// Integrator.
    pub method: Integrator,
    /// HHT alpha of the Newmark integrator, in [-1/3, 0] (0: average acceleration).
    pub hht_alpha: Option<f64>,
    /// Time step (output interval of Runge-Kutta), s.
    pub step: Option<f64>,
    /// Fixed-interface modes of a Craig-Bampton reduction.
    pub reduce: Option<usize>,
    /// Time discarded before the steady-state numbers, s.
    pub settle: Option<f64>,
    /// Recorded nodes.
    pub nodes: Option<Vec<usize>>,
    /// Contact law of the roller bearings.
    pub contact: Option<ContactLaw>,
    /// Record every N-th step.
    pub record_every: Option<usize>,
    /// Initial state.
    pub start: Option<Initial>,
    /// A recorded displacement beyond this (m) means divergence.
    pub divergence_bound: Option<f64>,
}

impl SimulationRequest {
    /// The library's settings of the run.
    ///
    /// # Errors
    /// [`crate::Error::Input`] naming `hht_alpha` when it is given to another integrator
    /// than Newmark, and `ramp_to` when the settling time it ramps over is zero.
    pub fn options(&self) -> Result<SimulationOptions> {
        let defaults = SimulationOptions::new(SpeedProfile::Constant(self.speed));
        let mut o = SimulationOptions {
            duration: self.duration.unwrap_or(defaults.duration),
            step: self.step,
            method: self.method()?,
            contact: self.contact,
            reduction: self.reduce,
            settle: self.settle,
            nodes: self.nodes.clone(),
            initial: self.start.unwrap_or(defaults.initial),
            divergence_bound: self.divergence_bound.unwrap_or(defaults.divergence_bound),
            record_every: self.record_every,
            ..defaults
        };
        o.speed = self.speed_profile(o.settle_time())?;
        Ok(o)
    }

    fn method(&self) -> Result<Method> {
        Ok(match (self.method, self.hht_alpha) {
            (Integrator::Newmark, Some(alpha)) => Method::Newmark(NewmarkScheme::Hht(alpha)),
            (Integrator::Newmark, None) => Method::Newmark(NewmarkScheme::AverageAcceleration),
            (_, Some(_)) => {
                return Err(
                    InputError::field("hht_alpha", "applies to the newmark method only")
                        .help("choose the newmark method, or leave the HHT alpha out")
                        .into(),
                )
            }
            (Integrator::Cd, None) => Method::CentralDifference,
            (Integrator::Rk, None) => Method::RungeKutta(RkTolerances::default()),
        })
    }

    /// Constant speed, or a ramp over the settling time `settle` to `ramp_to`.
    fn speed_profile(&self, settle: f64) -> Result<SpeedProfile> {
        match self.ramp_to {
            None => Ok(SpeedProfile::Constant(self.speed)),
            // A negative settling time is the settling time's error, said when the run starts.
            Some(_) if settle == 0.0 => Err(InputError::field(
                "ramp_to",
                "the speed ramps over the settling time, which is zero",
            )
            .help("give a settling time, e.g. 0.5 s")
            .into()),
            Some(to) => Ok(SpeedProfile::Ramp {
                from: self.speed,
                to,
                start: 0.0,
                duration: settle,
            }),
        }
    }
}

impl SetByName for SimulationRequest {
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "speed" => self.speed = v.speed(name)?,
            "duration" => self.duration = Some(v.time(name)?),
            "method" => self.method = v.choice(name)?,
            "hht_alpha" => self.hht_alpha = Some(v.number(name)?),
            "step" => self.step = Some(v.time(name)?),
            "reduce" => self.reduce = Some(v.whole(name, 1, MAX_MODES)?),
            "settle" => self.settle = Some(v.time(name)?),
            "nodes" => self.nodes = Some(v.wholes(name, 0, usize::MAX >> 1)?),
            "contact" => self.contact = Some(v.choice(name)?),
            "record_every" => self.record_every = Some(v.whole(name, 1, usize::MAX >> 1)?),
            "ramp_to" => self.ramp_to = Some(v.speed(name)?),
            "start" => self.start = Some(v.choice(name)?),
            "divergence_bound" => self.divergence_bound = Some(v.length(name)?),
            _ => return Err(unknown_option(name, &SIMULATE_OPTIONS, "simulation")),
        }
        Ok(())
    }
}

crate::given::choice!(Integrator { "cd" => Integrator::Cd, "newmark" => Integrator::Newmark, "rk" => Integrator::Rk });
