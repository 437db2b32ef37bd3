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
//! [`BAND_SAMPLES`](super::BAND_SAMPLES) steps, so the peak, its amplification factor and the polar loop
//! come out of the samples rather than out of the interpolation between them.
//!
//! On a fine mesh round-off makes the curves ripple: K's entries grow as the cube of the
//! elements (5e17 N/m for 10,000 elements of the reference rotor, against 1e6 N/m for its
//! lowest modes), so every solve carries an error that changes from one speed to the next.
//! At every local maximum of a curve (and the sample its prominence is measured from) the
//! solve is therefore repeated with an estimate of its round-off, and a maximum that does
//! not stand above it is neither refined nor reported as a peak
//! ([`super::peaks::stands_above_round_off`]); the estimate costs about two solves, so it
//! is made where it is needed, not at every speed.

mod report;

pub use report::UnbalanceSummary;

use faer::c64;
use serde::Serialize;

use super::frf::{harmonic_response, harmonic_response_and_round_off};
use super::peaks::{
    find_peaks, margins_not_applicable, maxima_with_bases, merge_sorted, refinement_points,
    samples_to_check, split_maxima, Maxima, ResponsePeak, REFINE_PASSES,
};
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
    /// Speeds, Hz, of the major semi-axis' local maxima that do not stand above the curve's
    /// round-off and are therefore no peaks (fine meshes: see the module's documentation).
    /// Where one lies at a resonance, that resonance's top is lost in round-off.
    pub maxima_within_round_off_hz: Vec<f64>,
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

/// The unbalance force at `omega`: Omega^2 f.
fn scaled_force(force: &[c64], omega: f64) -> Vec<c64> {
    force.iter().map(|f| f * (omega * omega)).collect()
}

/// Speeds of an unbalance response when none are given: a step of about 1 Hz up to 900 Hz,
/// which meets every peak of a few per cent of damping (half-power bands 2 zeta Nc wide)
/// before [`unbalance_response_refined`] adds speeds in its band.
pub const DEFAULT_UNBALANCE_SPEEDS: usize = 800;

/// Lowest speed of the default unbalance speeds, Hz: a sweep starts just above rest.
pub const DEFAULT_UNBALANCE_FROM_HZ: f64 = 1.0;

/// The speeds of an unbalance response when none are given, rad/s:
/// [`DEFAULT_UNBALANCE_SPEEDS`] from [`DEFAULT_UNBALANCE_FROM_HZ`] to the model's default
/// top ([`Model::default_speeds`]).
pub fn default_unbalance_speeds(model: &Model) -> Vec<f64> {
    let from = 2.0 * std::f64::consts::PI * DEFAULT_UNBALANCE_FROM_HZ;
    model.default_speeds(from, DEFAULT_UNBALANCE_SPEEDS)
}

/// Unbalance response at `nodes` over exactly `speeds` (rad/s).
///
/// # Errors
/// [`Error::InvalidOption`] for a node that is not on the shaft or more than
/// [`MAX_RANGE_COUNT`](crate::units::MAX_RANGE_COUNT) speeds, [`Error::Unsupported`] for
/// a model without unbalance, [`Error::Singular`] as in `unbalance_phasor`.
pub fn unbalance_response(
    model: &Model,
    system: &impl Matrices,
    speeds: &[f64],
    nodes: &[usize],
) -> Result<UnbalanceResult> {
    crate::units::check_count(speeds.len(), "unbalance speeds")?;
    let force = checked_force(model, system, nodes)?;
    let mut samples = samples_at(system, &force, speeds, nodes, None, 0, speeds.len())?;
    let maxima = resolved_maxima(system, &force, speeds, &mut samples, nodes, None)?;
    Ok(result_from(model, speeds, &samples, nodes, &maxima))
}

/// Unbalance response at `nodes` over `speeds` (rad/s) and, added to them, speeds around
/// every peak of a node's major semi-axis (where it exceeds a quarter of the peak) until
/// the peak's half-power band holds [`BAND_SAMPLES`](super::BAND_SAMPLES) steps, over at most
/// `REFINE_PASSES` (16) passes; a local maximum within the curve's round-off is no peak. The
/// result's speeds are sorted ascending without duplicates.
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
    crate::units::check_count(speeds.len(), "unbalance speeds")?;
    let force = checked_force(model, system, nodes)?;
    let mut speeds = speeds.to_vec();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup();
    let count = speeds.len();
    let mut samples = samples_at(system, &force, &speeds, nodes, progress, 0, count)?;
    let mut passes = 0;
    loop {
        let maxima = resolved_maxima(system, &force, &speeds, &mut samples, nodes, progress)?;
        let added = if passes < REFINE_PASSES {
            let majors: Vec<Vec<f64>> = (0..nodes.len())
                .map(|slot| major_of(&samples, slot))
                .collect();
            refinement_points(&speeds, &majors, &maxima)
        } else {
            Vec::new()
        };
        if added.is_empty() {
            return Ok(result_from(model, &speeds, &samples, nodes, &maxima));
        }
        passes += 1;
        let (before, total) = (speeds.len(), speeds.len() + added.len());
        let new_samples = samples_at(system, &force, &added, nodes, progress, before, total)?;
        (speeds, samples) = merge_sorted(speeds, samples, added, new_samples);
    }
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

/// The response at one speed where the result looks: what `nodes` did, not every DOF
/// (every DOF of every speed would take 1.3 GB for a 10,000-element rotor over the default
/// speeds and refinement).
struct SpeedSample {
    /// u_x and u_y of each node, in the order of `nodes`.
    phasors: Vec<c64>,
    /// Per node, the size of the round-off in its orbit's semi-axes, once estimated (see
    /// [`resolved_maxima`]): |du_x| + |du_y| bounds the change of |u_x +- i u_y| / 2 summed
    /// or subtracted.
    round_off: Option<Vec<f64>>,
}

impl SpeedSample {
    /// The orbit of the node in `slot` of the reported nodes.
    fn orbit(&self, slot: usize) -> NodeOrbit {
        orbit(&self.phasors, slot)
    }
}

/// The major semi-axis of the node in `slot` over the samples.
fn major_of(samples: &[SpeedSample], slot: usize) -> Vec<f64> {
    samples.iter().map(|s| s.orbit(slot).major()).collect()
}

/// u_x and u_y of `nodes` from a response vector `q`, in order.
fn at_nodes<T: Copy>(q: &[T], nodes: &[usize]) -> Vec<T> {
    nodes
        .iter()
        .flat_map(|&n| [q[dof(n, Direction::Ux)], q[dof(n, Direction::Uy)]])
        .collect()
}

/// Per node, the local maxima of its major semi-axis, split by whether they stand above the
/// curve's round-off ([`stands_above_round_off`]). The round-off is estimated at each
/// maximum and at the sample its prominence is measured from, where it is not yet known,
/// by solving there again ([`harmonic_response_and_round_off`], in parallel; `progress` is
/// told of these checks).
///
/// # Errors
/// As `samples_at`.
fn resolved_maxima(
    system: &impl Matrices,
    force: &[c64],
    speeds: &[f64],
    samples: &mut [SpeedSample],
    nodes: &[usize],
    progress: Option<&Progress>,
) -> Result<Vec<Maxima>> {
    let candidates: Vec<Vec<(usize, Option<usize>)>> = (0..nodes.len())
        .map(|slot| maxima_with_bases(&major_of(samples, slot)))
        .collect();
    let unknown: Vec<usize> = samples_to_check(&candidates)
        .into_iter()
        .filter(|&j| samples[j].round_off.is_none())
        .collect();
    let estimates = map_told(
        &unknown,
        progress,
        (0, unknown.len()),
        (
            "the round-off check of the peaks",
            "samples checked for round-off",
        ),
        |&j| {
            let w = speeds[j];
            let (_, round_off) =
                harmonic_response_and_round_off(system, w, w, &scaled_force(force, w))?;
            let parts = at_nodes(&round_off, nodes);
            Ok(parts.chunks_exact(2).map(|d| d[0] + d[1]).collect())
        },
    )?;
    for (j, estimate) in unknown.into_iter().zip(estimates) {
        samples[j].round_off = Some(estimate);
    }
    Ok(candidates
        .iter()
        .enumerate()
        .map(|(slot, candidates)| {
            // Every sample asked for was estimated above; a missing one would count as
            // exact, which keeps the maximum (the behaviour without the check).
            split_maxima(&major_of(samples, slot), candidates, |j| {
                samples[j].round_off.as_ref().map_or(0.0, |r| r[slot])
            })
        })
        .collect())
}

/// The response at `speeds` (rad/s), in parallel. `progress` counts them on from `before`
/// speeds done of `total`.
fn samples_at(
    system: &impl Matrices,
    force: &[c64],
    speeds: &[f64],
    nodes: &[usize],
    progress: Option<&Progress>,
    before: usize,
    total: usize,
) -> Result<Vec<SpeedSample>> {
    map_told(
        speeds,
        progress,
        (before, total),
        ("the unbalance response", "speeds"),
        |&w| {
            let q = harmonic_response(system, w, w, &scaled_force(force, w))?;
            Ok(SpeedSample {
                phasors: at_nodes(&q, nodes),
                round_off: None,
            })
        },
    )
}

/// The result at `nodes` from the samples at `speeds` (rad/s), each node's peaks at its
/// `maxima`.
fn result_from(
    model: &Model,
    speeds: &[f64],
    samples: &[SpeedSample],
    nodes: &[usize],
    maxima: &[Maxima],
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
        .map(|(slot, &node)| {
            let mut r = node_response(node, slot, z[node], samples);
            r.peaks = find_peaks(&speeds_hz, &r.major, operating_hz, |k| {
                maxima[slot].resolved.binary_search(&k).is_ok()
            });
            r.maxima_within_round_off_hz = maxima[slot]
                .within_round_off
                .iter()
                .map(|&k| speeds_hz[k])
                .collect();
            r
        })
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

/// The orbit of the node in `slot` of the reported nodes, from a speed's phasors `q` (see
/// [`SpeedSample`]).
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

/// The response of the node in `slot` over the samples; its peaks are found by the caller.
fn node_response(node: usize, slot: usize, z: f64, samples: &[SpeedSample]) -> NodeResponse {
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
        maxima_within_round_off_hz: Vec::new(),
    };
    for sample in samples {
        let o = sample.orbit(slot);
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
    r
}
