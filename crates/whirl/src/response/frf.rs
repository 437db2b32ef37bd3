//! Frequency response functions and the forced response to harmonic forces.
//!
//! At spin speed Omega, a force Re(F e^{i w t}) of any frequency w drives the steady
//! response Re(Q e^{i w t}) with
//!
//! ```text
//! (K - w^2 M + i w (C + Omega G)) Q = F
//! ```
//!
//! (the gyroscopic moments follow the spin, the inertia and damping the excitation). The
//! receptance H_oi(w) is Q at DOF o for a unit force at DOF i; the mobility is i w H (velocity
//! per force) and the accelerance -w^2 H (acceleration per force). Unbalance is the special
//! case w = Omega with F = Omega^2 f rotating (see [`super::unbalance`]). One complex LU per
//! frequency, frequencies in parallel.

mod report;

pub use report::{FrfReport, FrfSummary};

use faer::{c64, Mat};
use rayon::prelude::*;
use serde::Serialize;

use super::peaks::{find_peaks, ResponsePeak};
use crate::error::{Error, Result};
use crate::fe::{assemble, dof_name, Bearings, SystemMatrices};
use crate::modal::undamped_modes;
use crate::model::Model;

/// Which ratio of response to force.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrfKind {
    /// Displacement per force, m/N (rad/N, m/(N m) for rotations).
    Receptance,
    /// Velocity per force, i w H, m/(N s).
    Mobility,
    /// Acceleration per force, -w^2 H, m/(N s^2).
    Accelerance,
}

impl FrfKind {
    /// All three, in order.
    pub const ALL: [FrfKind; 3] = [FrfKind::Receptance, FrfKind::Mobility, FrfKind::Accelerance];

    /// Name used in files.
    pub fn name(self) -> &'static str {
        match self {
            FrfKind::Receptance => "receptance",
            FrfKind::Mobility => "mobility",
            FrfKind::Accelerance => "accelerance",
        }
    }

    /// The unit of a translation's FRF of this kind.
    pub fn unit(self) -> &'static str {
        match self {
            FrfKind::Receptance => "m/N",
            FrfKind::Mobility => "m/(N s)",
            FrfKind::Accelerance => "m/(N s^2)",
        }
    }

    /// The FRF of this kind from the receptance `h` at circular frequency `w`.
    pub fn from_receptance(self, h: c64, w: f64) -> c64 {
        match self {
            FrfKind::Receptance => h,
            FrfKind::Mobility => c64::new(0.0, w) * h,
            FrfKind::Accelerance => h * (-w * w),
        }
    }
}

/// The receptance at one output DOF over the frequencies.
#[derive(Debug, Clone, Serialize)]
pub struct FrfChannel {
    /// Global DOF index.
    pub dof: usize,
    /// Its name, `n<node>.<dir>`.
    pub name: String,
    /// Receptance at each frequency.
    #[serde(skip)]
    pub receptance: Vec<c64>,
    /// Peaks of |receptance| over frequency, with half-power bands.
    pub peaks: Vec<ResponsePeak>,
}

/// Frequency response functions from one input DOF to several outputs, at one spin speed.
#[derive(Debug, Clone, Serialize)]
pub struct FrfResult {
    /// Spin speed, rad/s.
    pub speed: f64,
    /// Excitation frequencies, Hz.
    pub frequencies_hz: Vec<f64>,
    /// Input DOF (where the unit force acts) and its name.
    pub input: (usize, String),
    /// One channel per output DOF.
    pub outputs: Vec<FrfChannel>,
}

impl FrfResult {
    /// The FRF of `kind` of output `o` at frequency index `k`.
    pub fn value(&self, kind: FrfKind, o: usize, k: usize) -> c64 {
        let w = 2.0 * std::f64::consts::PI * self.frequencies_hz[k];
        kind.from_receptance(self.outputs[o].receptance[k], w)
    }
}

/// Steady response Q to the harmonic force `force` (complex amplitudes, N) at circular
/// frequency `frequency` (rad/s) while the rotor spins at `speed` (rad/s).
///
/// # Errors
/// [`Error::Singular`] when the dynamic stiffness is singular (an undamped mode at this
/// frequency, or a rotor without supports at w = 0).
pub fn harmonic_response(
    system: &SystemMatrices,
    speed: f64,
    frequency: f64,
    force: &[c64],
) -> Result<Vec<c64>> {
    let n = system.dofs();
    let w = frequency;
    let z = Mat::<c64>::from_fn(n, n, |i, j| {
        c64::new(
            system.stiffness[(i, j)] - w * w * system.mass[(i, j)],
            w * (system.damping[(i, j)] + speed * system.gyroscopic[(i, j)]),
        )
    });
    let mut rhs = Mat::<c64>::from_fn(n, 1, |i, _| force[i]);
    faer::linalg::solvers::Solve::solve_in_place(&z.partial_piv_lu(), rhs.as_mut());
    let q: Vec<c64> = (0..n).map(|i| rhs[(i, 0)]).collect();
    if q.iter().any(|v| !v.re.is_finite() || !v.im.is_finite()) {
        return Err(Error::singular(
            "dynamic stiffness",
            format!(
                "the dynamic stiffness is singular at {:.3} Hz: the rotor has an undamped \
             mode at this frequency, or is not supported (add bearings or damping)",
                w / (2.0 * std::f64::consts::PI)
            ),
        ));
    }
    Ok(q)
}

/// Excitation frequencies of an FRF when none are given, rad/s: 1001 from 0 to 1.5 times
/// the sixth undamped natural frequency of the linearised rotor at rest (100 Hz when it has
/// fewer modes), so the first few resonances and what lies past them show.
///
/// # Errors
/// As [`undamped_modes`].
pub fn default_frequencies(model: &Model) -> Result<Vec<f64>> {
    let modes = undamped_modes(&assemble(model, Bearings::Linearised), 6)?;
    let top =
        1.5 * 2.0 * std::f64::consts::PI * modes.frequencies_hz.last().copied().unwrap_or(100.0);
    Ok((0..1001).map(|i| top * i as f64 / 1000.0).collect())
}

/// Receptances from a unit force at DOF `input` to the DOFs `outputs`, at spin speed `speed`
/// (rad/s) over the circular frequencies `frequencies` (rad/s).
///
/// # Errors
/// [`Error::InvalidOption`] for a DOF outside the model, [`Error::Singular`] for a
/// singular dynamic stiffness.
pub fn frf(
    system: &SystemMatrices,
    speed: f64,
    input: usize,
    outputs: &[usize],
    frequencies: &[f64],
) -> Result<FrfResult> {
    let n = system.dofs();
    if let Some(&bad) = std::iter::once(&input).chain(outputs).find(|&&d| d >= n) {
        return Err(Error::InvalidOption(format!(
            "DOF {bad} is not in the model (DOFs 0 to {})",
            n - 1
        )));
    }
    let mut force = vec![c64::new(0.0, 0.0); n];
    force[input] = c64::new(1.0, 0.0);
    let responses: Vec<Vec<c64>> = frequencies
        .par_iter()
        .map(|&w| {
            harmonic_response(system, speed, w, &force)
                .map(|q| outputs.iter().map(|&o| q[o]).collect())
        })
        .collect::<Result<_>>()?;
    let frequencies_hz: Vec<f64> = frequencies
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    let outputs = outputs
        .iter()
        .enumerate()
        .map(|(o, &d)| {
            let receptance: Vec<c64> = responses.iter().map(|r| r[o]).collect();
            let magnitude: Vec<f64> = receptance.iter().map(|h| h.norm()).collect();
            FrfChannel {
                dof: d,
                name: dof_name(d),
                peaks: find_peaks(&frequencies_hz, &magnitude, None),
                receptance,
            }
        })
        .collect();
    Ok(FrfResult {
        speed,
        frequencies_hz,
        input: (input, dof_name(input)),
        outputs,
    })
}
