//! A run-up as `whirl runup` and `whirl.runup` ask for it: the command line fills it from
//! its flags, the Python package by name ([`RunupRequest::set`]);
//! [`RunupRequest::options`] turns it into the library's [`RunupOptions`], every option
//! left out (`None`) at the library's default.

// Options are read once per request, as the study file reads its own; a large error type
// on this cold path is fine.
#![allow(clippy::result_large_err)]

use super::options::steady_speeds;
use super::{Direction, RunupOptions, Steady, DEFAULT_STEADY_SPEEDS};
use crate::error::{InputError, Result};
use crate::given::{Given, SetByName};
use crate::model::Model;
use crate::nsv::CascadeRequest;
use crate::units::hz_to_rad_s;

/// Default acceleration, Hz/s: the reference rotor's range (1-750 Hz) in 37 s.
pub const DEFAULT_RATE_HZ_PER_S: f64 = 20.0;

/// The options of a run-up as the user gives them; `None` leaves the library's default
/// ([`RunupOptions::new`], [`crate::nsv::CascadeOptions::new`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunupRequest {
    /// Lowest and highest speed, rad/s; `None` for the model's operating range.
    pub speeds: Option<(f64, f64)>,
    /// Acceleration, rad/s^2; `None` for [`DEFAULT_RATE_HZ_PER_S`].
    pub rate: Option<f64>,
    /// Run-up, coast-down, or both.
    pub direction: Option<Direction>,
    /// Time at the starting speed before the ramp, s.
    pub hold: Option<f64>,
    /// Length of one short-time window, s.
    pub window_length: Option<f64>,
    /// Overlap of consecutive windows, a fraction.
    pub overlap: Option<f64>,
    /// The steady cascade compared with.
    pub steady: Option<Steady>,
    /// Speeds of the steady cascade, spread evenly over the sweep.
    pub steady_speeds: Option<usize>,
    /// Ratio beyond which the directions differ.
    pub hysteresis_ratio: Option<f64>,
    /// Amplitude from which a difference counts, m.
    pub threshold_m: Option<f64>,
    /// Span of speed each direction is smoothed over before the comparison, Hz.
    pub smoothing_hz: Option<f64>,
    /// Span of speed each sweep's NSV is smoothed over before the steady comparison, Hz.
    pub steady_smoothing_hz: Option<f64>,
    /// The cascade's settings, for the sweeps (start, contact law, reduction, step, node,
    /// component, data window, band, synchronous tolerance) and the steady cascade (all of
    /// them); its speeds are not read: the steady speeds come from the sweep's range.
    pub cascade: CascadeRequest,
}

/// The run-up's own options by name; [`crate::nsv::RUN_SETTINGS`] are read as the cascade reads them.
pub const RUNUP_OPTIONS: [&str; 12] = [
    "speeds",
    "rate",
    "direction",
    "hold",
    "window_length",
    "overlap",
    "steady",
    "steady_speeds",
    "hysteresis_ratio",
    "threshold",
    "smoothing",
    "steady_smoothing",
];

impl RunupRequest {
    /// The library's options for `model`: each option given replaces its default.
    ///
    /// # Errors
    /// [`crate::Error::Input`] naming `speeds` when none are given and the model states no
    /// operating range, or `steady_speeds` for fewer than 2. The values themselves are
    /// checked where the run-up starts ([`super::runup`]).
    pub fn options(&self, model: &Model) -> Result<RunupOptions> {
        let (low, high) = match self.speeds {
            Some(range) => range,
            None => model.operating.ok_or_else(|| {
                InputError::field("speeds", "the model states no operating speed range")
                    .help("give the range, e.g. 1:750Hz, or add [operating] to the model")
            })?,
        };
        let rate = self
            .rate
            .unwrap_or_else(|| hz_to_rad_s(DEFAULT_RATE_HZ_PER_S));
        let count = self.steady_speeds.unwrap_or(DEFAULT_STEADY_SPEEDS);
        if count < 2 {
            return Err(InputError::field(
                "steady_speeds",
                format!("the steady cascade needs 2 speeds or more, got {count}"),
            )
            .help("e.g. 60, or --steady none for no steady cascade")
            .into());
        }
        let cascade = CascadeRequest {
            speeds: Some(steady_speeds(low, high, count)),
            ..self.cascade.clone()
        };
        let mut o = RunupOptions::new(model, low, high, rate);
        o.cascade = cascade.options(model)?;
        o.direction = self.direction.unwrap_or(o.direction);
        o.hold = self.hold.unwrap_or(o.hold);
        o.window = self.window_length.or(o.window);
        o.overlap = self.overlap.unwrap_or(o.overlap);
        o.steady = self.steady.unwrap_or(o.steady);
        o.hysteresis_ratio = self.hysteresis_ratio.unwrap_or(o.hysteresis_ratio);
        o.threshold_m = self.threshold_m.unwrap_or(o.threshold_m);
        o.smoothing_hz = self.smoothing_hz.unwrap_or(o.smoothing_hz);
        o.steady_smoothing_hz = self.steady_smoothing_hz.unwrap_or(o.steady_smoothing_hz);
        Ok(o)
    }
}

impl SetByName for RunupRequest {
    /// Sets the option named `name` (one of [`RUNUP_OPTIONS`] or [`crate::nsv::RUN_SETTINGS`]) to
    /// `value`.
    ///
    /// # Errors
    /// [`InputError`] naming `name` for a value it does not read, or an unknown name.
    fn set(&mut self, name: &str, value: &Given) -> std::result::Result<(), InputError> {
        let v = value;
        match name {
            "speeds" => self.speeds = Some(v.speed_range(name)?),
            "rate" => self.rate = Some(v.acceleration(name)?),
            "direction" => self.direction = Some(v.choice(name)?),
            "hold" => self.hold = Some(v.time(name)?),
            "window_length" => self.window_length = Some(v.time(name)?),
            "overlap" => self.overlap = Some(v.number(name)?),
            "steady" => self.steady = Some(v.choice(name)?),
            "steady_speeds" => self.steady_speeds = Some(v.whole(name, 0, usize::MAX >> 1)?),
            "hysteresis_ratio" => self.hysteresis_ratio = Some(v.number(name)?),
            "threshold" => self.threshold_m = Some(v.length(name)?),
            "smoothing" => self.smoothing_hz = Some(v.frequency_hz(name)?),
            "steady_smoothing" => self.steady_smoothing_hz = Some(v.frequency_hz(name)?),
            _ => {
                return self
                    .cascade
                    .set_run_setting(name, v, &RUNUP_OPTIONS, "run-up")
            }
        }
        Ok(())
    }
}
