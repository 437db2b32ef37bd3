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
mod request;

pub use report::{FrfReport, FrfSummary};
pub use request::{dof_spec, DofSpec, FrfRequest, ResolvedFrf, DEFAULT_FRF_FORCE};

use faer::{c64, Mat};
use serde::Serialize;

use super::peaks::{
    find_peaks, maxima_with_bases, merge_sorted, refinement_points, samples_to_check, split_maxima,
    Maxima, ResponsePeak, REFINE_PASSES,
};
use crate::error::{Error, Result};
use crate::fe::{assemble_banded, dof_name, BandedSystem, Bearings, Matrices, SystemMatrices};
use crate::linalg::banded::BandedLu;
use crate::modal::undamped_modes;
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
    /// Peaks of |receptance| over frequency, with half-power bands: the local maxima that
    /// stand above the curve's round-off.
    pub peaks: Vec<ResponsePeak>,
    /// Frequencies, Hz, of the local maxima of |receptance| within its round-off, which are
    /// no peaks (fine meshes, see [`frf`]); one at a resonance means its top is lost.
    pub maxima_within_round_off_hz: Vec<f64>,
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
/// the dynamic stiffness Z = K - w^2 M + i w (C + Omega G), on its bands where they are
/// narrow (`solves_banded`: an assembled mesh, whose cost grows linearly with the
/// elements) and dense otherwise (a reduced model).
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
    solve(system, speed, frequency, force, false).map(|solved| solved.q)
}

/// [`harmonic_response`] and, per DOF, the size of its round-off: the correction
/// Z^-1 (F - Z Q) that one step of iterative refinement would add, with the residual of
/// the computed Q taken in the same precision and solved with the same factors (Higham,
/// "Accuracy and Stability of Numerical Algorithms", 2nd ed., section 12.1). The residual
/// of a backward-stable solve is of the order of the rounding committed in forming and
/// factorising Z, so the correction measures the error in Q to within a small factor,
/// including the part that Z^-1 amplifies near a mode the force does not excite. One more
/// solve and product with Z: about a seventh more than the solve alone on the bands.
///
/// # Errors
/// As [`harmonic_response`].
pub(crate) fn harmonic_response_and_round_off(
    system: &impl Matrices,
    speed: f64,
    frequency: f64,
    force: &[c64],
) -> Result<(Vec<c64>, Vec<f64>)> {
    let solved = solve(system, speed, frequency, force, true)?;
    let round_off = solved
        .correction
        .map_or_else(Vec::new, |c| c.iter().map(|d| d.norm()).collect());
    Ok((solved.q, round_off))
}

/// A solve of Z Q = F: Q and, when asked for, the correction Z^-1 (F - Z Q).
struct Solved {
    q: Vec<c64>,
    correction: Option<Vec<c64>>,
}

/// [`harmonic_response`], with the correction of [`harmonic_response_and_round_off`] when
/// `estimate` is set.
fn solve(
    system: &impl Matrices,
    speed: f64,
    frequency: f64,
    force: &[c64],
    estimate: bool,
) -> Result<Solved> {
    let solved = if !solves_banded(system) {
        dense_response(&system.dense(), speed, frequency, force, estimate)
    } else {
        banded_response(&system.banded(), speed, frequency, force, estimate)
    };
    let finite = |v: &[c64]| v.iter().all(|v| v.re.is_finite() && v.im.is_finite());
    match solved {
        Some(s) if finite(&s.q) && s.correction.as_deref().is_none_or(finite) => Ok(s),
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

/// Whether Z is solved on its bands: an LU of half bandwidth b costs about 2 n b^2, a dense
/// one 2 n^3 / 3, so the bands pay when 3 b^2 < n^2. An assembled beam mesh (b = 7) is
/// solved on them at every size; a Craig-Bampton model, full, dense. The rule for the
/// modes ([`crate::modal::solves_dense`]) does not fit a single solve: at 40 elements (164 DOFs) it
/// kept the dense path, and `unbalance` took 1.1 s and 270 MB against 0.5 s and 28 MB at
/// 80 elements on the bands.
fn solves_banded(system: &impl Matrices) -> bool {
    let (n, b) = (system.dofs(), system.reach());
    3 * b * b < n * n
}

/// The complex entry (i, j) of Z = K - w^2 M + i w (C + Omega G) from the entries of the
/// four matrices.
fn dynamic_stiffness([k, m, c, g]: [f64; 4], speed: f64, w: f64) -> c64 {
    c64::new(k - w * w * m, w * (c + speed * g))
}

/// Q from a dense LU of Z (a small model), with the correction when `estimate` is set;
/// `None` is never returned: a singular Z gives entries that are not finite.
fn dense_response(
    system: &SystemMatrices,
    speed: f64,
    w: f64,
    force: &[c64],
    estimate: bool,
) -> Option<Solved> {
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
    let lu = z.partial_piv_lu();
    let f = Mat::<c64>::from_fn(n, 1, |i, _| force[i]);
    let mut q = f.clone();
    faer::linalg::solvers::Solve::solve_in_place(&lu, q.as_mut());
    let correction = estimate.then(|| {
        let mut r = &f - &z * &q;
        faer::linalg::solvers::Solve::solve_in_place(&lu, r.as_mut());
        (0..n).map(|i| r[(i, 0)]).collect()
    });
    Some(Solved {
        q: (0..n).map(|i| q[(i, 0)]).collect(),
        correction,
    })
}

/// Q from a band LU of Z in real form (see [`RealForm`]), with the correction when
/// `estimate` is set. `None` when Z is singular.
fn banded_response(
    system: &BandedSystem,
    speed: f64,
    w: f64,
    force: &[c64],
    estimate: bool,
) -> Option<Solved> {
    let z = RealForm::new(system, speed, w);
    let lu = BandedLu::new(z.size, z.lower, z.upper, |i, j| z.entry(i, j))?;
    let f: Vec<f64> = force.iter().flat_map(|f| [f.re, f.im]).collect();
    let mut q = f.clone();
    lu.solve_rows(&mut q, 1);
    let correction = estimate.then(|| {
        let mut r = z.residual(&f, &q);
        lu.solve_rows(&mut r, 1);
        complex(&r)
    });
    Some(Solved {
        q: complex(&q),
        correction,
    })
}

/// Complex values from their real and imaginary parts, interleaved.
fn complex(parts: &[f64]) -> Vec<c64> {
    parts
        .chunks_exact(2)
        .map(|p| c64::new(p[0], p[1]))
        .collect()
}

/// Z in real form: coordinate i's real and imaginary parts are rows 2i and 2i + 1,
/// [Re Z, -Im Z; Im Z, Re Z] per entry, which keeps the band (twice as wide plus one).
struct RealForm<'a> {
    system: &'a BandedSystem,
    speed: f64,
    w: f64,
    size: usize,
    lower: usize,
    upper: usize,
}

impl<'a> RealForm<'a> {
    fn new(system: &'a BandedSystem, speed: f64, w: f64) -> Self {
        let (lower, upper) = system.bands().iter().fold((0, 0), |(l, u), b| {
            let (bl, bu) = b.widths();
            (l.max(bl), u.max(bu))
        });
        RealForm {
            system,
            speed,
            w,
            size: 2 * system.dofs(),
            lower: 2 * lower + 1,
            upper: 2 * upper + 1,
        }
    }

    fn entry(&self, i: usize, j: usize) -> f64 {
        let z = dynamic_stiffness(
            self.system.bands().map(|b| b.get(i / 2, j / 2)),
            self.speed,
            self.w,
        );
        match (i % 2, j % 2) {
            (0, 0) | (1, 1) => z.re,
            (0, _) => -z.im,
            _ => z.im,
        }
    }

    /// f - Z q (both interleaved), from the products of the four bands with Re q and Im q:
    /// Z (a + i b) = (K - w^2 M) a - w (C + Omega G) b + i ((K - w^2 M) b + w (C + Omega G) a).
    /// The band products run along contiguous diagonals, far cheaper than Z's entries one
    /// by one.
    fn residual(&self, f: &[f64], q: &[f64]) -> Vec<f64> {
        let n = self.system.dofs();
        let part =
            |offset: usize| -> Vec<f64> { q.iter().skip(offset).step_by(2).copied().collect() };
        let (a, b) = (part(0), part(1));
        let products = |x: &[f64]| {
            self.system.bands().map(|band| {
                let mut out = vec![0.0; n];
                band.mul_add(x, &mut out);
                out
            })
        };
        let ([ka, ma, ca, ga], [kb, mb, cb, gb]) = (products(&a), products(&b));
        let (w, speed) = (self.w, self.speed);
        (0..n)
            .flat_map(|i| {
                let elastic = |k: &[f64], m: &[f64]| k[i] - w * w * m[i];
                let viscous = |c: &[f64], g: &[f64]| w * (c[i] + speed * g[i]);
                [
                    f[2 * i] - (elastic(&ka, &ma) - viscous(&cb, &gb)),
                    f[2 * i + 1] - (elastic(&kb, &mb) + viscous(&ca, &ga)),
                ]
            })
            .collect()
    }
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
/// (rad/s) over exactly the circular frequencies `frequencies` (rad/s), telling `progress`
/// after every frequency.
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
    let force = unit_force(system, input, outputs)?;
    let count = frequencies.len();
    let responses = responses_at(
        system,
        speed,
        &force,
        outputs,
        frequencies,
        progress,
        (0, count),
    )?;
    let magnitudes = magnitudes_of(&responses, outputs.len());
    let maxima = resolved_maxima(
        system,
        speed,
        frequencies,
        &force,
        outputs,
        &magnitudes,
        progress,
    )?;
    Ok(result_from(
        speed,
        input,
        outputs,
        frequencies,
        &responses,
        &magnitudes,
        &maxima,
    ))
}

/// [`frf`] over `frequencies` and, added to them, frequencies around every peak of an
/// output's |receptance| until the peak's half-power band holds
/// [`BAND_SAMPLES`](super::BAND_SAMPLES) steps, over at most 16 passes, as the unbalance
/// response refines its speeds ([`super::unbalance_response_refined`]): a lightly damped
/// resonance is narrower than an even grid samples, and its peak and amplification factor
/// must come out of samples, not out of the interpolation between them. The result's
/// frequencies are sorted ascending without duplicates; `progress`'s total grows with each
/// pass.
///
/// # Errors
/// As [`frf`].
pub fn frf_refined(
    system: &impl Matrices,
    speed: f64,
    input: usize,
    outputs: &[usize],
    frequencies: &[f64],
    progress: Option<&Progress>,
) -> Result<FrfResult> {
    let force = unit_force(system, input, outputs)?;
    let mut frequencies = frequencies.to_vec();
    frequencies.sort_by(f64::total_cmp);
    frequencies.dedup();
    let count = frequencies.len();
    let mut responses = responses_at(
        system,
        speed,
        &force,
        outputs,
        &frequencies,
        progress,
        (0, count),
    )?;
    let mut passes = 0;
    loop {
        let magnitudes = magnitudes_of(&responses, outputs.len());
        let maxima = resolved_maxima(
            system,
            speed,
            &frequencies,
            &force,
            outputs,
            &magnitudes,
            progress,
        )?;
        let added = if passes < REFINE_PASSES {
            refinement_points(&frequencies, &magnitudes, &maxima)
        } else {
            Vec::new()
        };
        if added.is_empty() {
            return Ok(result_from(
                speed,
                input,
                outputs,
                &frequencies,
                &responses,
                &magnitudes,
                &maxima,
            ));
        }
        passes += 1;
        let told = (frequencies.len(), frequencies.len() + added.len());
        let more = responses_at(system, speed, &force, outputs, &added, progress, told)?;
        (frequencies, responses) = merge_sorted(frequencies, responses, added, more);
    }
}

/// A unit force at DOF `input`, after checking that it and `outputs` are in the model.
fn unit_force(system: &impl Matrices, input: usize, outputs: &[usize]) -> Result<Vec<c64>> {
    let n = system.dofs();
    if let Some(&bad) = std::iter::once(&input).chain(outputs).find(|&&d| d >= n) {
        return Err(Error::InvalidOption(format!(
            "DOF {bad} is not in the model (DOFs 0 to {})",
            n - 1
        )));
    }
    let mut force = vec![c64::new(0.0, 0.0); n];
    force[input] = c64::new(1.0, 0.0);
    Ok(force)
}

/// The responses at `outputs` to `force` at each of `frequencies` (rad/s), in parallel;
/// `progress` is told `(done before, total)` as [`map_told`] is.
fn responses_at(
    system: &impl Matrices,
    speed: f64,
    force: &[c64],
    outputs: &[usize],
    frequencies: &[f64],
    progress: Option<&Progress>,
    told: (usize, usize),
) -> Result<Vec<Vec<c64>>> {
    map_told(
        frequencies,
        progress,
        told,
        ("the FRF", "frequencies"),
        |&w| {
            harmonic_response(system, speed, w, force)
                .map(|q| outputs.iter().map(|&o| q[o]).collect())
        },
    )
}

/// |receptance| of each output over the frequencies.
fn magnitudes_of(responses: &[Vec<c64>], outputs: usize) -> Vec<Vec<f64>> {
    (0..outputs)
        .map(|o| responses.iter().map(|r| r[o].norm()).collect())
        .collect()
}

/// The FRF from the responses at `frequencies` (rad/s), each output's peaks at its `maxima`.
fn result_from(
    speed: f64,
    input: usize,
    outputs: &[usize],
    frequencies: &[f64],
    responses: &[Vec<c64>],
    magnitudes: &[Vec<f64>],
    maxima: &[Maxima],
) -> FrfResult {
    let frequencies_hz: Vec<f64> = frequencies
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    let outputs = outputs
        .iter()
        .zip(magnitudes.iter().zip(maxima))
        .enumerate()
        .map(|(o, (&d, (magnitude, maxima)))| FrfChannel {
            dof: d,
            name: dof_name(d),
            peaks: find_peaks(&frequencies_hz, magnitude, None, |k| {
                maxima.resolved.binary_search(&k).is_ok()
            }),
            maxima_within_round_off_hz: maxima
                .within_round_off
                .iter()
                .map(|&k| frequencies_hz[k])
                .collect(),
            receptance: responses.iter().map(|r| r[o]).collect(),
        })
        .collect();
    FrfResult {
        speed,
        frequencies_hz,
        input: (input, dof_name(input)),
        outputs,
    }
}

/// Per output, the local maxima of |receptance|, split by whether they stand above the
/// curve's round-off ([`super::peaks::stands_above_round_off`]), estimated by solving again
/// at each maximum and at the sample its prominence is measured from
/// ([`harmonic_response_and_round_off`], in parallel; `progress` is told of these checks).
///
/// # Errors
/// As [`harmonic_response`].
fn resolved_maxima(
    system: &impl Matrices,
    speed: f64,
    frequencies: &[f64],
    force: &[c64],
    outputs: &[usize],
    magnitudes: &[Vec<f64>],
    progress: Option<&Progress>,
) -> Result<Vec<Maxima>> {
    let candidates: Vec<_> = magnitudes.iter().map(|y| maxima_with_bases(y)).collect();
    let checked = samples_to_check(&candidates);
    let estimates: Vec<Vec<f64>> = map_told(
        &checked,
        progress,
        (0, checked.len()),
        (
            "the round-off check of the peaks",
            "frequencies checked for round-off",
        ),
        |&j| {
            let (_, round_off) =
                harmonic_response_and_round_off(system, speed, frequencies[j], force)?;
            Ok(outputs
                .iter()
                .map(|&d| round_off.get(d).copied().unwrap_or(0.0))
                .collect())
        },
    )?;
    let round_off = |j: usize, o: usize| checked.binary_search(&j).map_or(0.0, |i| estimates[i][o]);
    Ok(candidates
        .iter()
        .zip(magnitudes)
        .enumerate()
        .map(|(o, (candidates, y))| split_maxima(y, candidates, |j| round_off(j, o)))
        .collect())
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
            let fast = banded_response(&banded, speed, w, &force, false).unwrap().q;
            let slow = dense_response(&dense, speed, w, &force, false).unwrap().q;
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
