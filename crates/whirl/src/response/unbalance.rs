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

use faer::c64;
use rayon::prelude::*;
use serde::Serialize;

use super::frf::harmonic_response;
use super::peaks::{find_peaks, margins_not_applicable, ResponsePeak};
use crate::error::{Error, Result};
use crate::fe::{dof, unbalance_force, Direction, SystemMatrices};
use crate::modal::Whirl;
use crate::model::Model;

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
pub fn unbalance_phasor(system: &SystemMatrices, force: &[c64], omega: f64) -> Result<Vec<c64>> {
    let scaled: Vec<c64> = force.iter().map(|f| f * (omega * omega)).collect();
    harmonic_response(system, omega, omega, &scaled)
}

/// Unbalance response at `nodes` over `speeds` (rad/s).
///
/// # Errors
/// [`Error::InvalidOption`] for a node that is not on the shaft, [`Error::Unsupported`] for
/// a model without unbalance, [`Error::Singular`] as in `unbalance_phasor`.
pub fn unbalance_response(
    model: &Model,
    system: &SystemMatrices,
    speeds: &[f64],
    nodes: &[usize],
) -> Result<UnbalanceResult> {
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
    let force = unbalance_force(model, system.dofs());
    let phasors: Vec<Vec<c64>> = speeds
        .par_iter()
        .map(|&w| unbalance_phasor(system, &force, w))
        .collect::<Result<_>>()?;
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
        .map(|&node| node_response(node, z[node], &phasors, &speeds_hz, operating_hz))
        .collect();
    Ok(UnbalanceResult {
        speeds_hz,
        nodes,
        operating_hz,
        api617_note: operating_hz.and_then(margins_not_applicable),
    })
}

fn node_response(
    node: usize,
    z: f64,
    phasors: &[Vec<c64>],
    speeds_hz: &[f64],
    operating_hz: Option<(f64, f64)>,
) -> NodeResponse {
    let i = c64::new(0.0, 1.0);
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
        let (a, b) = (q[dof(node, Direction::Ux)], q[dof(node, Direction::Uy)]);
        let forward = (a + i * b).norm() / 2.0;
        let backward = (a - i * b).norm() / 2.0;
        r.ux_amplitude.push(a.norm());
        r.ux_phase_deg.push(a.arg().to_degrees());
        r.uy_amplitude.push(b.norm());
        r.uy_phase_deg.push(b.arg().to_degrees());
        r.major.push(forward + backward);
        r.minor.push((forward - backward).abs());
        r.whirl.push(if forward >= backward {
            Whirl::Forward
        } else {
            Whirl::Backward
        });
    }
    r.peaks = find_peaks(speeds_hz, &r.major, operating_hz);
    r
}
