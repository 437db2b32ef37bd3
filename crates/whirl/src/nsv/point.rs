//! One speed of a cascade: simulate until the start has died away (or a cap), average the
//! spectra of consecutive records of the steady motion, and find the largest
//! non-synchronous peak with its whirl direction, how it changed while settling, and how
//! well the average knows it.
//!
//! # Settling by decay
//!
//! The first record is the last `record` seconds of the run at the first of these checks
//! (every half record, from `settle + record` on) that finds it settled: its largest
//! non-synchronous peak is steady (it does not keep falling over the three stretches of
//! [`dies_away`]), or negligible ([`negligible`]). A run that reaches `settle_max`
//! unsettled keeps that one record and is marked so: its peak is free vibration still
//! dying away, never an NSV of any class.
//!
//! # Averaging
//!
//! Above the first critical speed the reference rotor's NSV is often irregular: the first
//! mode rings at 45-50 Hz, driven by roller impacts, with an amplitude that wanders by
//! +-35 % from one half-second record to the next. One record is then one draw: two starts
//! that both settle (the static equilibrium and rest) gave NSV differing by more than 20 %
//! at 46 of 150 speeds. So a settled run goes on recording: the spectra of records that
//! overlap by half (Welch's method: with the Hann window two such records share little,
//! so each adds nearly a whole record's worth of information for half a record's time)
//! are power-averaged (the amplitude of a bin is the root of its mean square, a signal
//! analyser's RMS averaging, which leaves a steady sine's amplitude exactly as one record
//! gives it) until the largest non-synchronous peak is known as well as the summary needs
//! it ([`Averaging`]: at least `min_records`, at most `max_records` records).
//!
//! # How well is well enough
//!
//! The standard error of the averaged peak comes from the records' scatter, inflated by
//! the correlation of neighbouring records (measured at one and two records' distance:
//! overlapping records share samples, and a slowly wandering whip correlates records that
//! do not). Averaging stops at the first check where either
//!
//! - the standard error is within `relative_error` of the amplitude (or
//!   `absolute_error_m`), or the peak is negligible next to the 1X; or
//! - the standard error is within `decided_error` of the amplitude and the peak lies at
//!   least [`CLEAR_ERRORS`] standard errors from every onset level of the cascade: more
//!   records cannot move it across a level, so they cannot change an onset, and a summary
//!   statistic over many speeds (median, mean, 90th percentile) averages the remaining
//!   scatter down.
//!
//! So a steady vibration stops at `min_records`, an irregular whip far from the levels at
//! a few more, and only a speed whose NSV sits near a level runs to `max_records`: the rule
//! knows each speed's own variation. The peak carries its standard error and the
//! record-to-record variation of its amplitude.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use num_complex::Complex;
use serde::{Deserialize, Serialize};

use super::options::{Averaging, CascadeOptions, Component, Resolved};
use crate::error::{Error, Result};
use crate::linalg::rotate;
use crate::model::Model;
use crate::post::{
    amplitude_at, largest_non_synchronous_below, window_mean, FullSpectrumPlanner, SpectralPeak,
    Spectrum, SpectrumOptions, SpectrumPlanner, Window,
};
use crate::system::{linear, Linear, SpeedProfile};
use crate::time::{simulate_with, Hooks, RunStatus, SimulationOptions, Until};
use crate::units::rad_s_to_hz;

/// With only the record's halves to compare (a settling time shorter than half the
/// record), a peak dies away when its second half holds less than this fraction of its
/// first. Free vibration at 2 % damping of a 50 Hz mode decays by
/// exp(-0.02 * 2 pi * 50 * 0.25) = 0.21 over a quarter second (half the default record); a
/// steady vibration keeps a ratio near 1, and on the reference rotor beats of the first
/// mode's forward and backward whirl were seen down to 0.33 over 0.25 s, so the line is
/// drawn below that.
pub const TRANSIENT_DECAY: f64 = 0.25;

/// With three stretches compared (the end of the settling time and the record's halves), a
/// peak dies away when each stretch holds less than this fraction of the amplitude of the
/// one before (the second fraction at most twice the first). The 50 Hz mode above gives
/// 0.21 per quarter second, and 0.53 per tenth of a second (0.2 s records).
pub const DECAY_PER_STRETCH: f64 = 0.6;

/// A dying peak below this fraction of the 1X amplitude is negligible: the record counts as
/// settled (free vibration of a linear-like rotor decays for ever, and waiting for it to
/// stop being the largest non-synchronous peak would run every such speed to the cap).
pub const NEGLIGIBLE_FRACTION: f64 = 1e-3;

/// ... or below this amplitude, m, whatever the 1X.
pub const NEGLIGIBLE_M: f64 = 1e-9;

/// A peak this many standard errors from every onset level is on its side of each: at
/// two, a normal estimate is on the wrong side about once in 40.
pub const CLEAR_ERRORS: f64 = 2.0;

/// Correlation of the power estimates of two Hann-windowed records overlapping by half,
/// for a stationary random signal: the square of the window's overlap correlation
/// sum(w[n] w[n + N/2]) / sum(w[n]^2) = 1/6 (Harris 1978). The least the records'
/// correlation is taken to be, however few records there are to measure it.
const HANN_HALF_OVERLAP_POWER_CORRELATION: f64 = 1.0 / 36.0;

/// The largest non-synchronous peak at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct NsvPeak {
    /// Frequency, refined between bins, Hz.
    pub frequency_hz: f64,
    /// Zero-to-peak amplitude in the analysed component, refined between bins, m.
    pub amplitude_m: f64,
    /// Frequency over running speed.
    pub order: f64,
    /// Radius of the forward-whirling circular component at +frequency in the full
    /// spectrum of x + i y (largest bin within one bin), m.
    pub forward_m: f64,
    /// Radius of the backward-whirling component at -frequency, m.
    pub backward_m: f64,
    /// Amplitude at this frequency in the later half of the records averaged over that in
    /// the earlier half (with one record, its second half over its first): about 1 for a
    /// steady vibration, well below 1 for free vibration still dying away.
    pub decay_ratio: f64,
    /// Amplitude at this frequency in the record's first half over that in the equally
    /// long stretch just before the record (the end of the settling time); `None` when the
    /// settling time is shorter than half the record.
    pub settling_ratio: Option<f64>,
    /// Standard error of the averaged amplitude over the records, m: how far another
    /// stretch of the same steady motion (or another start) may put it.
    pub standard_error_m: f64,
    /// Standard deviation of the records' amplitudes at this frequency over their mean:
    /// near 0 for a steady (periodic or quasi-periodic) vibration, 0.3-0.5 for an
    /// irregular one whose amplitude wanders from record to record.
    pub variation: f64,
}

/// The result at one speed, as stored in a checkpoint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CascadePoint {
    /// Spin speed, rad/s.
    pub speed: f64,
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Added by the refinement of the speed grid (not one of the requested speeds).
    pub added: bool,
    /// Time simulated before the record, s: the settling time this speed needed.
    pub settle_s: f64,
    /// Whether the record is settled (see the module documentation); an unsettled point's
    /// peak is free vibration still dying away at the cap.
    pub settled: bool,
    /// Records averaged into the spectra, each `record` seconds long and overlapping the
    /// one before by half (1 for an unsettled point, 0 for a diverged one).
    pub records: usize,
    /// Why the run started from rest although the static equilibrium was asked for;
    /// `None` when it started where asked.
    pub start_fallback: Option<String>,
    /// Why the run at this speed stopped early; `None` when it completed (then the
    /// spectra below are empty).
    pub diverged: Option<String>,
    /// One-sided amplitude spectrum of the analysed component over the band, m
    /// (zero-to-peak), bin `k` at `k` times the resolution.
    pub amplitude: Vec<f64>,
    /// Full spectrum of x + i y over -band..=band (only with `CascadeOptions::full`), m.
    pub full_amplitude: Vec<f64>,
    /// The 1X amplitude of the analysed component, refined between bins, m.
    pub one_x_m: f64,
    /// The largest non-synchronous peak in the band; `None` when there is none.
    pub peak: Option<NsvPeak>,
}

/// The lengths of a point's spectra in one cascade.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct SpectrumLengths {
    /// Bins of the one-sided band.
    band: usize,
    /// Bins of the full spectrum; 0 when the cascade keeps none.
    full: usize,
}

impl SpectrumLengths {
    pub(super) fn of(options: &CascadeOptions, r: &Resolved) -> Self {
        SpectrumLengths {
            band: r.bins,
            full: if options.full {
                full_bins(r).count()
            } else {
                0
            },
        }
    }
}

#[cfg(test)]
impl SpectrumLengths {
    pub(super) fn for_test(band: usize, full: usize) -> Self {
        SpectrumLengths { band, full }
    }
}

impl CascadePoint {
    /// Whether the point is one a run of this cascade could have written: spectra of the
    /// cascade's lengths (none for a diverged point), every amplitude finite and not
    /// negative. A point read back from a file is checked so before it is used.
    pub(super) fn is_whole(&self, lengths: SpectrumLengths) -> bool {
        let amplitude = |x: f64| x.is_finite() && x >= 0.0;
        let (band, full) = match self.diverged {
            Some(_) => (0, 0),
            None => (lengths.band, lengths.full),
        };
        self.amplitude.len() == band
            && self.full_amplitude.len() == full
            && self
                .amplitude
                .iter()
                .chain(&self.full_amplitude)
                .all(|&a| amplitude(a))
            && amplitude(self.one_x_m)
            && amplitude(self.settle_s)
            && (self.speed_hz - self.speed / std::f64::consts::TAU).abs() <= 1e-9 * self.speed_hz
            && self.peak.as_ref().is_none_or(|p| p.is_whole())
    }
}

impl NsvPeak {
    fn is_whole(&self) -> bool {
        let amplitude = |x: f64| x.is_finite() && x >= 0.0;
        [
            self.frequency_hz,
            self.amplitude_m,
            self.forward_m,
            self.backward_m,
            self.decay_ratio,
            self.standard_error_m,
            self.variation,
        ]
        .into_iter()
        .all(amplitude)
            && self.order.is_finite()
            && self.settling_ratio.is_none_or(amplitude)
    }
}

#[cfg(test)]
impl CascadePoint {
    /// A settled point at `speed_hz` (4 records of 0.5 s, no spectra kept) with its 1X and
    /// its largest non-synchronous peak: the fixture of the nsv modules' unit tests.
    pub(crate) fn settled_at(speed_hz: f64, one_x_m: f64, peak: Option<NsvPeak>) -> Self {
        CascadePoint {
            speed: speed_hz * std::f64::consts::TAU,
            speed_hz,
            added: false,
            settle_s: 0.5,
            settled: true,
            records: 4,
            start_fallback: None,
            diverged: None,
            amplitude: Vec::new(),
            full_amplitude: Vec::new(),
            one_x_m,
            peak,
        }
    }
}

/// The spectra of one record length, planned once and reused by the speeds a thread
/// computes.
#[derive(Clone)]
pub(super) struct Planners {
    one_sided: SpectrumPlanner,
    full: FullSpectrumPlanner,
    /// The Hann window of half a record, for [`Stretches`]: computing it at every settling
    /// check (a cosine per sample) was 4 % of a cascade.
    stretches: Stretches,
}

impl Planners {
    pub(super) fn new(o: &CascadeOptions, r: &Resolved) -> Result<Planners> {
        // The static sag would otherwise be the largest "peak".
        let options = SpectrumOptions {
            window: o.window,
            remove_mean: true,
        };
        Ok(Planners {
            one_sided: SpectrumPlanner::new(r.samples, r.sample_rate_hz, options)?,
            full: FullSpectrumPlanner::new(r.samples, r.sample_rate_hz, options)?,
            stretches: Stretches::new(r.samples / 2, r.sample_rate_hz),
        })
    }

    /// The whole one-sided spectrum of `x` (up to Nyquist: peaks are refined with
    /// neighbours beyond the band).
    fn one_sided(&mut self, x: &[f64]) -> Result<Spectrum> {
        self.one_sided.spectrum(x)
    }

    /// The whole full spectrum of x + i y, bins ascending from -Nyquist.
    fn two_sided(&mut self, x: &[f64], y: &[f64]) -> Result<Vec<f64>> {
        let mut amplitude = vec![0.0; x.len()];
        self.full.process(x, y, &mut amplitude)?;
        Ok(amplitude)
    }
}

/// A record's one-sided spectrum and its largest non-synchronous peak (without the full
/// spectrum's whirl radii).
struct Reading {
    peak: Option<NsvPeak>,
    one_x_m: f64,
}

impl Reading {
    fn settled(&self) -> bool {
        self.peak
            .is_none_or(|p| !dies_away(&p) || p.amplitude_m < negligible(self.one_x_m))
    }
}

/// Samples of settling before the record starts at `settle` seconds (the first sample at
/// or after it).
fn samples_in(time: f64, r: &Resolved) -> usize {
    (time * r.sample_rate_hz - 1e-9).ceil().max(0.0) as usize
}

/// Samples between the starts of two consecutive records: they overlap by half.
pub(super) fn hop(r: &Resolved) -> usize {
    (r.samples / 2).max(1)
}

/// Complete records in `available` samples from the first record's start.
fn records_in(available: usize, r: &Resolved) -> usize {
    available
        .checked_sub(r.samples)
        .map_or(0, |rest| rest / hop(r) + 1)
}

/// Where a speed's run stands: settling, then averaging records.
struct Watch<'a> {
    o: &'a CascadeOptions,
    r: &'a Resolved,
    speed_hz: f64,
    /// The first sample a settled record may start at, and the last (the cap).
    first_start: usize,
    last_start: usize,
    /// The first record's start, once settled or at the cap.
    start: Option<usize>,
    records: Records,
}

impl Watch<'_> {
    /// Looks at the record so far (called every half record): settled yet, and if so, is the
    /// averaged NSV known well enough? `Break` ends the run.
    fn check(&mut self, values: &[f64], planners: &mut Planners) -> Result<ControlFlow<()>> {
        let (o, r) = (self.o, self.r);
        let start = match self.start {
            Some(start) => start,
            None => {
                let latest = values.len().saturating_sub(r.samples);
                if latest < self.first_start {
                    return Ok(ControlFlow::Continue(()));
                }
                let start = latest.min(self.last_start);
                let settled = read(values, start, self.speed_hz, o, r, planners)?.settled();
                if !settled && start < self.last_start {
                    return Ok(ControlFlow::Continue(()));
                }
                self.start = Some(start);
                if !settled {
                    // Still dying away at the cap: its last record is all it gets.
                    return Ok(ControlFlow::Break(()));
                }
                start
            }
        };
        let complete = records_in(values.len() - start, r).min(o.averaging.max_records);
        if complete == self.records.powers.len() {
            // No record finished since the last check (checks come every half record).
            return Ok(ControlFlow::Continue(()));
        }
        self.records.extend(values, start, complete, r, planners)?;
        let enough = complete >= o.averaging.max_records
            || (complete >= o.averaging.min_records
                && self
                    .records
                    .estimate(self.speed_hz, o, r)
                    .converged(&o.averaging, &o.refine.onset_levels_m));
        Ok(if enough {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        })
    }
}

/// The one-sided power spectra of records from a settled start, overlapping by half.
#[derive(Default)]
struct Records {
    /// Squared amplitude of every bin, one vector per record.
    powers: Vec<Vec<f64>>,
    /// Their sum over the records, bin by bin (so a check costs one pass over the bins,
    /// not one per record).
    sum: Vec<f64>,
    /// The first record's spectrum (its bins and window describe them all).
    first: Option<Spectrum>,
}

impl Records {
    /// Takes the spectra of records `len..count` (from `start`, one [`hop`] apart).
    fn extend(
        &mut self,
        values: &[f64],
        start: usize,
        count: usize,
        r: &Resolved,
        planners: &mut Planners,
    ) -> Result<()> {
        while self.powers.len() < count {
            let x = record(values, start + self.powers.len() * hop(r), r)?;
            self.push(planners.one_sided(x)?);
        }
        Ok(())
    }

    /// Adds one record's spectrum.
    fn push(&mut self, spectrum: Spectrum) {
        let power: Vec<f64> = spectrum.amplitude.iter().map(|a| a * a).collect();
        self.sum.resize(power.len(), 0.0);
        for (total, p) in self.sum.iter_mut().zip(&power) {
            *total += p;
        }
        self.powers.push(power);
        self.first.get_or_insert(spectrum);
    }

    /// The power-averaged spectrum (amplitude = root of the mean squared amplitude, as a
    /// signal analyser's RMS averaging: a steady sine keeps its amplitude exactly) and its
    /// largest non-synchronous peak with the peak's standard error.
    fn estimate(&self, speed_hz: f64, o: &CascadeOptions, r: &Resolved) -> Estimate {
        let n = self.powers.len().max(1) as f64;
        let template = self.first.as_ref();
        let amplitude: Vec<f64> = self.sum.iter().map(|total| (total / n).sqrt()).collect();
        let spectrum = Spectrum {
            frequency_hz: template.map_or_else(Vec::new, |s| s.frequency_hz.clone()),
            amplitude,
            resolution_hz: r.resolution_hz,
            window: o.window,
        };
        let measured = measure(&spectrum, speed_hz, o.tolerance_bins, r.max_frequency_hz);
        let spread = measured
            .nsv
            .map(|p| self.spread_at(p.frequency_hz / r.resolution_hz));
        Estimate {
            one_x_m: measured.one_x_m,
            spectrum,
            peak: measured.nsv.zip(spread),
        }
    }

    /// Amplitude of the bin nearest `position` (in bins) over the later half of the records
    /// over that over the earlier half (power-averaged, the middle record left out of an
    /// odd count); `None` for a single record.
    fn decay_at(&self, position: f64) -> Option<f64> {
        let n = self.powers.len();
        if n < 2 {
            return None;
        }
        let k = position.round().max(0.0) as usize;
        let mean = |records: &[Vec<f64>]| {
            records
                .iter()
                .map(|p| p.get(k).copied().unwrap_or(0.0))
                .sum::<f64>()
                / records.len() as f64
        };
        let (earlier, later) = (mean(&self.powers[..n / 2]), mean(&self.powers[n - n / 2..]));
        Some(if earlier > 0.0 {
            (later / earlier).sqrt()
        } else {
            1.0
        })
    }

    /// The scatter over the records of the bin nearest `position` (in bins).
    fn spread_at(&self, position: f64) -> Spread {
        let k = position.round().max(0.0) as usize;
        let powers: Vec<f64> = self
            .powers
            .iter()
            .map(|p| p.get(k).copied().unwrap_or(0.0))
            .collect();
        let amplitudes: Vec<f64> = powers.iter().map(|p| p.sqrt()).collect();
        let (mean_power, sd_power) = mean_and_deviation(&powers);
        let (mean_amplitude, sd_amplitude) = mean_and_deviation(&amplitudes);
        let n = powers.len() as f64;
        Spread {
            // A = sqrt(mean P): its relative error is half that of the mean power, whose
            // variance is that of independent records times the correlation's inflation.
            relative_error: if mean_power > 0.0 {
                0.5 * sd_power / mean_power * (correlation_inflation(&powers) / n).sqrt()
            } else {
                0.0
            },
            variation: if mean_amplitude > 0.0 {
                sd_amplitude / mean_amplitude
            } else {
                0.0
            },
        }
    }
}

/// How much the correlation of neighbouring records' powers inflates the variance of their
/// mean over that of independent records: 1 + 2 (rho_1 + rho_2), the correlations at one
/// record (overlapping: at least [`HANN_HALF_OVERLAP_POWER_CORRELATION`]) and at two
/// (records that touch), each measured once there are enough records to, and never taken
/// as negative (which would claim more than independent records know).
fn correlation_inflation(powers: &[f64]) -> f64 {
    let n = powers.len();
    let next = if n >= 4 {
        autocorrelation(powers, 1)
    } else {
        0.0
    };
    let touching = if n >= 6 {
        autocorrelation(powers, 2)
    } else {
        0.0
    };
    1.0 + 2.0 * (next.max(HANN_HALF_OVERLAP_POWER_CORRELATION) + touching.max(0.0))
}

/// Sample autocorrelation of `x` at `lag`, within -1..=1 (0 where `x` does not vary).
fn autocorrelation(x: &[f64], lag: usize) -> f64 {
    let (mean, _) = mean_and_deviation(x);
    let variance: f64 = x.iter().map(|v| (v - mean).powi(2)).sum();
    if variance <= 0.0 || lag >= x.len() {
        return 0.0;
    }
    let covariance: f64 = x
        .iter()
        .zip(&x[lag..])
        .map(|(a, b)| (a - mean) * (b - mean))
        .sum();
    (covariance / variance).clamp(-1.0, 1.0)
}

/// Mean and sample standard deviation (0 for fewer than two values).
fn mean_and_deviation(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    if x.is_empty() {
        return (0.0, 0.0);
    }
    let mean = x.iter().sum::<f64>() / n;
    if x.len() < 2 {
        return (mean, 0.0);
    }
    let variance = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, variance.sqrt())
}

/// How the records scatter at a peak's frequency.
#[derive(Debug, Clone, Copy)]
struct Spread {
    /// Standard error of the averaged amplitude over the amplitude.
    relative_error: f64,
    /// Standard deviation of the records' amplitudes over their mean.
    variation: f64,
}

/// The averaged spectrum of a speed, its 1X and its largest non-synchronous peak.
struct Estimate {
    spectrum: Spectrum,
    one_x_m: f64,
    peak: Option<(SpectralPeak, Spread)>,
}

impl Estimate {
    /// Whether the averaged NSV is known as well as the summary needs (the module
    /// documentation): its standard error within the tolerance, the peak negligible next to
    /// the 1X, or within `decided_error` and clear of every level in `levels_m`.
    fn converged(&self, a: &Averaging, levels_m: &[f64]) -> bool {
        self.peak.is_none_or(|(p, s)| {
            let error = s.relative_error * p.amplitude;
            error <= (a.relative_error * p.amplitude).max(a.absolute_error_m)
                || p.amplitude < negligible(self.one_x_m)
                || (error <= a.decided_error * p.amplitude
                    && clear_of_levels(p.amplitude, error, levels_m))
        })
    }
}

/// Whether an amplitude with this standard error lies [`CLEAR_ERRORS`] standard errors or
/// more from every level, m.
fn clear_of_levels(amplitude_m: f64, error_m: f64, levels_m: &[f64]) -> bool {
    levels_m
        .iter()
        .all(|level| (amplitude_m - level).abs() >= CLEAR_ERRORS * error_m)
}

/// The linear system every speed of the cascade marches, and whose stability limit sets
/// the step (assembled and reduced once: it does not depend on the speed).
///
/// # Errors
/// Those of [`linear`].
pub(super) fn linear_system(model: &Model, o: &CascadeOptions) -> Result<Linear> {
    let run = o.run_settings();
    linear(model, run.reduction, run.contact_law(model).bearings())
}

/// Simulates and analyses one speed (rad/s). A run that diverges is a point with its
/// message and no spectra, not an error: the cascade goes on.
pub(super) fn compute(
    model: &Model,
    o: &CascadeOptions,
    r: &Resolved,
    linear: &Linear,
    speed: f64,
    planners: &mut Planners,
) -> Result<CascadePoint> {
    let speed_hz = rad_s_to_hz(speed);
    let channel = match o.component {
        Component::Ux => 0,
        Component::Uy => 1,
    };
    let first_start = samples_in(o.settle, r);
    let last_start = samples_in(o.settle_max, r).max(first_start);
    let simulation = SimulationOptions {
        speed: SpeedProfile::Constant(speed),
        // Two samples more than the records, so that rounding of the step count never
        // leaves the last a sample short.
        duration: o.settle_max.max(o.settle)
            + o.averaging.recorded_time(o.record)
            + 2.0 / r.sample_rate_hz,
        step: Some(r.step),
        record_every: Some(r.record_every),
        ..o.run_settings()
    };
    let mut watch = Watch {
        o,
        r,
        speed_hz,
        first_start,
        last_start,
        start: None,
        records: Records::default(),
    };
    let mut failure: Option<Error> = None;
    let mut decide = |values: &[Vec<f64>]| match watch.check(&values[channel], planners) {
        Ok(flow) => flow,
        Err(e) => {
            failure = Some(e);
            ControlFlow::Break(())
        }
    };
    let until = Until {
        every: (r.samples / 2).max(1),
        decide: &mut decide,
    };
    let hooks = Hooks {
        forces: None,
        until: Some(until),
        linear: Some(linear),
    };
    let result = simulate_with(model, &simulation, hooks)?;
    if let Some(e) = failure {
        return Err(e);
    }
    let start_fallback = result.start_fallback.clone();
    if let RunStatus::Diverged { message, .. } = &result.status {
        return Ok(CascadePoint {
            speed,
            speed_hz,
            added: false,
            settle_s: 0.0,
            settled: false,
            records: 0,
            start_fallback,
            diverged: Some(message.clone()),
            amplitude: Vec::new(),
            full_amplitude: Vec::new(),
            one_x_m: 0.0,
            peak: None,
        });
    }
    let values = &result.channels[channel].values;
    let start = watch.start.unwrap_or(last_start);
    let first = read(values, start, speed_hz, o, r, planners)?;
    let count = if first.settled() {
        records_in(values.len().saturating_sub(start), r).clamp(1, o.averaging.max_records)
    } else {
        1
    };
    // The checks took at most `count` records (the same settled reading, fewer samples).
    let mut records = watch.records;
    records.extend(values, start, count, r, planners)?;
    let estimate = records.estimate(speed_hz, o, r);
    let (xs, ys) = (&result.channels[0].values, &result.channels[1].values);
    let full = averaged_two_sided(xs, ys, start, count, r, planners)?;
    let x = record(values, start, r)?;
    let half = r.samples / 2;
    let tail = start.checked_sub(half).map(|from| &values[from..start]);
    let peak = estimate.peak.map(|(p, spread)| NsvPeak {
        frequency_hz: p.frequency_hz,
        amplitude_m: p.amplitude,
        order: p.order,
        forward_m: full_reading(&full, r, p.frequency_hz),
        backward_m: full_reading(&full, r, -p.frequency_hz),
        decay_ratio: records
            .decay_at(p.frequency_hz / r.resolution_hz)
            .unwrap_or_else(|| planners.stretches.decay_ratio(x, p.frequency_hz)),
        settling_ratio: tail.map(|tail| planners.stretches.ratio(&x[..half], tail, p.frequency_hz)),
        standard_error_m: spread.relative_error * p.amplitude,
        variation: spread.variation,
    });
    let mut amplitude = estimate.spectrum.amplitude;
    amplitude.truncate(r.bins);
    Ok(CascadePoint {
        speed,
        speed_hz,
        added: false,
        settle_s: start as f64 / r.sample_rate_hz,
        settled: first.settled(),
        records: count,
        start_fallback,
        diverged: None,
        amplitude,
        full_amplitude: if o.full {
            full_band(&full, r)
        } else {
            Vec::new()
        },
        one_x_m: estimate.one_x_m,
        peak,
    })
}

/// The full spectrum of x + i y power-averaged over `count` records from `start` (one
/// [`hop`] apart).
fn averaged_two_sided(
    x: &[f64],
    y: &[f64],
    start: usize,
    count: usize,
    r: &Resolved,
    planners: &mut Planners,
) -> Result<Vec<f64>> {
    let mut power = vec![0.0; r.samples];
    for k in 0..count {
        let from = start + k * hop(r);
        let full = planners.two_sided(record(x, from, r)?, record(y, from, r)?)?;
        for (p, a) in power.iter_mut().zip(&full) {
            *p += a * a;
        }
    }
    Ok(power
        .into_iter()
        .map(|p| (p / count.max(1) as f64).sqrt())
        .collect())
}

/// The record of `samples` samples from `start`.
fn record<'a>(values: &'a [f64], start: usize, r: &Resolved) -> Result<&'a [f64]> {
    values.get(start..start + r.samples).ok_or_else(|| {
        Error::Internal(format!(
            "the record after settling holds {} samples, fewer than the {} planned",
            values.len().saturating_sub(start),
            r.samples
        ))
    })
}

/// The spectrum of the record of `values` starting at `start`, its 1X and its largest
/// non-synchronous peak with how that peak changed over time (the half record before the
/// record, when there is one, and the record's halves).
fn read(
    values: &[f64],
    start: usize,
    speed_hz: f64,
    o: &CascadeOptions,
    r: &Resolved,
    planners: &mut Planners,
) -> Result<Reading> {
    let x = record(values, start, r)?;
    let spectrum = planners.one_sided(x)?;
    let half = r.samples / 2;
    let tail = start.checked_sub(half).map(|from| &values[from..start]);
    let measured = measure(&spectrum, speed_hz, o.tolerance_bins, r.max_frequency_hz);
    let peak = measured.nsv.map(|p| NsvPeak {
        frequency_hz: p.frequency_hz,
        amplitude_m: p.amplitude,
        order: p.order,
        forward_m: 0.0,
        backward_m: 0.0,
        decay_ratio: planners.stretches.decay_ratio(x, p.frequency_hz),
        settling_ratio: tail.map(|tail| planners.stretches.ratio(&x[..half], tail, p.frequency_hz)),
        standard_error_m: 0.0,
        variation: 0.0,
    });
    Ok(Reading {
        peak,
        one_x_m: measured.one_x_m,
    })
}

/// What the cascade reads off one amplitude spectrum at one running speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// The 1X amplitude, refined between bins ([`amplitude_at`]), m.
    pub one_x_m: f64,
    /// The largest non-synchronous peak at or below the band's top
    /// ([`largest_non_synchronous_below`]); `None` when every peak is synchronous.
    pub nsv: Option<SpectralPeak>,
}

/// The cascade's one measurement of a spectrum taken at running speed `speed_hz`: its 1X
/// and its NSV, a peak counting as synchronous within `tolerance_bins` of a multiple of the
/// running speed, searched up to `max_frequency_hz`. Every reading of a cascade (a record
/// while settling, the averaged records) and each short-time spectrum of a run-up
/// ([`crate::runup`]) is this one, so the two compare like with like.
pub fn measure(
    spectrum: &Spectrum,
    speed_hz: f64,
    tolerance_bins: f64,
    max_frequency_hz: f64,
) -> Measured {
    Measured {
        one_x_m: amplitude_at(spectrum, speed_hz),
        nsv: largest_non_synchronous_below(spectrum, speed_hz, tolerance_bins, max_frequency_hz),
    }
}

/// Whether `peak` is free vibration dying away: it falls over the three stretches (the
/// half record before the record and the record's halves), each below
/// [`DECAY_PER_STRETCH`] of the one before and the later fall at most twice the earlier as
/// an exponential decay does. Two components closer than a bin (a mode's forward and
/// backward whirl, split by a hertz) beat instead: their envelope does not keep falling.
/// Without the stretch before the record, only the halves are compared, against
/// [`TRANSIENT_DECAY`].
pub fn dies_away(peak: &NsvPeak) -> bool {
    let later = peak.decay_ratio;
    match peak.settling_ratio {
        Some(earlier) => {
            // Falling on, not rebounding: the later fall may be steeper (a decay that
            // reaches the level of other components' leakage).
            let falls_on = later <= 2.0 * earlier;
            earlier < DECAY_PER_STRETCH && later < DECAY_PER_STRETCH && falls_on
        }
        None => later < TRANSIENT_DECAY,
    }
}

/// The amplitude below which a dying peak no longer keeps a speed unsettled, m.
pub fn negligible(one_x_m: f64) -> f64 {
    NEGLIGIBLE_M.max(NEGLIGIBLE_FRACTION * one_x_m)
}

/// Index in the full spectrum of the bin at `k` bins from zero (negative below).
fn full_index(r: &Resolved, k: i64) -> Option<usize> {
    usize::try_from(k + (r.samples / 2) as i64)
        .ok()
        .filter(|&j| j < r.samples)
}

/// The largest full-spectrum bin within one bin of `frequency_hz` (signed).
fn full_reading(full: &[f64], r: &Resolved, frequency_hz: f64) -> f64 {
    let position = frequency_hz / r.resolution_hz;
    let (low, high) = (position.floor() as i64, position.ceil() as i64);
    (low - 1..=high + 1)
        .filter(|k| (*k as f64 - position).abs() <= 1.0)
        .filter_map(|k| full_index(r, k))
        .map(|j| full[j])
        .fold(0.0, f64::max)
}

/// Signed bins of the full spectrum kept: -band..=band, within the spectrum.
pub(super) fn full_bins(r: &Resolved) -> std::ops::RangeInclusive<i64> {
    let top = r.bins as i64 - 1;
    let highest = (r.samples - 1 - r.samples / 2) as i64;
    -top..=top.min(highest)
}

/// The full spectrum over [`full_bins`].
fn full_band(full: &[f64], r: &Resolved) -> Vec<f64> {
    full_bins(r)
        .filter_map(|k| full_index(r, k))
        .map(|j| full[j])
        .collect()
}

/// Amplitudes at one frequency in stretches of half a record: how a peak changes while a
/// run settles.
#[derive(Clone)]
struct Stretches {
    /// Hann window of half a record, and the sum of its samples.
    window: Vec<f64>,
    window_sum: f64,
    sample_rate_hz: f64,
}

impl Stretches {
    /// Stretches of `samples` samples at `sample_rate_hz`.
    fn new(samples: usize, sample_rate_hz: f64) -> Self {
        let window = Window::Hann.samples(samples);
        Stretches {
            window_sum: window.iter().sum(),
            window,
            sample_rate_hz,
        }
    }

    /// Amplitude at `frequency_hz` in the second half of the record `x` over that in the
    /// first.
    fn decay_ratio(&self, x: &[f64], frequency_hz: f64) -> f64 {
        let half = x.len() / 2;
        self.ratio(&x[half..2 * half], &x[..half], frequency_hz)
    }

    /// Amplitude at `frequency_hz` in `later` over that in `earlier` (each half a record,
    /// Hann-windowed, mean removed, one DFT term). 1 when `earlier` shows nothing.
    fn ratio(&self, later: &[f64], earlier: &[f64], frequency_hz: f64) -> f64 {
        let first = self.component(earlier, frequency_hz);
        let second = self.component(later, frequency_hz);
        if first > 0.0 {
            second / first
        } else {
            1.0
        }
    }

    /// Hann-windowed amplitude of the half record `x` at `frequency_hz`, mean removed.
    fn component(&self, x: &[f64], frequency_hz: f64) -> f64 {
        let w = &self.window;
        debug_assert_eq!(x.len(), w.len());
        let mean = window_mean(x, w);
        let step = -2.0 * PI * frequency_hz / self.sample_rate_hz;
        // The phasor turned by a fixed rotation from sample to sample and evaluated afresh
        // every PHASOR_RESEED samples: a sine and cosine per sample were a few per cent of a
        // cascade, and following the angle by `Turning` 5 %.
        let turn = step.sin_cos();
        let mut sum = Complex::new(0.0, 0.0);
        for (k, (xs, ws)) in x
            .chunks(PHASOR_RESEED)
            .zip(w.chunks(PHASOR_RESEED))
            .enumerate()
        {
            let mut phase = (step * (k * PHASOR_RESEED) as f64).sin_cos();
            for (v, wn) in xs.iter().zip(ws) {
                let weighted = (v - mean) * wn;
                sum += Complex::new(weighted * phase.1, weighted * phase.0);
                phase = rotate(phase, turn);
            }
        }
        2.0 * sum.norm() / self.window_sum
    }
}

/// Samples between exact evaluations of [`Stretches::component`]'s phasor: each rotation
/// rounds by a few ulps, so the phasor drifts by at most about 1e-14 before it is reset.
const PHASOR_RESEED: usize = 64;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stretch_component_is_the_direct_windowed_sum() {
        // Against sin and cos evaluated at every sample: the rotated phasor drifts by a few
        // ulps per sample between its resets, so 1e-12 of the amplitude bounds it with a
        // wide margin; a wrong reset index or sign shows at order one.
        let (samples, rate) = (7776, 31_104.0);
        let stretches = Stretches::new(samples, rate);
        let x: Vec<f64> = (0..samples)
            .map(|n| {
                let t = n as f64 / rate;
                3e-6 + 2e-6 * (2.0 * PI * 47.3 * t + 0.4).sin()
                    + 5e-7 * (2.0 * PI * 1311.0 * t).cos()
            })
            .collect();
        let w = &stretches.window;
        let mean = window_mean(&x, w);
        for f in [0.5, 47.3, 300.0, 1311.0, 3400.0] {
            let step = -2.0 * PI * f / rate;
            let (re, im) =
                x.iter()
                    .zip(w)
                    .enumerate()
                    .fold((0.0, 0.0), |(re, im), (n, (v, wn))| {
                        let (sin, cos) = (step * n as f64).sin_cos();
                        (re + (v - mean) * wn * cos, im + (v - mean) * wn * sin)
                    });
            let direct = 2.0 * re.hypot(im) / w.iter().sum::<f64>();
            let fast = stretches.component(&x, f);
            assert!(
                (fast - direct).abs() <= 1e-12 * 2e-6,
                "{f} Hz: {fast} vs {direct}"
            );
        }
    }

    fn peak(decay_ratio: f64, settling_ratio: Option<f64>) -> NsvPeak {
        NsvPeak {
            frequency_hz: 47.0,
            amplitude_m: 1e-6,
            order: 0.235,
            forward_m: 1e-6,
            backward_m: 2e-7,
            decay_ratio,
            settling_ratio,
            standard_error_m: 0.0,
            variation: 0.0,
        }
    }

    #[test]
    fn a_peak_dies_away_when_it_keeps_falling() {
        // Falling by about 0.2 per stretch, twice: an exponential decay.
        assert!(dies_away(&peak(0.2, Some(0.25))));
        // Steady, then falling: a beat, not a decay.
        assert!(!dies_away(&peak(0.2, Some(0.9))));
        // Without the settling stretch, only a fall below TRANSIENT_DECAY counts.
        assert!(!dies_away(&peak(0.3, None)));
        assert!(dies_away(&peak(0.1, None)));
    }

    /// Records of a sine at 10 Hz (exactly on a bin) whose amplitude is `amplitudes` record
    /// by record, averaged as a settled speed's are (each record its own sine, so the
    /// scatter is known exactly; overlapping records are tested with a steady sine).
    fn averaged(amplitudes: &[f64]) -> (Records, Resolved, CascadeOptions) {
        let (o, r) = one_hertz_bins();
        let mut planners = Planners::new(&o, &r).unwrap();
        let mut records = Records::default();
        for a in amplitudes {
            records.push(planners.one_sided(&sine(*a, 1000)).unwrap());
        }
        (records, r, o)
    }

    /// Options and sampling of 1 s records at 1 kHz (1 Hz bins).
    fn one_hertz_bins() -> (CascadeOptions, Resolved) {
        let model =
            crate::model::Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let mut o = CascadeOptions::new(&model, vec![1.0]);
        o.record = 1.0;
        let r = Resolved {
            step: 1e-3,
            record_every: 1,
            samples: 1000,
            sample_rate_hz: 1000.0,
            resolution_hz: 1.0,
            max_frequency_hz: 100.0,
            bins: 101,
        };
        (o, r)
    }

    /// `len` samples of a 10 Hz sine of amplitude `a` at 1 kHz.
    fn sine(a: f64, len: usize) -> Vec<f64> {
        (0..len)
            .map(|n| a * (2.0 * PI * 10.0 * n as f64 / 1000.0).sin())
            .collect()
    }

    #[test]
    fn overlapping_records_keep_a_steady_sine() {
        // Running at 40 Hz: 10 Hz is a quarter of the running speed, non-synchronous.
        let (o, r) = one_hertz_bins();
        let values = sine(2.0, 2500);
        assert_eq!(
            records_in(values.len(), &r),
            4,
            "2.5 records' time holds 4 halves"
        );
        let mut planners = Planners::new(&o, &r).unwrap();
        let mut steady = Records::default();
        steady.extend(&values, 0, 4, &r, &mut planners).unwrap();
        let (p, spread) = steady.estimate(40.0, &o, &r).peak.unwrap();
        // An integer number of periods on a bin: the Hann spectrum is exact to round-off.
        assert!((p.amplitude - 2.0).abs() < 1e-9, "{}", p.amplitude);
        assert!(spread.relative_error < 1e-9 && spread.variation < 1e-9);
    }

    #[test]
    fn averaging_measures_a_wandering_sine_with_its_correlation() {
        let speed_hz = 40.0;
        let (wandering, r, o) = averaged(&[1.0, 3.0, 1.0, 3.0]);
        let (p, spread) = wandering.estimate(speed_hz, &o, &r).peak.unwrap();
        // Power average: sqrt((1 + 9) / 2). The powers 1, 9, 1, 9 have a sample standard
        // deviation of 4.6188 (n - 1) and a negative correlation at one record, so the
        // overlap's least correlation 1/36 inflates the variance: the amplitude's relative
        // standard error is 0.5 * 4.6188 / 5 * sqrt((1 + 2/36) / 4) = 0.237273; the
        // amplitudes' variation is 1.1547 / 2 = 0.57735.
        assert!((p.amplitude - 5f64.sqrt()).abs() < 1e-9, "{}", p.amplitude);
        assert!(
            (spread.relative_error - 0.237_273).abs() < 1e-5,
            "{spread:?}"
        );
        assert!((spread.variation - 0.577_350).abs() < 1e-5, "{spread:?}");

        // Pairs of equal records: correlated at one record (0.125), anti-correlated at two
        // (taken as 0): inflation 1.25, so 0.5 * 4.2762 / 5 * sqrt(1.25 / 8) = 0.169030.
        let (paired, r, o) = averaged(&[1.0, 1.0, 3.0, 3.0, 1.0, 1.0, 3.0, 3.0]);
        let (_, spread) = paired.estimate(speed_hz, &o, &r).peak.unwrap();
        assert!(
            (spread.relative_error - 0.169_030).abs() < 1e-5,
            "{spread:?}"
        );
    }

    #[test]
    fn averaging_stops_once_the_peak_is_known_or_clear_of_every_level() {
        let speed_hz = 40.0;
        let (wandering, r, o) = averaged(&[1.0, 3.0, 1.0, 3.0]);
        let e = wandering.estimate(speed_hz, &o, &r);
        // Amplitude 2.236 with a relative standard error of 0.237 (0.531 absolute).
        let mut a = Averaging::default();
        assert!(!e.converged(&a, &[]), "5 % is not met");
        a.relative_error = 0.25;
        assert!(e.converged(&a, &[]), "25 % is");
        a.relative_error = 0.05;
        a.decided_error = 0.25;
        // Clear of a level at 1.0 (2.3 standard errors) and of one at 5.0 (5.2): decided.
        assert!(e.converged(&a, &[1.0, 5.0]));
        // 2.0 is within 0.5 standard errors: more records could cross it.
        assert!(!e.converged(&a, &[1.0, 2.0]));
        // Clear, but the error is above the decided tolerance.
        a.decided_error = 0.2;
        assert!(!e.converged(&a, &[1.0, 5.0]));
    }

    #[test]
    fn a_dying_peak_far_below_the_1x_is_negligible() {
        assert!((negligible(1e-4) - 1e-7).abs() < 1e-20);
        assert_eq!(negligible(1e-8), NEGLIGIBLE_M);
    }
}
