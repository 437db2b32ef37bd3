//! Stability of a periodic solution from its monodromy matrix (Floquet theory).
//!
//! A small perturbation p of the periodic solution obeys the equations linearised about it,
//!
//! ```text
//! M p'' + (D - J_v(t)) p' + (K - J_q(t)) p = 0,   D = C + w G,
//! ```
//!
//! with J_q = dF_nl/dq and J_v = dF_nl/dv taken along the orbit, so T-periodic (T = 2 pi / w).
//! In the state z = (p, p') this is z' = A(t) z, and one period maps z(0) to Phi z(0): Phi is
//! the monodromy matrix, and its eigenvalues, the Floquet multipliers mu, decide stability
//! (stable when every |mu| < 1). The exponents lambda = ln(mu) / T have real part ln|mu| / T
//! and imaginary part arg(mu) / T in (-w/2, w/2] (the exponents of Hill's method folded into
//! that strip; Nayfeh & Balachandran, "Applied Nonlinear Dynamics", 1995, ch. 5).
//!
//! Phi is the product over the N AFT samples of exp(h A(t_j)), h = T / N, each interval
//! centred on its sample t_j = j T / N, where the harmonic balance samples the tangents: the
//! exponential midpoint rule. It is exact when A is constant (a linear system, or a force
//! whose tangents do not vary), of second order in h otherwise, and stable for every h: the
//! stiff, heavily damped modes of a contact stay decaying, however coarse the samples.
//! Each exp(h A(t_j)) is a Taylor polynomial with scaling and squaring (`linalg::Exponential`,
//! whose documentation gives the method and its sources), its powers formed by blocks of
//! the first-order form.
//! Multipliers below the round-off of Phi (about 1e-16 |Phi|: modes damped out within a
//! period) carry exponents that are only bounds, far from deciding stability.

use faer::diag::Diag;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par, Spec};

use super::balance::SampledTangents;
use crate::error::{Error, Result};
use crate::fe::SystemMatrices;
use crate::linalg::Exponential;

/// Floquet multipliers and exponents of a periodic solution.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Stability {
    /// The Floquet multipliers, eigenvalues of the monodromy matrix, (real, imaginary).
    pub multipliers: Vec<(f64, f64)>,
    /// Their exponents ln(mu) / T, (real, imaginary), 1/s and rad/s, imaginary parts in
    /// (-w/2, w/2].
    pub exponents: Vec<(f64, f64)>,
    /// The largest real part, 1/s.
    pub max_real: f64,
    /// True when every multiplier lies inside the unit circle (beyond round-off).
    pub stable: bool,
    /// The natural frequencies of the orbit: the damped natural frequencies (rad/s,
    /// ascending) and damping ratios of the linearisation averaged over the period
    /// ([`OrbitMode`]).
    pub orbit_modes: Vec<OrbitMode>,
}

/// A mode of the orbit's averaged linearisation M p'' + (C + w G - <dF/dv>) p' + (K -
/// <dF/dq>) p = 0, <.> the mean over the period of the bearings' tangents along the
/// orbit: the natural frequency a roller bearing's contacts give the rotor while it runs
/// on this orbit, which the stiffness written in the model file does not (a bearing with
/// clearance is soft when its rollers barely touch and stiff when the orbit presses them).
/// Resonance lines (a roller-passing frequency, a sum of two of these, half the speed
/// meeting one) are drawn with these frequencies.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct OrbitMode {
    /// Damped natural frequency, rad/s (positive).
    pub frequency: f64,
    /// Damping ratio, -Re(lambda) / |lambda|.
    pub damping_ratio: f64,
}

/// A multiplier is outside the unit circle when ln|mu| exceeds this: far above the
/// round-off of the eigenvalues of a product of a few hundred well-scaled exponentials
/// (1e-13), far below any physical growth over one period.
const ROUND_OFF: f64 = 1e-10;

/// Whether the multiplier (real, imaginary) lies outside the unit circle beyond the
/// round-off, as the verdict [`Stability::stable`] judges it.
pub(super) fn outside_circle((re, im): (f64, f64)) -> bool {
    re.hypot(im).ln() > ROUND_OFF
}

/// The linear part of the linearised equations with M^-1 applied, shared by every Floquet
/// problem of one model: M^-1 K, M^-1 C, M^-1 G and M^-1, row-major.
pub(crate) struct FloquetModel {
    n: usize,
    stiffness: Vec<f64>,
    damping: Vec<f64>,
    gyroscopic: Vec<f64>,
    mass_inverse: Vec<f64>,
}

impl FloquetModel {
    /// # Errors
    /// [`Error::Singular`] when M is singular.
    pub(crate) fn new(matrices: &SystemMatrices) -> Result<FloquetModel> {
        let n = matrices.mass.nrows();
        let lu = matrices.mass.partial_piv_lu();
        let solved = |m: &Mat<f64>| -> Result<Vec<f64>> {
            let mut x = m.clone();
            faer::linalg::solvers::Solve::solve_in_place(&lu, x.as_mut());
            let plain: Vec<f64> = (0..n * n).map(|k| x[(k / n, k % n)]).collect();
            if plain.iter().all(|v| v.is_finite()) {
                Ok(plain)
            } else {
                Err(Error::singular(
                    "mass matrix",
                    "the Floquet stability needs a nonsingular mass matrix".into(),
                ))
            }
        };
        Ok(FloquetModel {
            n,
            stiffness: solved(&matrices.stiffness)?,
            damping: solved(&matrices.damping)?,
            gyroscopic: solved(&matrices.gyroscopic)?,
            mass_inverse: solved(&Mat::identity(n, n))?,
        })
    }

    /// The Floquet problem of the orbit at w (rad/s) whose force tangents are `tangents`
    /// (on coordinates of this model).
    pub(crate) fn problem(&self, frequency: f64, tangents: &SampledTangents) -> FloquetProblem {
        let (n, samples) = (self.n, tangents.samples);
        let (stiffness, damping) = self.sampled_blocks(frequency, tangents);
        // The state (s p, p') with s^2 the largest 1-norm of the stiffness blocks: both
        // blocks of A then have norms of the highest natural frequency, not its square,
        // which saves the exponentials about log2(s) squarings. The multipliers do not
        // depend on s (a similarity).
        let scale = state_scale(&stiffness, n);
        let h = std::f64::consts::TAU / frequency / samples as f64;
        let states = 2 * n;
        // Column-major, as the exponential reads them: its norm and scaling run along
        // contiguous columns.
        let mut generators = vec![0.0; samples * states * states];
        for ((g, k), d) in generators
            .chunks_exact_mut(states * states)
            .zip(&stiffness)
            .zip(&damping)
        {
            for i in 0..n {
                g[(n + i) * states + i] = h * scale;
                for col in 0..n {
                    g[col * states + n + i] = -h * k[i * n + col] / scale;
                    g[(n + col) * states + n + i] = -h * d[i * n + col];
                }
            }
        }
        FloquetProblem {
            generators,
            states,
            coupling: h * scale,
            frequency,
        }
    }

    /// M^-1 (K - J_q(t_j)) and M^-1 (C + w G - J_v(t_j)) at every sample j of the orbit
    /// at w (rad/s) whose force tangents are `tangents`, row-major.
    fn sampled_blocks(
        &self,
        frequency: f64,
        tangents: &SampledTangents,
    ) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let (n, samples) = (self.n, tangents.samples);
        let (dofs, m) = (&tangents.dofs, tangents.dofs.len());
        let linear_damping: Vec<f64> = (0..n * n)
            .map(|e| self.damping[e] + frequency * self.gyroscopic[e])
            .collect();
        let mut stiffness = Vec::with_capacity(samples);
        let mut damping = Vec::with_capacity(samples);
        for j in 0..samples {
            let mut k = self.stiffness.clone();
            let mut d = linear_damping.clone();
            for (c, &col) in dofs.iter().enumerate() {
                for (a, &force_row) in dofs.iter().enumerate() {
                    let (jq, jv) = (
                        tangents.dq[(a * m + c) * samples + j],
                        tangents.dv[(a * m + c) * samples + j],
                    );
                    if jq == 0.0 && jv == 0.0 {
                        continue;
                    }
                    for i in 0..n {
                        let minv = self.mass_inverse[i * n + force_row];
                        k[i * n + col] -= minv * jq;
                        d[i * n + col] -= minv * jv;
                    }
                }
            }
            stiffness.push(k);
            damping.push(d);
        }
        (stiffness, damping)
    }
}

/// s of the scaled state (s p, p'): the square root of the largest 1-norm of the n x n
/// `stiffness` blocks (row-major), 1 where that is zero or not finite.
fn state_scale(stiffness: &[Vec<f64>], n: usize) -> f64 {
    let largest = stiffness
        .iter()
        .map(|k| {
            (0..n)
                .map(|col| (0..n).map(|i| k[i * n + col].abs()).sum::<f64>())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    if largest > 0.0 && largest.is_finite() {
        largest.sqrt()
    } else {
        1.0
    }
}

/// The monodromy matrix's factors of one periodic solution, ready to multiply out: building
/// them needs the harmonic balance (and its work buffers), solving does not, so the solves
/// of a branch's points can run on another thread while the path goes on.
pub struct FloquetProblem {
    /// h A(t_j) of every interval, column-major, one states x states block after another.
    generators: Vec<f64>,
    /// Size of the state, twice the coordinates.
    states: usize,
    /// The upper right block of every h A(t_j), h s times the identity.
    coupling: f64,
    frequency: f64,
}

impl FloquetProblem {
    /// The multipliers, the exponents and the verdict.
    ///
    /// # Errors
    /// [`Error::NotConverged`] when an exponential or the eigen-solver fails (a tangent
    /// that is not finite).
    pub fn solve(self) -> Result<Stability> {
        let (s, frequency, coupling) = (self.states, self.frequency, self.coupling);
        let failed = || {
            Error::not_converged(
                "monodromy matrix",
                None,
                None,
                format!("the monodromy matrix could not be formed at {frequency} rad/s"),
            )
        };
        let orbit_modes = self.averaged_modes().ok_or_else(failed)?;
        // Every step's exponential and product reuse the same buffers.
        let mut exponential = Exponential::new(s);
        let mut monodromy = Mat::<f64>::identity(s, s);
        let mut next = Mat::<f64>::zeros(s, s);
        for generator in self.generators.chunks_exact(s * s) {
            let step = exponential
                .of_state(generator, coupling)
                .ok_or_else(failed)?;
            matmul(
                next.as_mut(),
                Accum::Replace,
                step,
                monodromy.as_ref(),
                1.0,
                Par::Seq,
            );
            std::mem::swap(&mut monodromy, &mut next);
        }
        let multipliers = eigenvalues(&monodromy).map_err(|_| failed())?;
        let period = std::f64::consts::TAU / frequency;
        let exponents: Vec<(f64, f64)> = multipliers
            .iter()
            .map(|&(re, im)| {
                let modulus = re.hypot(im).max(f64::MIN_POSITIVE);
                (modulus.ln() / period, im.atan2(re) / period)
            })
            .collect();
        let max_real = exponents
            .iter()
            .map(|e| e.0)
            .fold(f64::NEG_INFINITY, f64::max);
        Ok(Stability {
            stable: max_real * period < ROUND_OFF,
            multipliers,
            exponents,
            max_real,
            orbit_modes,
        })
    }

    /// The modes of the mean of the intervals' generators h A(t_j) over the period: the
    /// averaged linearisation's state matrix times h (with the coordinates scaled by s, a
    /// similarity that leaves the eigenvalues alone), whose eigenvalues divided by h are
    /// lambda = -zeta w_n +- i w_d. One of each conjugate pair is kept; real eigenvalues
    /// (overdamped) have no frequency and are left out. `None` when the eigen-solver fails.
    fn averaged_modes(&self) -> Option<Vec<OrbitMode>> {
        let s = self.states;
        let intervals = self.generators.len() / (s * s);
        let mut mean = Mat::<f64>::zeros(s, s);
        for generator in self.generators.chunks_exact(s * s) {
            for col in 0..s {
                for row in 0..s {
                    mean[(row, col)] += generator[col * s + row];
                }
            }
        }
        let h = std::f64::consts::TAU / self.frequency / intervals as f64;
        for col in 0..s {
            for row in 0..s {
                mean[(row, col)] /= h * intervals as f64;
            }
        }
        // The upper right block, h s I in every interval, is the same in the mean.
        let mut modes: Vec<OrbitMode> = eigenvalues(&mean)
            .ok()?
            .into_iter()
            .filter(|&(_, im)| im > 0.0)
            .map(|(re, im)| OrbitMode {
                frequency: im,
                damping_ratio: -re / re.hypot(im),
            })
            .collect();
        modes.sort_by(|a, b| a.frequency.total_cmp(&b.frequency));
        Some(modes)
    }
}

/// The eigenvalues of the real matrix `a` (faer's Hessenberg reduction and real Schur QR):
/// real ones with an imaginary part of exactly zero, complex ones in conjugate pairs.
fn eigenvalues(a: &Mat<f64>) -> std::result::Result<Vec<(f64, f64)>, evd::EvdError> {
    let n = a.nrows();
    let params: Spec<evd::EvdParams, f64> = Default::default();
    let mut re = Diag::<f64>::zeros(n);
    let mut im = Diag::<f64>::zeros(n);
    let par = faer::Par::Seq;
    let no = evd::ComputeEigenvectors::No;
    let scratch = evd::evd_scratch::<f64>(n, no, no, par, params);
    let mut buffer = MemBuffer::new(scratch);
    let stack = MemStack::new(&mut buffer);
    evd::evd_real(
        a.as_ref(),
        re.as_mut(),
        im.as_mut(),
        None,
        None,
        par,
        stack,
        params,
    )?;
    let (re, im) = (re.column_vector(), im.column_vector());
    Ok(re.iter().zip(im.iter()).map(|(&r, &i)| (r, i)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hbm::continuation::Periodic;
    use crate::hbm::{HarmonicBalance, HbOptions};
    use crate::system::System;

    #[test]
    fn linear_system_exponents_are_its_eigenvalues_shifted_into_the_strip() {
        // A damped gyroscopic 2-DOF rotor: Floquet exponents of any periodic response are
        // the eigenvalues of M s^2 + (C + w G) s + K, up to multiples of i w.
        let w = 1.3;
        let mass = Mat::from_fn(2, 2, |i, j| if i == j { 1.0 + i as f64 } else { 0.0 });
        let stiffness = Mat::from_fn(2, 2, |i, j| [[5.0, 0.5], [0.5, 3.0]][i][j]);
        let damping = Mat::from_fn(2, 2, |i, j| if i == j { 0.05 } else { 0.0 });
        let gyroscopic = Mat::from_fn(2, 2, |i, j| [[0.0, 0.4], [-0.4, 0.0]][i][j]);
        let d = &damping + &gyroscopic * faer::Scale(w);
        let problem = System {
            matrices: SystemMatrices {
                mass: mass.clone(),
                stiffness: stiffness.clone(),
                damping,
                gyroscopic,
            },
            constant_force: vec![0.0; 2],
            unbalance_re: vec![0.1, 0.0],
            unbalance_im: vec![0.0, 0.1],
            harmonic_re: vec![0.0; 2],
            harmonic_im: vec![0.0; 2],
            nonlinear: Vec::new(),
        };
        let mut hb = HarmonicBalance::new(problem, HbOptions::new(3)).unwrap();
        let zero = vec![0.0; hb.unknowns()];
        let solution = hb.solve(w, &zero).unwrap();
        let stability = hb
            .floquet_problem(&solution.coefficients, w)
            .unwrap()
            .solve()
            .unwrap();

        let companion = Mat::<f64>::from_fn(4, 4, |i, j| match (i < 2, j < 2) {
            (true, true) => 0.0,
            (true, false) => f64::from(u8::from(j - 2 == i)),
            (false, true) => -stiffness[(i - 2, j)] / mass[(i - 2, i - 2)],
            (false, false) => -d[(i - 2, j - 2)] / mass[(i - 2, i - 2)],
        });
        let values = companion.eigen().unwrap();
        let values = values.S().column_vector();
        assert_eq!(stability.exponents.len(), 4);
        for k in 0..4 {
            let (re, im) = (values[k].re, values[k].im);
            let shifted = im - w * (im / w).round();
            let nearest = stability
                .exponents
                .iter()
                .map(|e| (e.0 - re).hypot(e.1 - shifted))
                .fold(f64::INFINITY, f64::min);
            // A constant A: the product of the N exponentials is exp(A T) to round-off
            // (N products of matrices of norm about 1), and two eigen-solves.
            assert!(nearest < 1e-10, "eigenvalue {re} + {im} i: {nearest:e}");
        }
        assert!(stability.stable);
        // Without a nonlinear force the averaged linearisation is the linear system: its
        // modes are the eigenvalues with positive imaginary part, unshifted (the average of
        // equal generators and one eigen-solve: round-off).
        let mut expected: Vec<(f64, f64)> = (0..4)
            .map(|k| (values[k].re, values[k].im))
            .filter(|v| v.1 > 0.0)
            .collect();
        expected.sort_by(|a, b| a.1.total_cmp(&b.1));
        assert_eq!(stability.orbit_modes.len(), expected.len());
        for (mode, (re, im)) in stability.orbit_modes.iter().zip(expected) {
            assert!(
                (mode.frequency - im).abs() < 1e-12 * im,
                "{mode:?} against {im}"
            );
            let zeta = -re / re.hypot(im);
            assert!(
                (mode.damping_ratio - zeta).abs() < 1e-12,
                "{mode:?} against {zeta}"
            );
        }
    }
}
