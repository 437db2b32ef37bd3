//! The NSV of a whole cascade in a few numbers: where it starts, how large it gets, and
//! what kind dominates.

use serde::Serialize;

use super::classify::{Nsv, NsvClass, WhirlDirection};

/// Default NSV threshold, m: 1 um zero-to-peak at the disk, about a thirtieth of the
/// largest NSV the thesis reports for the reference rotor (3e-5 m at 20 um clearance,
/// fig. 5.5) and 40 times the amplitude of the reference rotor's 4e-5 m unbalance would
/// need to excite at rest; below it a peak is a detail of the spectrum, above it a
/// vibration an engineer would look at.
pub const DEFAULT_THRESHOLD_M: f64 = 1e-6;

/// The largest NSV of a cascade.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LargestNsv {
    /// Spin speed, Hz.
    pub speed_hz: f64,
    /// Frequency, Hz.
    pub frequency_hz: f64,
    /// Zero-to-peak amplitude, m.
    pub amplitude_m: f64,
    /// Frequency over running speed.
    pub order: f64,
    /// Its class.
    pub class: NsvClass,
    /// Its whirl direction.
    pub direction: WhirlDirection,
}

/// How many speeds' NSV above the threshold fall in one class, and their largest.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClassCount {
    /// The class.
    pub class: NsvClass,
    /// Speeds whose NSV is of this class and at or above the threshold.
    pub speeds: usize,
    /// The largest of them, m.
    pub largest_m: f64,
    /// Their amplitudes summed, m (what "dominant" weighs).
    pub total_m: f64,
}

/// The NSV of a cascade in a few numbers. Transient peaks (free vibration still dying
/// away) are counted in `classes` but never make the onset, the largest or the dominant
/// class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NsvSummary {
    /// The threshold applied, m.
    pub threshold_m: f64,
    /// The lowest speed whose steady NSV reaches the threshold, Hz.
    pub onset_speed_hz: Option<f64>,
    /// The largest steady NSV, wherever it is (threshold or not).
    pub largest: Option<LargestNsv>,
    /// The class with the largest summed amplitude over the speeds at or above the
    /// threshold.
    pub dominant_class: Option<NsvClass>,
    /// Speeds whose steady NSV reaches the threshold.
    pub speeds_above_threshold: usize,
    /// Per class, the speeds at or above the threshold (classes with none left out).
    pub classes: Vec<ClassCount>,
    /// Speeds whose run diverged, Hz.
    pub diverged_speeds_hz: Vec<f64>,
}

/// Summarises the classified NSV of the speeds.
pub(super) fn summarise(
    nsv: &[Option<Nsv>],
    diverged_speeds_hz: Vec<f64>,
    threshold_m: f64,
) -> NsvSummary {
    let steady = || {
        nsv.iter()
            .flatten()
            .filter(|n| n.class != NsvClass::Transient)
    };
    let above = |n: &&Nsv| n.peak.amplitude_m >= threshold_m;
    let onset_speed_hz = steady()
        .filter(above)
        .map(|n| n.speed_hz)
        .min_by(f64::total_cmp);
    let largest = steady()
        .max_by(|a, b| a.peak.amplitude_m.total_cmp(&b.peak.amplitude_m))
        .map(|n| LargestNsv {
            speed_hz: n.speed_hz,
            frequency_hz: n.peak.frequency_hz,
            amplitude_m: n.peak.amplitude_m,
            order: n.peak.order,
            class: n.class,
            direction: n.direction,
        });
    let classes: Vec<ClassCount> = NsvClass::ALL
        .iter()
        .map(|&class| {
            let members = || {
                nsv.iter()
                    .flatten()
                    .filter(|n| n.class == class)
                    .filter(above)
            };
            ClassCount {
                class,
                speeds: members().count(),
                largest_m: members().map(|n| n.peak.amplitude_m).fold(0.0, f64::max),
                total_m: members().map(|n| n.peak.amplitude_m).sum(),
            }
        })
        .filter(|c| c.speeds > 0)
        .collect();
    let dominant_class = classes
        .iter()
        .filter(|c| c.class != NsvClass::Transient)
        .max_by(|a, b| a.total_m.total_cmp(&b.total_m))
        .map(|c| c.class);
    NsvSummary {
        threshold_m,
        onset_speed_hz,
        largest,
        dominant_class,
        speeds_above_threshold: steady().filter(above).count(),
        classes,
        diverged_speeds_hz,
    }
}
