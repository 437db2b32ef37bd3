//! One speed of a cascade: simulate past the settling time, take the spectra of the
//! record, and find its largest non-synchronous peak with its whirl direction and whether
//! it is still dying away.

use std::f64::consts::PI;

use num_complex::Complex;
use serde::{Deserialize, Serialize};

use super::options::{CascadeOptions, Component, Resolved};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::post::{
    amplitude_at, largest_non_synchronous_below, FullSpectrumPlanner, Spectrum, SpectrumOptions,
    SpectrumPlanner, Window,
};
use crate::time::{
    simulate_response, Initial, Method, RunStatus, SimulationOptions, SimulationResult,
    SpeedProfile,
};
use crate::units::rad_s_to_hz;

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

/// Simulates and analyses one speed (rad/s). A run that diverges is a point with its
/// message and no spectra, not an error: the cascade goes on.
pub(super) fn compute(
    model: &Model,
    o: &CascadeOptions,
    r: &Resolved,
    speed: f64,
) -> Result<CascadePoint> {
    let simulation = SimulationOptions {
        speed: SpeedProfile::Constant(speed),
        // Two samples more than the record, so that rounding of the step count never
        // leaves it a sample short.
        duration: o.settle + o.record + 2.0 / r.sample_rate_hz,
        step: r.step,
        method: Method::CentralDifference,
        reduction: o.reduction,
        settle: o.settle,
        nodes: vec![o.node],
        initial: Initial::StaticEquilibrium,
        divergence_bound: o.divergence_bound,
        progress: None,
    };
    let result = simulate_response(model, &simulation, o.law, r.record_every)?;
    let speed_hz = rad_s_to_hz(speed);
    if let RunStatus::Diverged { message, .. } = &result.status {
        return Ok(CascadePoint {
            speed,
            speed_hz,
            diverged: Some(message.clone()),
            amplitude: Vec::new(),
            full_amplitude: Vec::new(),
            one_x_m: 0.0,
            peak: None,
        });
    }
    let (x, y) = settled_record(&result, r)?;
    let channel = match o.component {
        Component::Ux => 0,
        Component::Uy => 1,
    };
    let chosen = [&x, &y][channel];
    let tail = settling_tail(&result.channels[channel].values, result.settled_start(), r);
    let spectrum = one_sided(chosen, o.window, r)?;
    let full = two_sided(&x, &y, o.window, r)?;
    let peak =
        largest_non_synchronous_below(&spectrum, speed_hz, o.tolerance_bins, r.max_frequency_hz)
            .map(|p| NsvPeak {
                frequency_hz: p.frequency_hz,
                amplitude_m: p.amplitude,
                order: p.order,
                forward_m: full_reading(&full, r, p.frequency_hz),
                backward_m: full_reading(&full, r, -p.frequency_hz),
                decay_ratio: decay_ratio(chosen, p.frequency_hz, r.sample_rate_hz),
                settling_ratio: tail.map(|tail| {
                    let first_half = &chosen[..r.samples / 2];
                    ratio(first_half, tail, p.frequency_hz, r.sample_rate_hz)
                }),
            });
    let one_x_m = amplitude_at(&spectrum, speed_hz);
    let mut amplitude = spectrum.amplitude;
    amplitude.truncate(r.bins);
    Ok(CascadePoint {
        speed,
        speed_hz,
        diverged: None,
        amplitude,
        full_amplitude: if o.full {
            full_band(&full, r)
        } else {
            Vec::new()
        },
        one_x_m,
        peak,
    })
}

/// The first `samples` samples of the response node's x and y after the settling time.
fn settled_record(result: &SimulationResult, r: &Resolved) -> Result<(Vec<f64>, Vec<f64>)> {
    let start = result.settled_start();
    let end = start + r.samples;
    let take = |i: usize| -> Result<Vec<f64>> {
        let values = &result.channels[i].values;
        values.get(start..end).map(<[f64]>::to_vec).ok_or_else(|| {
            Error::Numerical(format!(
                "the record after settling holds {} samples, fewer than the {} planned",
                values.len().saturating_sub(start),
                r.samples
            ))
        })
    };
    // The run records one node: channel 0 is its u_x, channel 1 its u_y.
    Ok((take(0)?, take(1)?))
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

/// The whole one-sided spectrum (up to Nyquist: peaks are refined with neighbours beyond
/// the band).
fn one_sided(x: &[f64], window: Window, r: &Resolved) -> Result<Spectrum> {
    let w = window.samples(x.len());
    SpectrumPlanner::new(x.len(), r.sample_rate_hz, SpectrumOptions::window(window))?
        .spectrum(&centred(x, &w))
}

/// The whole full spectrum of x + i y, bins ascending from -Nyquist.
fn two_sided(x: &[f64], y: &[f64], window: Window, r: &Resolved) -> Result<Vec<f64>> {
    let w = window.samples(x.len());
    let mut planner =
        FullSpectrumPlanner::new(x.len(), r.sample_rate_hz, SpectrumOptions::window(window))?;
    let mut amplitude = vec![0.0; x.len()];
    planner.process(&centred(x, &w), &centred(y, &w), &mut amplitude)?;
    Ok(amplitude)
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

/// The half record's worth of samples of `values` just before `start`, if there are
/// that many.
fn settling_tail<'a>(values: &'a [f64], start: usize, r: &Resolved) -> Option<&'a [f64]> {
    let half = r.samples / 2;
    start.checked_sub(half).map(|from| &values[from..start])
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
