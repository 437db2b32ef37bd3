//! The settings of a harmonic-balance sweep as a request gives them: every one optional,
//! `None` meaning the library's default. `whirl hbm`, `whirl map` and the NSV map's request
//! fill one [`SweepSettings`] and turn it into [`SweepOptions`] here, so that a default and
//! the way the settings compose are written once.

use serde::Serialize;

use super::bearings::CageModel;
use super::condensation::DEFAULT_STABILITY_MODES;
use super::sweep::SweepOptions;
use crate::bearing::ContactLaw;

/// Harmonics H of the running speed when a request gives none: the count every measurement
/// of the reference rotor in docs/theory.md section 7 is made with (its contact forces'
/// spectra decay slowly, and each harmonic more costs about (2H + 1)^3 in the dense Newton
/// solves; `whirl hbm --harmonics-study` shows the convergence in H).
pub const DEFAULT_HARMONICS: usize = 5;

/// The discretisation and model of a sweep; `None` takes the default of
/// [`SweepOptions::new`] (or [`DEFAULT_HARMONICS`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SweepSettings {
    /// Harmonics H of the running speed.
    pub harmonics: Option<usize>,
    /// AFT samples per period ([`super::default_samples`] when `None`).
    pub samples: Option<usize>,
    /// Contact law of the roller bearings (Hertz when `None`).
    pub contact: Option<ContactLaw>,
    /// How the Hertz bearings' roller passage is made periodic ([`CageModel::DEFAULT`]).
    pub cage: Option<CageModel>,
    /// Approach below which the Hertz law is blended, m (0, the exact law, when `None`).
    pub contact_smoothing: Option<f64>,
    /// Floquet stability at every point (on when `None`).
    pub stability: Option<bool>,
    /// Fixed-interface modes of the stability model ([`DEFAULT_STABILITY_MODES`]).
    pub stability_modes: Option<usize>,
    /// Craig-Bampton modes of the solved model; `None` for the full model.
    pub reduction: Option<usize>,
}

impl SweepSettings {
    /// Harmonics H, given or [`DEFAULT_HARMONICS`].
    pub fn harmonics(&self) -> usize {
        self.harmonics.unwrap_or(DEFAULT_HARMONICS)
    }

    /// The options of a sweep from `from` to `to` (rad/s) with these settings.
    pub fn options(&self, from: f64, to: f64) -> SweepOptions {
        let mut options = SweepOptions::new(from, to, self.harmonics());
        // Checked with the harmonic count by the sweep, before anything is allocated.
        options.samples = self.samples;
        options.contact = self.contact.unwrap_or(options.contact);
        options.cage = self.cage.unwrap_or(options.cage);
        options.contact_smoothing = self.contact_smoothing.unwrap_or(options.contact_smoothing);
        options.stability = self.stability.unwrap_or(options.stability);
        options.stability_modes = self.stability_modes.unwrap_or(DEFAULT_STABILITY_MODES);
        options.reduction = self.reduction;
        options
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_setting_gives_the_sweeps_own_defaults() {
        let from_settings = SweepSettings::default().options(1.0, 2.0);
        let direct = SweepOptions::new(1.0, 2.0, DEFAULT_HARMONICS);
        assert_eq!(
            serde_json::to_string(&from_settings).ok(),
            serde_json::to_string(&direct).ok()
        );
    }
}
