//! What a critical-speed map reports ([`crate::report`]), as `whirl ucs` writes it.

use serde::Serialize;

use super::CriticalSpeedMap;
use crate::report::{Report, Table};

/// The key numbers of a [`CriticalSpeedMap`].
#[derive(Debug, Clone, Serialize)]
pub struct CriticalSpeedSummary {
    /// Whether the gyroscopic moments of synchronous spin were included.
    pub synchronous: bool,
    /// First and last stiffness, N/m.
    pub stiffness_range_n_per_m: [f64; 2],
    /// Stiffnesses swept.
    pub stiffness_count: usize,
    /// Critical speeds (curves).
    pub modes: usize,
    /// Each bearing's own stiffness and the critical speeds where it cuts the curves.
    pub bearings: Vec<BearingCut>,
}

/// A bearing's stiffness on the map.
#[derive(Debug, Clone, Serialize)]
pub struct BearingCut {
    /// The bearing.
    pub bearing: String,
    /// Its stiffness, N/m.
    pub stiffness_n_per_m: f64,
    /// The critical speeds at that stiffness, Hz (none where a curve has none).
    pub critical_speeds_hz: Vec<Option<f64>>,
}

impl Report for CriticalSpeedMap {
    type Summary = CriticalSpeedSummary;

    fn summary(&self) -> CriticalSpeedSummary {
        let k = &self.stiffness;
        CriticalSpeedSummary {
            synchronous: self.synchronous,
            stiffness_range_n_per_m: [
                k.first().copied().unwrap_or(f64::NAN),
                k.last().copied().unwrap_or(f64::NAN),
            ],
            stiffness_count: k.len(),
            modes: self.critical_speeds_hz.len(),
            bearings: self
                .bearings
                .iter()
                .map(|b| BearingCut {
                    bearing: b.label.clone(),
                    stiffness_n_per_m: b.stiffness,
                    critical_speeds_hz: b.critical_speeds_hz.clone(),
                })
                .collect(),
        }
    }

    /// `ucs` (the critical speeds at each stiffness) and `bearings` (each bearing's
    /// stiffness and the critical speeds where it cuts the curves).
    fn tables(&self) -> Vec<Table> {
        let mut map = Table::new("ucs");
        map.numbers("stiffness_n_per_m", self.stiffness.iter().copied());
        for (m, curve) in self.critical_speeds_hz.iter().enumerate() {
            map.numbers(format!("mode{}_hz", m + 1), curve.iter().copied());
        }
        let b = &self.bearings;
        let mut bearings = Table::new("bearings");
        bearings
            .text("bearing", b.iter().map(|b| b.label.as_str()))
            .numbers("stiffness_n_per_m", b.iter().map(|b| b.stiffness));
        for m in 0..self.critical_speeds_hz.len() {
            bearings.optional(
                format!("mode{}_hz", m + 1),
                b.iter()
                    .map(|b| b.critical_speeds_hz.get(m).copied().flatten()),
            );
        }
        vec![map, bearings]
    }
}
