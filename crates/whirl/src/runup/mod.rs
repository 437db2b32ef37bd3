//! Run-up and coast-down: one transient through a speed range at a constant acceleration,
//! its time-frequency cascade, and the hysteresis between the two directions
//! (docs/theory.md, "Run-up and coast-down").
//!
//! # The sweep
//!
//! The rotor is marched (the same reduced model, roller-bearing contact law, start, step and
//! sampling as the steady cascade of [`crate::nsv`]) with the spin speed
//!
//! ```text
//! Omega(t) = Omega_0                          t < t_h   (the hold: the start rings down)
//!          = Omega_0 +- alpha (t - t_h)       during the ramp, (high - low) / alpha long
//! ```
//!
//! and the bearings, the cage and the unbalance force follow the integrated spin angle
//! `phi = int Omega dt` ([`SpeedProfile::Ramp`]); the unbalance force carries the tangential
//! term of the acceleration, `m e (Omega^2 - i alpha) e^(i phi)`.
//!
//! # Its time-frequency cascade
//!
//! The response is cut into Hann windows of length `T` overlapping by `overlap`
//! (short-time Fourier transform). Each window's running speed is the speed at its middle,
//! and its 1X and NSV are read off its amplitude spectrum by the steady cascade's own
//! measurement ([`crate::nsv::measure`]: the 1X refined between bins, the largest peak
//! farther than `tolerance_bins` from every multiple of the running speed). By default
//! `T = 1 / sqrt(alpha / 2 pi)`: within one window the speed moves by `alpha T / 2 pi`,
//! exactly one bin `1 / T`, so each order's line stays within the synchronous tolerance and
//! the 1X read at the middle speed loses about 1 % to the chirp (a Hann-weighted
//! quadratic phase of at most pi/4 at the window's ends).
//!
//! # Against the steady cascade, and between the directions
//!
//! The steady cascade at the same settings (optionally from both starts, which marks the
//! speeds where two steady motions coexist: [`crate::nsv::compare_starts`]) is compared with
//! each sweep read at the cascade's speeds (its NSV power-averaged over
//! `steady_smoothing_hz`), and the RMS difference of 1X and NSV over the
//! range is reported for each direction ([`SteadyDifference`]). As the acceleration falls
//! the transient approaches the sequence of steady states, and these differences shrink,
//! except where the steady state is not unique.
//!
//! Run-up and coast-down are compared at the run-up's window speeds, the NSV of each
//! power-averaged over `smoothing_hz` of speed first ([`Hysteresis`]): a speed differs when
//! the larger amplitude exceeds the smaller by `hysteresis_ratio` and reaches `threshold_m`;
//! neighbouring differing speeds form a band. A linear rotor swept slowly shows none; a
//! rotor with coexisting motions keeps, in each direction, the motion it arrived on.

mod compare;
mod options;
mod report;
mod request;

use std::time::Instant;

use serde::Serialize;

pub use compare::{Band, FlaggedSpeed, Hysteresis, HysteresisPoint, Quantity, SteadyDifference};
pub use options::{
    steady_speeds, Direction, RunupOptions, Steady, Sweep, DEFAULT_DIRECTION, DEFAULT_HOLD,
    DEFAULT_HYSTERESIS_RATIO, DEFAULT_OVERLAP, DEFAULT_SMOOTHING_HZ, DEFAULT_STEADY,
    DEFAULT_STEADY_SMOOTHING_HZ, DEFAULT_STEADY_SPEEDS,
};
pub use report::{RunupReport, RunupSummary, SweepSummary};
pub use request::{RunupRequest, DEFAULT_RATE_HZ_PER_S, RUNUP_OPTIONS};

use crate::error::{Error, Result};
use crate::model::Model;
use crate::nsv::{
    compare_starts, measure, next_five_smooth, other_start_options, Cascade, PreparedCascade,
    StartComparison,
};
use crate::post::{SpectrumOptions, SpectrumPlanner};
use crate::progress::Progress;
use crate::system::SpeedProfile;
use crate::time::{simulate_with, Hooks, RunStatus, SimulationOptions, SimulationResult};
use crate::units::rad_s_to_hz;

/// At most this many windows of a sweep keep their spectrum (evenly spread; every window
/// keeps its readings): about as many as a cascade's speeds, more than a map can show, and
/// the spectra of 2,000 windows of 1,400 bins were 700 MB of CSV.
pub const MAX_KEPT_SPECTRA: usize = 200;

/// Sampling and spectra shared by the sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RunupResolved {
    /// Time step, s (the steady cascade's).
    pub step: f64,
    /// Steps per recorded sample.
    pub record_every: usize,
    /// Sample rate, Hz.
    pub sample_rate_hz: f64,
    /// Samples in one window (the next length at or above the window's time whose only
    /// prime factors are 2, 3 and 5, for a fast FFT).
    pub window_samples: usize,
    /// Window length, s.
    pub window_s: f64,
    /// Samples from one window's start to the next.
    pub hop_samples: usize,
    /// Bin spacing, Hz.
    pub resolution_hz: f64,
    /// Top of the band searched and kept, Hz (the steady cascade's).
    pub max_frequency_hz: f64,
    /// One-sided bins kept: 0 up to `bins - 1`.
    pub bins: usize,
}

/// The largest non-synchronous peak of one window.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct NsvReading {
    /// Frequency, refined between bins, Hz.
    pub frequency_hz: f64,
    /// Zero-to-peak amplitude, m.
    pub amplitude_m: f64,
    /// Frequency over the window's running speed.
    pub order: f64,
}

/// One short-time window of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepWindow {
    /// Time at the window's middle, s.
    pub time_s: f64,
    /// Running speed there, Hz.
    pub speed_hz: f64,
    /// 1X amplitude, m.
    pub one_x_m: f64,
    /// Largest non-synchronous peak; `None` when every peak is synchronous.
    pub nsv: Option<NsvReading>,
    /// One-sided amplitude spectrum over the band, m, bin `k` at `k` times the resolution;
    /// empty for the windows whose spectrum is not kept ([`MAX_KEPT_SPECTRA`]).
    pub amplitude: Vec<f64>,
}

impl SweepWindow {
    /// NSV amplitude, 0 without a non-synchronous peak, m.
    pub fn nsv_m(&self) -> f64 {
        self.nsv.map_or(0.0, |n| n.amplitude_m)
    }
}

/// One sweep: its windows in time order.
#[derive(Debug, Clone, Serialize)]
pub struct SweepResult {
    /// Its direction.
    pub sweep: Sweep,
    /// The windows, in time order (ascending speed for a run-up, descending for a
    /// coast-down).
    pub windows: Vec<SweepWindow>,
    /// Why the march stopped early; `None` when it completed.
    pub diverged: Option<String>,
    /// Why it started from rest although the static equilibrium was asked for.
    pub start_fallback: Option<String>,
    /// Wall-clock time of the march, s.
    pub wall_s: f64,
}

/// A computed run-up (coast-down, or both).
#[derive(Debug, Clone, Serialize)]
pub struct Runup {
    /// The options it was computed with.
    pub options: RunupOptions,
    /// Sampling and spectra.
    pub resolved: RunupResolved,
    /// Frequencies of the bins kept, Hz.
    pub frequency_hz: Vec<f64>,
    /// The sweeps, run-up first.
    pub sweeps: Vec<SweepResult>,
    /// The steady cascade at the same settings, when asked for.
    pub steady: Option<Cascade>,
    /// The steady cascade from the other start, compared speed by speed, when asked for.
    #[serde(skip)]
    pub starts: Option<StartComparison>,
    /// Wall-clock time of the whole analysis, s.
    pub wall_time_s: f64,
}

impl Runup {
    /// The sweep in direction `sweep`, if computed.
    pub fn sweep(&self, sweep: Sweep) -> Option<&SweepResult> {
        self.sweeps.iter().find(|s| s.sweep == sweep)
    }

    /// Each sweep against the steady cascade (none without one).
    pub fn against_steady(&self) -> Vec<SteadyDifference> {
        let Some(steady) = &self.steady else {
            return Vec::new();
        };
        self.sweeps
            .iter()
            .filter_map(|s| compare::against_steady(s, steady, self.options.steady_smoothing_hz))
            .collect()
    }

    /// The hysteresis between run-up and coast-down; `None` unless both were computed.
    pub fn hysteresis(&self) -> Option<Hysteresis> {
        let up = self.sweep(Sweep::Up)?;
        let down = self.sweep(Sweep::Down)?;
        Some(compare::hysteresis(
            up,
            down,
            &self.options,
            self.starts.as_ref(),
        ))
    }
}

/// Computes the run-up of `model` (see the module documentation): the sweeps in parallel,
/// then the steady cascade they are compared with. `progress` is told how far the steady
/// cascade has got, and may stop it.
///
/// # Errors
/// [`Error::Input`] naming the field for bad options (`speeds`, `rate`, `hold`, `window`,
/// `overlap`, `hysteresis_ratio`, `threshold`, `smoothing`, and the cascade's settings);
/// [`Error::Diverged`] when a sweep diverged before its first window; the errors of the
/// simulation and of the steady cascade ([`crate::nsv::cascade`]).
pub fn runup(model: &Model, options: &RunupOptions, progress: Option<&Progress>) -> Result<Runup> {
    let start = Instant::now();
    options::check(options)?;
    // A linear model's sweep is worth reading (its 1X); its steady cascade is refused.
    let prepared = match options.steady {
        Steady::None => PreparedCascade::for_transient(model, &options.cascade)?,
        _ => PreparedCascade::new(model, &options.cascade)?,
    };
    let resolved = resolve(options, &prepared)?;
    let sweep = |s: Sweep| run_sweep(model, options, &prepared, &resolved, s);
    let sweeps: Vec<SweepResult> = match options.direction.sweeps().as_slice() {
        [a, b] => {
            let (a, b) = rayon::join(|| sweep(*a), || sweep(*b));
            vec![a?, b?]
        }
        list => list.iter().map(|&s| sweep(s)).collect::<Result<_>>()?,
    };
    let (steady, starts) = steady_cascade(model, options, &prepared, progress)?;
    Ok(Runup {
        options: options.clone(),
        frequency_hz: (0..resolved.bins)
            .map(|k| k as f64 * resolved.resolution_hz)
            .collect(),
        resolved,
        sweeps,
        steady,
        starts,
        wall_time_s: start.elapsed().as_secs_f64(),
    })
}

/// The steady cascade, and from the other start, as the options ask.
fn steady_cascade(
    model: &Model,
    options: &RunupOptions,
    prepared: &PreparedCascade<'_>,
    progress: Option<&Progress>,
) -> Result<(Option<Cascade>, Option<StartComparison>)> {
    if options.steady == Steady::None {
        return Ok((None, None));
    }
    let first = prepared.run(None, progress)?;
    if options.steady == Steady::Cascade {
        return Ok((Some(first), None));
    }
    let other = other_start_options(&first);
    let second = PreparedCascade::new(model, &other)?.run(None, progress)?;
    let starts = compare_starts(&first, second, options.threshold_m)?;
    Ok((Some(first), Some(starts)))
}

/// Sampling and window of the sweeps: the steady cascade's step and band.
fn resolve(o: &RunupOptions, prepared: &PreparedCascade<'_>) -> Result<RunupResolved> {
    let r = prepared.resolved();
    let interval = r.step * r.record_every as f64;
    let window_samples = next_five_smooth(options::window_samples(o, interval)?);
    let hop_samples = (((1.0 - o.overlap) * window_samples as f64).round() as usize).max(1);
    let sample_rate_hz = 1.0 / interval;
    let resolution_hz = sample_rate_hz / window_samples as f64;
    let max_frequency_hz = r.max_frequency_hz;
    let bins =
        ((max_frequency_hz / resolution_hz).floor() as usize + 1).min(window_samples / 2 + 1);
    Ok(RunupResolved {
        step: r.step,
        record_every: r.record_every,
        sample_rate_hz,
        window_samples,
        window_s: window_samples as f64 * interval,
        hop_samples,
        resolution_hz,
        max_frequency_hz,
        bins,
    })
}

/// The speed profile of one sweep.
fn profile(o: &RunupOptions, sweep: Sweep) -> SpeedProfile {
    let (from, to) = match sweep {
        Sweep::Up => (o.low, o.high),
        Sweep::Down => (o.high, o.low),
    };
    SpeedProfile::Ramp {
        from,
        to,
        start: o.hold,
        duration: o.ramp_s(),
    }
}

/// Marches one sweep and reads its windows.
fn run_sweep(
    model: &Model,
    o: &RunupOptions,
    prepared: &PreparedCascade<'_>,
    r: &RunupResolved,
    sweep: Sweep,
) -> Result<SweepResult> {
    let speed = profile(o, sweep);
    let interval = 1.0 / r.sample_rate_hz;
    // Half a window past the ramp's end (at the final speed), so the last window centred
    // on the ramp is whole; two samples more for the rounding of the step count.
    let duration = o.hold + o.ramp_s() + 0.5 * r.window_s + 2.0 * interval;
    let simulation = SimulationOptions {
        speed,
        duration,
        step: Some(r.step),
        record_every: Some(r.record_every),
        settle: Some(0.0),
        ..o.cascade.run_settings()
    };
    let hooks = Hooks {
        forces: None,
        until: None,
        linear: Some(prepared.linear()),
    };
    let started = Instant::now();
    let result = simulate_with(model, &simulation, hooks)?;
    let wall_s = started.elapsed().as_secs_f64();
    let diverged = match &result.status {
        RunStatus::Diverged { message, .. } => Some(message.clone()),
        _ => None,
    };
    let windows = read_windows(&result, o, r, &speed)?;
    if windows.is_empty() {
        if let Some(message) = diverged {
            return Err(Error::Diverged {
                time: result.time.last().copied().unwrap_or(0.0),
                coordinate: 0,
                message,
            });
        }
    }
    Ok(SweepResult {
        sweep,
        windows,
        diverged,
        start_fallback: result.start_fallback.clone(),
        wall_s,
    })
}

/// The short-time spectra of the analysed component whose middles lie from the ramp's
/// start (or half a window in) to its end, each read by the cascade's measurement.
fn read_windows(
    result: &SimulationResult,
    o: &RunupOptions,
    r: &RunupResolved,
    speed: &SpeedProfile,
) -> Result<Vec<SweepWindow>> {
    let channel = match o.cascade.component {
        crate::nsv::Component::Ux => 0,
        crate::nsv::Component::Uy => 1,
    };
    let values = &result.channels[channel].values;
    let n = r.window_samples;
    let interval = 1.0 / r.sample_rate_hz;
    let half = 0.5 * (n - 1) as f64 * interval;
    let end = o.hold + o.ramp_s();
    let first = ((o.hold - half) / interval).round().max(0.0) as usize;
    let mut planner = SpectrumPlanner::new(
        n,
        r.sample_rate_hz,
        SpectrumOptions {
            window: o.cascade.window,
            remove_mean: true,
        },
    )?;
    let mut windows = Vec::new();
    let mut at = first;
    while at + n <= values.len() {
        let middle = result.time[at] + half;
        if middle > end + 1e-9 {
            break;
        }
        let spectrum = planner.spectrum(&values[at..at + n])?;
        let speed_hz = rad_s_to_hz(speed.at(middle).0.speed);
        let m = measure(
            &spectrum,
            speed_hz,
            o.cascade.tolerance_bins,
            r.max_frequency_hz,
        );
        let mut amplitude = spectrum.amplitude;
        amplitude.truncate(r.bins);
        windows.push(SweepWindow {
            time_s: middle,
            speed_hz,
            one_x_m: m.one_x_m,
            nsv: m.nsv.map(|p| NsvReading {
                frequency_hz: p.frequency_hz,
                amplitude_m: p.amplitude,
                order: p.order,
            }),
            amplitude,
        });
        at += r.hop_samples;
    }
    let every = windows.len().div_ceil(MAX_KEPT_SPECTRA).max(1);
    for (k, w) in windows.iter_mut().enumerate() {
        if k % every != 0 {
            w.amplitude = Vec::new();
        }
    }
    Ok(windows)
}
