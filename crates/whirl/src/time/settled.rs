//! "Settle, then analyse the record": what the settled part of each recorded channel of a
//! run shows. One analysis for `whirl simulate` and the harmonic-balance comparison.
//!
//! The spectrum is the flat-top amplitude spectrum (it reads a peak's amplitude within
//! 0.05 % wherever it falls between bins) with the mean as the window weighs it removed
//! ([`crate::post::window_mean`]): the static sag under gravity would otherwise be the
//! largest "peak", and the plain mean of a record that is not a whole number of periods
//! would leak into the first bins. The 1X comes from order tracking over the shaft angle
//! ([`order_component`]), in the phase convention of the unbalance response.

use serde::Serialize;

use super::SimulationResult;
use crate::error::{Error, Result};
use crate::post::spectrum::MIN_SAMPLES;
use crate::post::{
    amplitude_spectrum_with, largest_non_synchronous, order_component, spectral_peaks, window_mean,
    OrderComponent, SpectralPeak, Spectrum, SpectrumOptions, Window,
};
use crate::system::SpeedProfile;
use crate::units::rad_s_to_hz;

/// Peaks within this many bins of an order of the running speed are synchronous.
pub const ORDER_TOLERANCE_BINS: f64 = 2.0;

/// Multiples of the running speed up to this one count as synchronous.
pub const MAX_ORDER: usize = 20;

/// Peaks listed per channel.
pub const MAX_PEAKS: usize = 10;

/// The smallest peak listed, relative to the channel's largest: 80 dB, about the flat-top
/// window's side-lobe level, below which peaks may be leakage.
pub const MIN_PEAK_RELATIVE: f64 = 1e-4;

/// What the settled part of one channel shows.
#[derive(Debug, Clone, Serialize)]
pub struct SettledChannel {
    /// `n10.ux`.
    pub name: String,
    /// Node.
    pub node: usize,
    /// Mean as the spectrum's window weighs it (the static position), m.
    pub mean: f64,
    /// Flat-top amplitude spectrum, that mean removed.
    pub spectrum: Spectrum,
    /// Largest peaks, largest first (at most [`MAX_PEAKS`], down to
    /// [`MIN_PEAK_RELATIVE`] of the largest).
    pub peaks: Vec<SpectralPeak>,
    /// The 1X component; `None` at zero speed.
    pub one_x: Option<OrderComponent>,
    /// Largest minus smallest value, m.
    pub peak_to_peak: f64,
    /// Largest peak not within [`ORDER_TOLERANCE_BINS`] of an order up to [`MAX_ORDER`].
    pub non_synchronous: Option<SpectralPeak>,
}

impl SimulationResult {
    /// The settled part of every channel (from [`SimulationResult::settled_start`]),
    /// analysed at the running speed the run ended at; `speed` is the run's profile.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] when the settled part holds fewer samples than a spectrum
    /// needs ([`MIN_SAMPLES`]); those of [`order_component`].
    pub fn settled(&self, speed: &SpeedProfile) -> Result<Vec<SettledChannel>> {
        let start = self.settled_start();
        let settled_time = &self.time[start..];
        if settled_time.len() < MIN_SAMPLES {
            return Err(Error::InvalidOption(format!(
                "the settled part holds {} samples; a spectrum needs at least {MIN_SAMPLES}: \
                 settle for less time, run longer, or record more often",
                settled_time.len()
            )));
        }
        let running_hz = self
            .time
            .last()
            .map_or(0.0, |&t| rad_s_to_hz(speed.at(t).0.speed));
        let angle: Vec<f64> = settled_time.iter().map(|&t| speed.at(t).0.angle).collect();
        let window = Window::FlatTop.samples(settled_time.len());
        let options = SpectrumOptions {
            window: Window::FlatTop,
            remove_mean: true,
        };
        self.channels
            .iter()
            .map(|c| {
                let x = &c.values[start..];
                let spectrum = amplitude_spectrum_with(x, 1.0 / self.sample_interval(), options)?;
                let one_x = if running_hz > 0.0 {
                    Some(order_component(&angle, x, 1.0)?)
                } else {
                    None
                };
                let (low, high) = x
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
                        (l.min(v), h.max(v))
                    });
                Ok(SettledChannel {
                    name: c.name.clone(),
                    node: c.node,
                    mean: window_mean(x, &window),
                    peaks: spectral_peaks(&spectrum, running_hz, MIN_PEAK_RELATIVE, MAX_PEAKS),
                    non_synchronous: largest_non_synchronous(
                        &spectrum,
                        running_hz,
                        ORDER_TOLERANCE_BINS,
                        MAX_ORDER,
                    ),
                    spectrum,
                    one_x,
                    peak_to_peak: high - low,
                })
            })
            .collect()
    }
}
