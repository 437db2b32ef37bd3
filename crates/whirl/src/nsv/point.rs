//! One speed of a cascade: simulate until the start has died away (or a cap), take the
//! spectra of the record, and find its largest non-synchronous peak with its whirl
//! direction and how it changes over time.
//!
//! # Settling by decay
//!
//! The record is the last `record` seconds of the run, and the run ends at the first of
//! these checks (every half record, from `settle + record` on) that finds the record
//! settled: its largest non-synchronous peak is steady (it does not keep falling over the
//! three stretches of [`dies_away`]), or negligible ([`negligible`]). A run that reaches
//! `settle_max` unsettled keeps its last record and is marked so: its peak is free
//! vibration still dying away, never an NSV of any class.

use std::f64::consts::PI;
use std::ops::ControlFlow;

use num_complex::Complex;
use serde::{Deserialize, Serialize};

use super::options::{CascadeOptions, Component, Resolved};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::post::{
    amplitude_at, largest_non_synchronous_below, FullSpectrumPlanner, Spectrum, SpectrumOptions,
    SpectrumPlanner, Window,
};
use crate::time::{simulate_response, Method, RunStatus, SimulationOptions, SpeedProfile, Until};
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
    /// Amplitude at this frequency in the record's second half over that in its first
    /// half: about 1 for a steady vibration, well below 1 for free vibration still dying
    /// away.
    pub decay_ratio: f64,
    /// Amplitude at this frequency in the record's first half over that in the equally
    /// long stretch just before the record (the end of the settling time); `None` when the
    /// settling time is shorter than half the record.
    pub settling_ratio: Option<f64>,
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

/// The spectra of one record length, planned once and reused by the speeds a thread
/// computes.
#[derive(Clone)]
pub(super) struct Planners {
    one_sided: SpectrumPlanner,
    full: FullSpectrumPlanner,
    window: Vec<f64>,
}

impl Planners {
    pub(super) fn new(o: &CascadeOptions, r: &Resolved) -> Result<Planners> {
        let options = SpectrumOptions::window(o.window);
        Ok(Planners {
            one_sided: SpectrumPlanner::new(r.samples, r.sample_rate_hz, options)?,
            full: FullSpectrumPlanner::new(r.samples, r.sample_rate_hz, options)?,
            window: o.window.samples(r.samples),
        })
    }

    /// The whole one-sided spectrum of `x` (up to Nyquist: peaks are refined with
    /// neighbours beyond the band).
    fn one_sided(&mut self, x: &[f64]) -> Result<Spectrum> {
        let centred = centred(x, &self.window);
        self.one_sided.spectrum(&centred)
    }

    /// The whole full spectrum of x + i y, bins ascending from -Nyquist.
    fn two_sided(&mut self, x: &[f64], y: &[f64]) -> Result<Vec<f64>> {
        let mut amplitude = vec![0.0; x.len()];
        let (x, y) = (centred(x, &self.window), centred(y, &self.window));
        self.full.process(&x, &y, &mut amplitude)?;
        Ok(amplitude)
    }
}

/// A record's one-sided spectrum and its largest non-synchronous peak (without the full
/// spectrum's whirl radii).
struct Reading {
    spectrum: Spectrum,
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

/// Simulates and analyses one speed (rad/s). A run that diverges is a point with its
/// message and no spectra, not an error: the cascade goes on.
pub(super) fn compute(
    model: &Model,
    o: &CascadeOptions,
    r: &Resolved,
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
        // Two samples more than the record, so that rounding of the step count never
        // leaves it a sample short.
        duration: o.settle_max.max(o.settle) + o.record + 2.0 / r.sample_rate_hz,
        step: r.step,
        method: Method::CentralDifference,
        reduction: o.reduction,
        settle: o.settle,
        nodes: vec![o.node],
        initial: o.initial,
        divergence_bound: o.divergence_bound,
        progress: None,
    };
    // The record's start where a check found it settled.
    let mut settled_at: Option<usize> = None;
    let mut failure: Option<Error> = None;
    let half = (r.samples / 2).max(1);
    let mut decide = |values: &[Vec<f64>]| {
        let start = values[channel].len().saturating_sub(r.samples);
        if start < first_start || start >= last_start {
            return ControlFlow::Continue(());
        }
        match read(&values[channel], start, speed_hz, o, r, planners) {
            Ok(reading) if reading.settled() => {
                settled_at = Some(start);
                ControlFlow::Break(())
            }
            Ok(_) => ControlFlow::Continue(()),
            Err(e) => {
                failure = Some(e);
                ControlFlow::Break(())
            }
        }
    };
    let until = (last_start > first_start).then_some(Until {
        every: half,
        decide: &mut decide,
    });
    let result = simulate_response(model, &simulation, o.law, r.record_every, until)?;
    if let Some(e) = failure {
        return Err(e);
    }
    if let RunStatus::Diverged { message, .. } = &result.status {
        return Ok(CascadePoint {
            speed,
            speed_hz,
            added: false,
            settle_s: 0.0,
            settled: false,
            diverged: Some(message.clone()),
            amplitude: Vec::new(),
            full_amplitude: Vec::new(),
            one_x_m: 0.0,
            peak: None,
        });
    }
    let start = settled_at.unwrap_or(last_start);
    let x = record(&result.channels[0].values, start, r)?;
    let y = record(&result.channels[1].values, start, r)?;
    let reading = read(
        &result.channels[channel].values,
        start,
        speed_hz,
        o,
        r,
        planners,
    )?;
    let settled = reading.settled();
    let full = planners.two_sided(x, y)?;
    let peak = reading.peak.map(|p| NsvPeak {
        forward_m: full_reading(&full, r, p.frequency_hz),
        backward_m: full_reading(&full, r, -p.frequency_hz),
        ..p
    });
    let mut amplitude = reading.spectrum.amplitude;
    amplitude.truncate(r.bins);
    Ok(CascadePoint {
        speed,
        speed_hz,
        added: false,
        settle_s: start as f64 / r.sample_rate_hz,
        settled,
        diverged: None,
        amplitude,
        full_amplitude: if o.full {
            full_band(&full, r)
        } else {
            Vec::new()
        },
        one_x_m: reading.one_x_m,
        peak,
    })
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
    let peak =
        largest_non_synchronous_below(&spectrum, speed_hz, o.tolerance_bins, r.max_frequency_hz)
            .map(|p| NsvPeak {
                frequency_hz: p.frequency_hz,
                amplitude_m: p.amplitude,
                order: p.order,
                forward_m: 0.0,
                backward_m: 0.0,
                decay_ratio: decay_ratio(x, p.frequency_hz, r.sample_rate_hz),
                settling_ratio: tail
                    .map(|tail| ratio(&x[..half], tail, p.frequency_hz, r.sample_rate_hz)),
            });
    let one_x_m = amplitude_at(&spectrum, speed_hz);
    Ok(Reading {
        spectrum,
        peak,
        one_x_m,
    })
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

/// The mean as the window weighs it: removing it leaves nothing at DC (the static sag
/// would otherwise be the largest "peak"), where the plain mean of a record that is not a
/// whole number of periods would leak into the first bins.
fn weighted_mean(x: &[f64], window: &[f64]) -> f64 {
    let sum: f64 = window.iter().sum();
    x.iter().zip(window).map(|(v, w)| v * w).sum::<f64>() / sum
}

fn centred(x: &[f64], window: &[f64]) -> Vec<f64> {
    let mean = weighted_mean(x, window);
    x.iter().map(|v| v - mean).collect()
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

/// Amplitude at `frequency_hz` in the second half of `x` over that in the first.
fn decay_ratio(x: &[f64], frequency_hz: f64, sample_rate_hz: f64) -> f64 {
    let half = x.len() / 2;
    ratio(&x[half..2 * half], &x[..half], frequency_hz, sample_rate_hz)
}

/// Amplitude at `frequency_hz` in `later` over that in `earlier` (each Hann-windowed, mean
/// removed, one DFT term). 1 when `earlier` shows nothing.
fn ratio(later: &[f64], earlier: &[f64], frequency_hz: f64, sample_rate_hz: f64) -> f64 {
    let first = component(earlier, frequency_hz, sample_rate_hz);
    let second = component(later, frequency_hz, sample_rate_hz);
    if first > 0.0 {
        second / first
    } else {
        1.0
    }
}

/// Hann-windowed amplitude of `x` at `frequency_hz`, mean removed.
fn component(x: &[f64], frequency_hz: f64, sample_rate_hz: f64) -> f64 {
    let w = Window::Hann.samples(x.len());
    let x = centred(x, &w);
    let step = -2.0 * PI * frequency_hz / sample_rate_hz;
    let sum: Complex<f64> = x
        .iter()
        .zip(&w)
        .enumerate()
        .map(|(n, (v, wn))| Complex::from_polar(v * wn, step * n as f64))
        .sum();
    2.0 * sum.norm() / w.iter().sum::<f64>()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peak(decay_ratio: f64, settling_ratio: Option<f64>) -> NsvPeak {
        NsvPeak {
            frequency_hz: 47.0,
            amplitude_m: 1e-6,
            order: 0.235,
            forward_m: 1e-6,
            backward_m: 2e-7,
            decay_ratio,
            settling_ratio,
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

    #[test]
    fn a_dying_peak_far_below_the_1x_is_negligible() {
        assert!((negligible(1e-4) - 1e-7).abs() < 1e-20);
        assert_eq!(negligible(1e-8), NEGLIGIBLE_M);
    }
}
