//! Coexisting motions: the same cascade from the other start, speed by speed.
//!
//! Averaged records make the NSV of one steady motion independent of the start (its
//! amplitude is known to its standard error). A speed can still hold two steady motions
//! (a super-harmonic orbit beside a whirl of the first mode, say), and which one a run
//! settles on depends on where it starts. The cascade is run again from the other start
//! ([`Initial::Rest`] after the static equilibrium, and the reverse) at exactly the speeds of
//! the first run ([`other_start_options`]), and [`compare_starts`] marks the speeds where the two NSV amplitudes differ by
//! more than three standard errors of their difference: two estimates of one steady motion
//! disagree by that much in about 0.3 % of cases, so such a speed most likely has two
//! motions (or one that switches more slowly than the records can average).

use serde::Serialize;

use super::{Cascade, CascadeOptions, CascadePoint};
use crate::error::{InputError, Result};
use crate::time::Initial;

/// Standard errors of the difference beyond which two starts are said to differ.
pub const STARTS_DIFFER_SIGMAS: f64 = 3.0;

/// The NSV at one speed from both starts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StartPair {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// NSV amplitude from the first start (0 where there is no non-synchronous peak), m.
    pub first_m: f64,
    /// Its standard error, m.
    pub first_error_m: f64,
    /// NSV amplitude from the other start, m.
    pub other_m: f64,
    /// Its standard error, m.
    pub other_error_m: f64,
    /// Both runs settled and did not diverge: the two amplitudes can be compared.
    pub comparable: bool,
    /// The amplitudes differ by more than [`STARTS_DIFFER_SIGMAS`] standard errors of their
    /// difference and the larger reaches the threshold.
    pub differs: bool,
}

/// The cascade from the other start and the comparison at every speed.
#[derive(Debug, Clone)]
pub struct StartComparison {
    /// The start of the second run.
    pub other: Initial,
    /// The second run itself (its points at the first run's speeds, no refinement).
    pub cascade: Cascade,
    /// One pair per speed, ascending.
    pub pairs: Vec<StartPair>,
}

impl StartComparison {
    /// Speeds where the two starts differ, Hz.
    pub fn differing_speeds_hz(&self) -> Vec<f64> {
        self.pairs
            .iter()
            .filter(|p| p.differs)
            .map(|p| p.speed_hz)
            .collect()
    }

    /// Speeds compared (both settled, neither diverged).
    pub fn compared(&self) -> usize {
        self.pairs.iter().filter(|p| p.comparable).count()
    }
}

/// The start a second run uses to test `first`.
pub fn other_start(first: Initial) -> Initial {
    match first {
        Initial::StaticEquilibrium => Initial::Rest,
        Initial::Rest => Initial::StaticEquilibrium,
    }
}

/// The options of the run that tests `first` from the other start: exactly its speeds
/// (requested and added), refinement off, every other option the same.
pub fn other_start_options(first: &Cascade) -> CascadeOptions {
    let mut options = CascadeOptions {
        initial: other_start(first.options.initial),
        speeds: first.points.iter().map(|p| p.speed).collect(),
        ..first.options.clone()
    };
    options.refine.enabled = false;
    options
}

/// Compares `first` with `second`, its cascade from the other start
/// ([`other_start_options`]), speed by speed; a peak counts as differing only when the
/// larger of the two reaches `threshold_m` (m), so noise below the level that matters is
/// never reported.
///
/// # Errors
///
/// [`crate::Error::Input`] when `second` is not at `first`'s speeds.
pub fn compare_starts(
    first: &Cascade,
    second: Cascade,
    threshold_m: f64,
) -> Result<StartComparison> {
    let same_speeds = first.points.len() == second.points.len()
        && first
            .points
            .iter()
            .zip(&second.points)
            .all(|(a, b)| a.speed == b.speed);
    if !same_speeds {
        return Err(InputError::field(
            "speeds",
            "the second cascade is not at the first one's speeds",
        )
        .help("run it with other_start_options(first)")
        .into());
    }
    let pairs = first
        .points
        .iter()
        .zip(&second.points)
        .map(|(a, b)| pair(a, b, threshold_m))
        .collect();
    Ok(StartComparison {
        other: second.options.initial,
        cascade: second,
        pairs,
    })
}

/// The NSV of one speed from both starts, compared.
fn pair(first: &CascadePoint, other: &CascadePoint, threshold_m: f64) -> StartPair {
    let read = |p: &CascadePoint| {
        p.peak
            .map_or((0.0, 0.0), |peak| (peak.amplitude_m, peak.standard_error_m))
    };
    let (first_m, first_error_m) = read(first);
    let (other_m, other_error_m) = read(other);
    let comparable = [first, other]
        .iter()
        .all(|p| p.settled && p.diverged.is_none());
    let beyond_errors =
        (first_m - other_m).abs() > STARTS_DIFFER_SIGMAS * first_error_m.hypot(other_error_m);
    StartPair {
        speed_hz: first.speed_hz,
        first_m,
        first_error_m,
        other_m,
        other_error_m,
        comparable,
        differs: comparable && beyond_errors && first_m.max(other_m) >= threshold_m,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nsv::NsvPeak;

    fn point(amplitude_m: f64, standard_error_m: f64) -> CascadePoint {
        let peak = NsvPeak {
            frequency_hz: 50.0,
            amplitude_m,
            order: 0.5,
            forward_m: amplitude_m,
            backward_m: 0.0,
            decay_ratio: 1.0,
            settling_ratio: None,
            standard_error_m,
            variation: 0.0,
        };
        CascadePoint::settled_at(100.0, 1e-5, Some(peak))
    }

    #[test]
    fn two_starts_differ_only_beyond_three_standard_errors_and_above_the_threshold() {
        let threshold = 1e-6;
        // Difference 1.0 um against 3 x hypot(0.2, 0.2) = 0.85 um: differs.
        assert!(pair(&point(10e-6, 0.2e-6), &point(9e-6, 0.2e-6), threshold).differs);
        // Against 3 x hypot(0.3, 0.3) = 1.27 um: within the errors.
        assert!(!pair(&point(10e-6, 0.3e-6), &point(9e-6, 0.3e-6), threshold).differs);
        // Far apart in ratio, but both below the threshold: not reported.
        assert!(!pair(&point(0.5e-6, 0.0), &point(0.1e-6, 0.0), threshold).differs);
        // An unsettled run cannot be compared.
        let mut unsettled = point(9e-6, 0.0);
        unsettled.settled = false;
        let p = pair(&point(20e-6, 0.0), &unsettled, threshold);
        assert!(!p.comparable && !p.differs);
    }
}
