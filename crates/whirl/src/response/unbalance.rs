//! Steady-state unbalance response of the linear model.
//!
//! At spin speed Omega the unbalance force is Re(Omega^2 f e^{i Omega t}) with f from
//! [`crate::fe::unbalance_force`], and the steady response Re(Q e^{i Omega t}) solves
//!
//! ```text
//! (K - Omega^2 M + i Omega (C + Omega G)) Q = Omega^2 f
//! ```
//!
//! one complex LU solve per speed (speeds in parallel). At each node the orbit is the
//! ellipse traced by (Re(Q_x e^{i w t}), Re(Q_y e^{i w t})): its forward and backward
//! circular parts have radii |Q_x + i Q_y|/2 and |Q_x - i Q_y|/2, its semi-axes are their
//! sum and difference, and it whirls forward when the forward part is larger.
//!
//! A lightly damped peak is narrower than an even speed grid resolves: the half-power
//! band of a mode with damping ratio zeta is about 2 zeta Nc wide (1.8 Hz at 50 Hz for
//! zeta = 1.8 %), narrower than the 1.1 Hz step of 800 speeds up to 900 Hz allows to
//! sample. [`unbalance_response_refined`] therefore adds speeds around each peak of the
//! major semi-axis, halving the steps there until the half-power band holds
//! [`BAND_SAMPLES`] steps, so the peak, its amplification factor and the polar loop
//! come out of the samples rather than out of the interpolation between them.

mod report;

pub use report::UnbalanceSummary;

use faer::c64;
use serde::Serialize;

use super::frf::harmonic_response;
use super::peaks::{find_peaks, is_peak, margins_not_applicable, samples_below, ResponsePeak};
use crate::error::{Error, Result};
use crate::fe::{dof, unbalance_force, Direction, Matrices};
use crate::modal::Whirl;
use crate::model::Model;
use crate::progress::{map_told, Progress};

/// The response at one node over the speeds.
#[derive(Debug, Clone, Serialize)]
pub struct NodeResponse {
    /// Node index.
    pub node: usize,
    /// Axial position, m.
    pub z: f64,
    /// Amplitude of ux, m (zero-to-peak).
    pub ux_amplitude: Vec<f64>,
    /// Phase of ux, degrees (response lags the unbalance when negative).
    pub ux_phase_deg: Vec<f64>,
    /// Amplitude of uy, m.
    pub uy_amplitude: Vec<f64>,
    /// Phase of uy, degrees.
    pub uy_phase_deg: Vec<f64>,
    /// Orbit major semi-axis, m.
    pub major: Vec<f64>,
    /// Orbit minor semi-axis, m.
    pub minor: Vec<f64>,
    /// Whirl direction of the orbit.
    pub whirl: Vec<Whirl>,
    /// Peaks of the major semi-axis over speed.
    pub peaks: Vec<ResponsePeak>,
}

/// Unbalance response at several nodes.
#[derive(Debug, Clone, Serialize)]
pub struct UnbalanceResult {
    /// Spin speeds, Hz.
    pub speeds_hz: Vec<f64>,
    /// One entry per requested node.
    pub nodes: Vec<NodeResponse>,
    /// Operating speed range, Hz, when the model gives one.
    pub operating_hz: Option<(f64, f64)>,
    /// Why the API 617 margins were not assessed, when the operating range makes them
    /// meaningless (see [`margins_not_applicable`]).
    pub api617_note: Option<String>,
}

/// Complex response vector at one speed: the harmonic response to Omega^2 f at w = Omega.
///
/// # Errors
/// [`Error::Singular`] when the dynamic stiffness is singular at `omega` (see
/// [`harmonic_response`]).
pub fn unbalance_phasor(system: &impl Matrices, force: &[c64], omega: f64) -> Result<Vec<c64>> {
    let scaled: Vec<c64> = force.iter().map(|f| f * (omega * omega)).collect();
    harmonic_response(system, omega, omega, &scaled)
}

/// Steps a peak's half-power band is refined to: the parabola through the top three
/// samples then misses the peak of a resonance by about (1/40)^2 of the band's curvature
/// scale, well under 0.1 %, and the half-power crossings are interpolated over 1/40 of
/// the band.
pub const BAND_SAMPLES: f64 = 40.0;

/// Most refinement passes; each halves the steps inside the bands, so a band 2^16 times
/// narrower than the requested step is still resolved.
const REFINE_PASSES: usize = 16;

/// Unbalance response at `nodes` over exactly `speeds` (rad/s).
///
/// # Errors
/// [`Error::InvalidOption`] for a node that is not on the shaft, [`Error::Unsupported`] for
/// a model without unbalance, [`Error::Singular`] as in `unbalance_phasor`.
pub fn unbalance_response(
    model: &Model,
    system: &impl Matrices,
    speeds: &[f64],
    nodes: &[usize],
) -> Result<UnbalanceResult> {
    let force = checked_force(model, system, nodes)?;
    let phasors = phasors_at(system, &force, speeds, nodes, None, 0, speeds.len())?;
    Ok(result_from(model, speeds, &phasors, nodes))
}

/// Unbalance response at `nodes` over `speeds` (rad/s) and, added to them, speeds around
/// every peak of a node's major semi-axis (where it exceeds a quarter of the peak) until
/// the peak's half-power band holds [`BAND_SAMPLES`] steps. The result's speeds are sorted ascending without duplicates.
/// `progress` is told after every speed; its total grows with each pass of refinement.
///
/// # Errors
/// As [`unbalance_response`]; [`Error::Interrupted`] when `progress` stopped it.
pub fn unbalance_response_refined(
    model: &Model,
    system: &impl Matrices,
    speeds: &[f64],
    nodes: &[usize],
    progress: Option<&Progress>,
) -> Result<UnbalanceResult> {
    let force = checked_force(model, system, nodes)?;
    let mut speeds = speeds.to_vec();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let count = speeds.len();
    let mut phasors = phasors_at(system, &force, &speeds, nodes, progress, 0, count)?;
    for _ in 0..REFINE_PASSES {
        let added = refinement_speeds(&speeds, &phasors, nodes);
        if added.is_empty() {
            break;
        }
        let (before, total) = (speeds.len(), speeds.len() + added.len());
        let new_phasors = phasors_at(system, &force, &added, nodes, progress, before, total)?;
        (speeds, phasors) = merge_sorted(speeds, phasors, added, new_phasors);
    }
    Ok(result_from(model, &speeds, &phasors, nodes))
}

/// Fraction of a peak's height above which its steps are refined: the loop of the polar
/// plot spans most of its sweep there (a single mode's amplitude falls to a quarter at
/// about 2 half-power widths from the peak).
const REFINE_LEVEL: f64 = 0.25;

/// Midpoints of the steps wider than 1/[`BAND_SAMPLES`] of a peak's half-power band where
/// the curve is above [`REFINE_LEVEL`] of the peak, over every peak of every node's major
/// semi-axis, sorted and unique. A band whose edge lies outside the sweep is measured to
/// the sweep's end, so a broad rise is left alone.
fn refinement_speeds(speeds: &[f64], phasors: &[Vec<c64>], nodes: &[usize]) -> Vec<f64> {
    let mut added = Vec::new();
    for slot in 0..nodes.len() {
        let major: Vec<f64> = phasors.iter().map(|q| orbit(q, slot).major()).collect();
        for k in 1..major.len().saturating_sub(1) {
            if !is_peak(&major, k) {
                continue;
            }
            let (low, high) = band(&major, k, major[k] / std::f64::consts::SQRT_2);
            let step = (speeds[high] - speeds[low]) / BAND_SAMPLES;
            let (low, high) = band(&major, k, REFINE_LEVEL * major[k]);
            added.extend(
                (low..high)
                    .filter(|&j| speeds[j + 1] - speeds[j] > step)
                    .map(|j| 0.5 * (speeds[j] + speeds[j + 1])),
            );
        }
    }
    added.sort_by(f64::total_cmp);
    added.dedup();
    added
}

/// The nearest samples on either side of the peak at `k` below `level` (the ends of the
/// curve when it stays above).
fn band(y: &[f64], k: usize, level: f64) -> (usize, usize) {
    let (below, above) = samples_below(y, k, level);
    (below.unwrap_or(0), above.unwrap_or(y.len() - 1))
}

/// Two ascending speed lists and their phasors merged into one ascending list.
fn merge_sorted(
    speeds: Vec<f64>,
    phasors: Vec<Vec<c64>>,
    added: Vec<f64>,
    added_phasors: Vec<Vec<c64>>,
) -> (Vec<f64>, Vec<Vec<c64>>) {
    let mut pairs: Vec<(f64, Vec<c64>)> = speeds
        .into_iter()
        .zip(phasors)
        .chain(added.into_iter().zip(added_phasors))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs.dedup_by(|a, b| a.0 == b.0);
    pairs.into_iter().unzip()
}

/// The unbalance force vector, after checking `nodes` and that the model has unbalance.
fn checked_force(model: &Model, system: &impl Matrices, nodes: &[usize]) -> Result<Vec<c64>> {
    let count = model.node_count();
    if let Some(&bad) = nodes.iter().find(|&&n| n >= count) {
        return Err(Error::InvalidOption(format!(
            "node {bad} is not on the shaft (nodes 0 to {})",
            count - 1
        )));
    }
    if model.unbalances.is_empty() {
        return Err(Error::Unsupported(
            "the model has no [[unbalance]]: add one to compute an unbalance response".into(),
        ));
    }
    Ok(unbalance_force(model, system.dofs()))
}

/// The response phasors at `speeds` (rad/s), in parallel: of each speed, u_x and u_y of
/// `nodes` in their order (what the result reports; every DOF of every speed would take
/// 1.3 GB for a 10,000-element rotor over the default speeds and refinement). `progress`
/// counts them on from `before` speeds done of `total`.
fn phasors_at(
    system: &impl Matrices,
    force: &[c64],
    speeds: &[f64],
    nodes: &[usize],
    progress: Option<&Progress>,
    before: usize,
    total: usize,
) -> Result<Vec<Vec<c64>>> {
    map_told(
        speeds,
        progress,
        (before, total),
        ("the unbalance response", "speeds"),
        |&w| {
            let q = unbalance_phasor(system, force, w)?;
            Ok(nodes
                .iter()
                .flat_map(|&n| [q[dof(n, Direction::Ux)], q[dof(n, Direction::Uy)]])
                .collect())
        },
    )
}

/// The result at `nodes` from the phasors at `speeds` (rad/s).
fn result_from(
    model: &Model,
    speeds: &[f64],
    phasors: &[Vec<c64>],
    nodes: &[usize],
) -> UnbalanceResult {
    let speeds_hz: Vec<f64> = speeds
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    let operating_hz = model.operating.map(|(a, b)| {
        (
            a / (2.0 * std::f64::consts::PI),
            b / (2.0 * std::f64::consts::PI),
        )
    });
    let z = model.node_positions();
    let nodes = nodes
        .iter()
        .enumerate()
        .map(|(slot, &node)| node_response(node, slot, z[node], phasors, &speeds_hz, operating_hz))
        .collect();
    UnbalanceResult {
        speeds_hz,
        nodes,
        operating_hz,
        api617_note: operating_hz.and_then(margins_not_applicable),
    }
}

/// The displacement phasors of one node and the radii of their circular parts.
struct NodeOrbit {
    ux: c64,
    uy: c64,
    forward: f64,
    backward: f64,
}

impl NodeOrbit {
    fn major(&self) -> f64 {
        self.forward + self.backward
    }
}

/// The orbit of the node in `slot` of the reported nodes, from its phasors `q` (see
/// `phasors_at`).
fn orbit(q: &[c64], slot: usize) -> NodeOrbit {
    let i = c64::new(0.0, 1.0);
    let (ux, uy) = (q[2 * slot], q[2 * slot + 1]);
    NodeOrbit {
        ux,
        uy,
        forward: (ux + i * uy).norm() / 2.0,
        backward: (ux - i * uy).norm() / 2.0,
    }
}

fn node_response(
    node: usize,
    slot: usize,
    z: f64,
    phasors: &[Vec<c64>],
    speeds_hz: &[f64],
    operating_hz: Option<(f64, f64)>,
) -> NodeResponse {
    let mut r = NodeResponse {
        node,
        z,
        ux_amplitude: Vec::new(),
        ux_phase_deg: Vec::new(),
        uy_amplitude: Vec::new(),
        uy_phase_deg: Vec::new(),
        major: Vec::new(),
        minor: Vec::new(),
        whirl: Vec::new(),
        peaks: Vec::new(),
    };
    for q in phasors {
        let o = orbit(q, slot);
        r.ux_amplitude.push(o.ux.norm());
        r.ux_phase_deg.push(o.ux.arg().to_degrees());
        r.uy_amplitude.push(o.uy.norm());
        r.uy_phase_deg.push(o.uy.arg().to_degrees());
        r.major.push(o.major());
        r.minor.push((o.forward - o.backward).abs());
        r.whirl.push(if o.forward >= o.backward {
            Whirl::Forward
        } else {
            Whirl::Backward
        });
    }
    r.peaks = find_peaks(speeds_hz, &r.major, operating_hz);
    r
}
