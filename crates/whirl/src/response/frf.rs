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
use serde::Serialize;

use super::peaks::{find_peaks, ResponsePeak};
use crate::error::{Error, Result};
use crate::fe::{assemble_banded, dof_name, BandedSystem, Bearings, Matrices, SystemMatrices};
use crate::linalg::banded::BandedLu;
use crate::modal::{solves_dense, undamped_modes};
use crate::model::Model;
use crate::progress::{map_told, Progress};

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
/// frequency `frequency` (rad/s) while the rotor spins at `speed` (rad/s): the solve of
/// the dynamic stiffness Z = K - w^2 M + i w (C + Omega G), dense for a small model and on
/// the bands above ([`crate::modal::solves_dense`]), so its cost grows linearly with the
/// elements.
///
/// # Errors
/// [`Error::Singular`] when the dynamic stiffness is singular (an undamped mode at this
/// frequency, or a rotor without supports at w = 0).
pub fn harmonic_response(
    system: &impl Matrices,
    speed: f64,
    frequency: f64,
    force: &[c64],
) -> Result<Vec<c64>> {
    let q = if solves_dense(system.dofs(), 0) {
        dense_response(&system.dense(), speed, frequency, force)
    } else {
        banded_response(&system.banded(), speed, frequency, force)
    };
    match q {
        Some(q) if q.iter().all(|v| v.re.is_finite() && v.im.is_finite()) => Ok(q),
        _ => Err(Error::singular(
            "dynamic stiffness",
            format!(
                "the dynamic stiffness is singular at {:.3} Hz: the rotor has an undamped \
             mode at this frequency, or is not supported (add bearings or damping)",
                frequency / (2.0 * std::f64::consts::PI)
            ),
        )),
    }
}

/// The complex entry (i, j) of Z = K - w^2 M + i w (C + Omega G) from the entries of the
/// four matrices.
fn dynamic_stiffness([k, m, c, g]: [f64; 4], speed: f64, w: f64) -> c64 {
    c64::new(k - w * w * m, w * (c + speed * g))
}

/// Q from a dense LU of Z (a small model); `None` is never returned: a singular Z gives
/// entries that are not finite.
fn dense_response(system: &SystemMatrices, speed: f64, w: f64, force: &[c64]) -> Option<Vec<c64>> {
    let n = system.dofs();
    let z = Mat::<c64>::from_fn(n, n, |i, j| {
        let entry = |a: &Mat<f64>| a[(i, j)];
        dynamic_stiffness(
            [
                &system.stiffness,
                &system.mass,
                &system.damping,
                &system.gyroscopic,
            ]
            .map(entry),
            speed,
            w,
        )
    });
    let mut rhs = Mat::<c64>::from_fn(n, 1, |i, _| force[i]);
    faer::linalg::solvers::Solve::solve_in_place(&z.partial_piv_lu(), rhs.as_mut());
    Some((0..n).map(|i| rhs[(i, 0)]).collect())
}

/// Q from a band LU of Z in real form: coordinate i's real and imaginary parts are rows
/// 2i and 2i + 1, [Re Z, -Im Z; Im Z, Re Z] per entry, which keeps the band (twice as wide
/// plus one). `None` when Z is singular.
fn banded_response(system: &BandedSystem, speed: f64, w: f64, force: &[c64]) -> Option<Vec<c64>> {
    let n = system.dofs();
    let bands = [
        &system.stiffness,
        &system.mass,
        &system.damping,
        &system.gyroscopic,
    ];
    let (lower, upper) = bands.iter().fold((0, 0), |(l, u), b| {
        let (bl, bu) = b.widths();
        (l.max(bl), u.max(bu))
    });
    let lu = BandedLu::new(2 * n, 2 * lower + 1, 2 * upper + 1, |i, j| {
        let z = dynamic_stiffness(bands.map(|b| b.get(i / 2, j / 2)), speed, w);
        match (i % 2, j % 2) {
            (0, 0) | (1, 1) => z.re,
            (0, _) => -z.im,
            _ => z.im,
        }
    })?;
    let mut rhs: Vec<f64> = force.iter().flat_map(|f| [f.re, f.im]).collect();
    lu.solve_rows(&mut rhs, 1);
    Some(rhs.chunks_exact(2).map(|p| c64::new(p[0], p[1])).collect())
}

/// Excitation frequencies of an FRF when none are given, rad/s: 1001 from 0 to 1.5 times
/// the sixth undamped natural frequency of the linearised rotor at rest (100 Hz when it has
/// fewer modes), so the first few resonances and what lies past them show.
///
/// # Errors
/// As [`undamped_modes`].
pub fn default_frequencies(model: &Model) -> Result<Vec<f64>> {
    let modes = undamped_modes(&assemble_banded(model, Bearings::Linearised), 6)?;
    let top =
        1.5 * 2.0 * std::f64::consts::PI * modes.frequencies_hz.last().copied().unwrap_or(100.0);
    Ok((0..1001).map(|i| top * i as f64 / 1000.0).collect())
}

/// Receptances from a unit force at DOF `input` to the DOFs `outputs`, at spin speed `speed`
/// (rad/s) over the circular frequencies `frequencies` (rad/s), telling `progress` after
/// every frequency.
///
/// # Errors
/// [`Error::InvalidOption`] for a DOF outside the model, [`Error::Singular`] for a
/// singular dynamic stiffness, [`Error::Interrupted`] when `progress` stopped it.
pub fn frf(
    system: &impl Matrices,
    speed: f64,
    input: usize,
    outputs: &[usize],
    frequencies: &[f64],
    progress: Option<&Progress>,
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
    let responses: Vec<Vec<c64>> = map_told(
        frequencies,
        progress,
        (0, frequencies.len()),
        ("the FRF", "frequencies"),
        |&w| {
            harmonic_response(system, speed, w, &force)
                .map(|q| outputs.iter().map(|&o| q[o]).collect())
        },
    )?;
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

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::fe::{assemble_banded, unbalance_force, Bearings};
    use crate::model::Model;

    #[test]
    fn the_banded_response_equals_the_dense_one() {
        // 160 elements (644 DOFs): harmonic_response takes the band; both solves are run on
        // the same matrices, at rest and spinning, below, near and above the first
        // critical speed (about 50 Hz).
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .remeshed(&[160])
            .unwrap();
        let banded = assemble_banded(&model, Bearings::Linearised);
        let dense = banded.to_dense();
        let force = unbalance_force(&model, banded.dofs());
        for (speed_hz, frequency_hz) in [(0.0, 20.0), (50.0, 50.0), (120.0, 300.0)] {
            let (speed, w) = (2.0 * PI * speed_hz, 2.0 * PI * frequency_hz);
            let fast = banded_response(&banded, speed, w, &force).unwrap();
            let slow = dense_response(&dense, speed, w, &force).unwrap();
            let largest = slow.iter().map(|q| q.norm()).fold(0.0, f64::max);
            let difference = fast
                .iter()
                .zip(&slow)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0, f64::max);
            // Two pivoted LU solves of one system agree to about n eps cond(Z): K's
            // largest entries are 2e12 N/m at this mesh against 1e6 N/m for the lowest
            // mode, so 1288 x 2.2e-16 x 2e6 = 6e-7 of the largest response (1.1e-7 measured).
            assert!(difference <= 1e-6 * largest, "{difference} of {largest}");
            assert!(largest > 0.0);
        }
    }
}
