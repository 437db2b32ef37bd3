//! What an unbalance response reports ([`crate::report`]): each node's response over speed
//! and its resonance peaks with the API 617 margins, as `whirl unbalance` writes them.

use serde::Serialize;

use super::UnbalanceResult;
use crate::report::{Report, Table};
use crate::response::ResponsePeak;

/// The key numbers of an [`UnbalanceResult`].
#[derive(Debug, Clone, Serialize)]
pub struct UnbalanceSummary {
    /// First and last speed, Hz.
    pub speed_range_hz: [Option<f64>; 2],
    /// Speeds.
    pub speed_count: usize,
    /// The operating range, Hz.
    pub operating_speed_hz: Option<(f64, f64)>,
    /// The verdict on the API 617 margins ([`UnbalanceResult::api617_status`]).
    pub api617_status: String,
    /// Each reported node.
    pub nodes: Vec<NodeSummary>,
}

/// One reported node.
#[derive(Debug, Clone, Serialize)]
pub struct NodeSummary {
    /// Node.
    pub node: usize,
    /// Axial position, m.
    pub z_m: f64,
    /// Largest major semi-axis of the orbit, m.
    pub max_major_semi_axis_m: f64,
    /// The speed where it is, Hz.
    pub max_major_semi_axis_speed_hz: Option<f64>,
    /// Resonance peaks.
    pub peaks: Vec<PeakSummary>,
    /// Local maxima within the curve's round-off, which are no peaks, Hz (fine meshes).
    pub maxima_within_round_off_hz: Vec<f64>,
}

/// One resonance peak.
#[derive(Debug, Clone, Serialize)]
pub struct PeakSummary {
    /// Speed, Hz.
    pub speed_hz: f64,
    /// Speed, rpm.
    pub speed_rpm: f64,
    /// Major semi-axis, m.
    pub major_semi_axis_m: f64,
    /// Half-power band, Hz.
    pub half_power_hz: Option<(f64, f64)>,
    /// Amplification factor.
    pub amplification_factor: Option<f64>,
    /// API 617 required separation margin, %.
    pub api617_required_margin_pct: Option<f64>,
    /// Actual separation margin, %.
    pub api617_actual_margin_pct: Option<f64>,
    /// Whether the margin is met.
    pub meets_api617: Option<bool>,
}

impl From<&ResponsePeak> for PeakSummary {
    fn from(p: &ResponsePeak) -> Self {
        PeakSummary {
            speed_hz: p.speed_hz,
            speed_rpm: 60.0 * p.speed_hz,
            major_semi_axis_m: p.amplitude,
            half_power_hz: p.half_power_hz,
            amplification_factor: p.amplification_factor,
            api617_required_margin_pct: p.required_margin_pct,
            api617_actual_margin_pct: p.actual_margin_pct,
            meets_api617: p.meets_api617,
        }
    }
}

/// The index and value of the largest entry (the first of equals; NaN when all are NaN).
fn largest(values: &[f64]) -> (usize, f64) {
    values
        .iter()
        .copied()
        .enumerate()
        .fold((0, f64::NAN), |a, (i, v)| {
            if v > a.1 || a.1.is_nan() {
                (i, v)
            } else {
                a
            }
        })
}

impl UnbalanceResult {
    /// The verdict on the API 617 margins: "assessed" (see each peak's `meets_api617`),
    /// the reason they are not applicable, or "no operating range".
    pub fn api617_status(&self) -> String {
        match (&self.api617_note, self.operating_hz) {
            (Some(note), _) => note.clone(),
            (None, Some(_)) => "assessed".to_string(),
            (None, None) => "no operating range: give [operating] min_speed and max_speed to \
                             assess separation margins"
                .to_string(),
        }
    }
}

impl Report for UnbalanceResult {
    type Summary = UnbalanceSummary;

    fn summary(&self) -> UnbalanceSummary {
        let speeds_hz = &self.speeds_hz;
        UnbalanceSummary {
            speed_range_hz: [speeds_hz.first().copied(), speeds_hz.last().copied()],
            speed_count: speeds_hz.len(),
            operating_speed_hz: self.operating_hz,
            api617_status: self.api617_status(),
            nodes: self
                .nodes
                .iter()
                .map(|r| {
                    let (k, max) = largest(&r.major);
                    NodeSummary {
                        node: r.node,
                        z_m: r.z,
                        max_major_semi_axis_m: max,
                        max_major_semi_axis_speed_hz: speeds_hz.get(k).copied(),
                        peaks: r.peaks.iter().map(PeakSummary::from).collect(),
                        maxima_within_round_off_hz: r.maxima_within_round_off_hz.clone(),
                    }
                })
                .collect(),
        }
    }

    /// `unbalance` (one row per speed; per node the amplitude and phase of ux and uy, the
    /// orbit's semi-axes and its whirl) and `peaks` (each resonance peak of the major
    /// semi-axis with its half-power band, amplification factor and API 617 margins).
    fn tables(&self) -> Vec<Table> {
        let speeds = &self.speeds_hz;
        let mut response = Table::new("unbalance");
        response
            .numbers("speed_hz", speeds.iter().copied())
            .numbers("speed_rpm", speeds.iter().map(|f| 60.0 * f));
        for r in &self.nodes {
            let n = r.node;
            response
                .numbers(
                    format!("n{n}_ux_amplitude_m"),
                    r.ux_amplitude.iter().copied(),
                )
                .numbers(format!("n{n}_ux_phase_deg"), r.ux_phase_deg.iter().copied())
                .numbers(
                    format!("n{n}_uy_amplitude_m"),
                    r.uy_amplitude.iter().copied(),
                )
                .numbers(format!("n{n}_uy_phase_deg"), r.uy_phase_deg.iter().copied())
                .numbers(format!("n{n}_major_semi_axis_m"), r.major.iter().copied())
                .numbers(format!("n{n}_minor_semi_axis_m"), r.minor.iter().copied())
                .text(format!("n{n}_whirl"), r.whirl.iter().map(|w| w.name()));
        }
        let rows: Vec<_> = self
            .nodes
            .iter()
            .flat_map(|r| r.peaks.iter().map(move |p| (r, p)))
            .collect();
        let mut peaks = Table::new("peaks");
        peaks
            .counts("node", rows.iter().map(|(r, _)| r.node))
            .numbers("z_m", rows.iter().map(|(r, _)| r.z))
            .numbers("speed_hz", rows.iter().map(|(_, p)| p.speed_hz))
            .numbers("speed_rpm", rows.iter().map(|(_, p)| 60.0 * p.speed_hz))
            .numbers("major_semi_axis_m", rows.iter().map(|(_, p)| p.amplitude))
            .optional(
                "half_power_low_hz",
                rows.iter().map(|(_, p)| p.half_power_hz.map(|b| b.0)),
            )
            .optional(
                "half_power_high_hz",
                rows.iter().map(|(_, p)| p.half_power_hz.map(|b| b.1)),
            )
            .optional(
                "amplification_factor",
                rows.iter().map(|(_, p)| p.amplification_factor),
            )
            .optional(
                "api617_required_margin_pct",
                rows.iter().map(|(_, p)| p.required_margin_pct),
            )
            .optional(
                "api617_actual_margin_pct",
                rows.iter().map(|(_, p)| p.actual_margin_pct),
            )
            .text(
                "meets_api617",
                rows.iter()
                    .map(|(_, p)| match (p.meets_api617, &self.api617_note) {
                        (Some(m), _) => m.to_string(),
                        (None, Some(_)) => "not applicable".to_string(),
                        (None, None) => String::new(),
                    }),
            );
        vec![response, peaks]
    }
}
