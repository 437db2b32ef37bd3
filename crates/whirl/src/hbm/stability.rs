//! Stability of a periodic solution by Hill's method.
//!
//! A perturbation e^{lambda t} p(t), p periodic and written in the same Fourier basis as
//! the solution, satisfies (the time derivative acting on e^{lambda t} p is lambda + Nabla)
//!
//! ```text
//! (lambda^2 Delta_2 + lambda Delta_1 + Delta_0) p = 0
//! Delta_2 = M,   Delta_1 = D + 2 M Nabla - G[dF/dv],   Delta_0 = dR/dx
//! ```
//!
//! (M and D = C + w G applied per slot). The truncated problem has n (2H + 1) pairs of
//! eigenvalues, copies lambda + i k w of the 2n Floquet exponents; the copies whose
//! imaginary parts are smallest converge first, so the 2n of smallest |Im| are kept
//! (Lazarus & Thomas 2010; Peletan et al. 2013). The solution is stable when all have
//! negative real parts.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::evd;
use faer::{diag::Diag, Mat, Spec};

use super::balance::HarmonicBalance;
use crate::error::{Error, Result};

/// Floquet exponents of a periodic solution.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Stability {
    /// The 2n Floquet exponents kept, (real, imaginary), 1/s and rad/s.
    pub exponents: Vec<(f64, f64)>,
    /// The largest real part, 1/s.
    pub max_real: f64,
    /// True when every exponent has a negative real part (beyond round-off).
    pub stable: bool,
}

/// Hill's method at the solution `x` at frequency w (rad/s).
///
/// # Errors
/// [`Error::Singular`] when M is singular, [`Error::NotConverged`] when the eigen-solver
/// fails.
pub fn hill_stability(hb: &mut HarmonicBalance, x: &[f64], frequency: f64) -> Result<Stability> {
    hb.check_arguments(frequency, x)?;
    let lin = hb.linearise(x, frequency);
    hill_problem(hb, &lin.jacobian, &lin.velocity_galerkin, frequency)?.solve()
}

/// Hill's eigenproblem of one periodic solution, ready to solve: building it needs the
/// harmonic balance (and its work buffers), solving it does not, so the solves of a
/// branch's points can run in parallel.
pub struct HillProblem {
    companion: Mat<f64>,
    /// Number of coordinates n (2n exponents are kept).
    coordinates: usize,
    frequency: f64,
}

/// Hill's eigenproblem from dR/dx (`jacobian`) and G[dF/dv] (`velocity_galerkin`) of a
/// solution of `hb`'s problem, which supplies M and D.
pub(crate) fn hill_problem(
    hb: &HarmonicBalance,
    jacobian: &Mat<f64>,
    velocity_galerkin: &Mat<f64>,
    frequency: f64,
) -> Result<HillProblem> {
    let n = hb.problem().size();
    let size = hb.unknowns();
    let mass_inverse = block_inverse_mass(hb, size)?;
    let d = hb.damping_operator(frequency);
    let mass = block_diagonal(&hb.problem().matrices.mass, size);
    let mut delta_1 =
        block_diagonal(&d, size) + hb.times_derivative(&mass, frequency) * faer::Scale(2.0);
    delta_1 -= velocity_galerkin;
    let stiffness_part = &mass_inverse * jacobian;
    let damping_part = &mass_inverse * &delta_1;
    // Companion form of the quadratic problem: state (p, lambda p).
    let companion = Mat::<f64>::from_fn(2 * size, 2 * size, |i, j| match (i < size, j < size) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - size == i)),
        (false, true) => -stiffness_part[(i - size, j)],
        (false, false) => -damping_part[(i - size, j - size)],
    });
    Ok(HillProblem {
        companion,
        coordinates: n,
        frequency,
    })
}

impl HillProblem {
    /// The Floquet exponents and the verdict.
    ///
    /// # Errors
    /// [`Error::NotConverged`] when the eigen-solver fails.
    pub fn solve(self) -> Result<Stability> {
        let frequency = self.frequency;
        let mut all = eigenvalues(&self.companion).map_err(|_| {
            Error::not_converged(
                "Hill's eigenproblem",
                None,
                None,
                format!("Hill's eigenproblem did not converge at {frequency} rad/s"),
            )
        })?;
        let largest = all.iter().map(|(re, im)| re.hypot(*im)).fold(0.0, f64::max);
        let exponents = floquet_exponents(all.as_mut_slice(), 2 * self.coordinates, frequency);
        let max_real = exponents
            .iter()
            .map(|e| e.0)
            .fold(f64::NEG_INFINITY, f64::max);
        // Eigenvalues carry round-off of about eps |A|; 1e-10 of the largest is well above
        // it and well below any physical growth rate.
        let stable = max_real < 1e-10 * largest;
        Ok(Stability {
            exponents,
            max_real,
            stable,
        })
    }
}

/// The `count` Floquet exponents among the Hill eigenvalues `values`, folded into the strip
/// |Im| <= w/2.
///
/// Copies lambda + i k w closest to the real axis are the best converged, so eigenvalues are
/// taken by increasing |Im| and folded into the strip; a folded value that repeats one
/// already taken is another copy and is skipped. Skipping matters when a mode's frequency
/// lies beyond H w: the truncated problem then holds no copy of it in the strip, and
/// without the skip its place would go to a duplicate of a lower mode.
fn floquet_exponents(values: &mut [(f64, f64)], count: usize, frequency: f64) -> Vec<(f64, f64)> {
    values.sort_by(|a, b| a.1.abs().total_cmp(&b.1.abs()));
    // Copies differ by the truncation error of the outer harmonics, a small fraction of w
    // (measured 2e-5 w on the reference rotor at H = 3); distinct exponents closer than
    // 1e-3 w are merged, which at worst hides a duplicate of an exponent already listed.
    let tolerance = 1e-3 * frequency;
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(count);
    for &(re, im) in values.iter() {
        let folded = im - frequency * (im / frequency).round();
        let repeated = kept.iter().any(|&(r, i)| {
            let d = (folded - i).abs();
            (re - r).abs() <= tolerance && d.min(frequency - d) <= tolerance
        });
        if !repeated {
            kept.push((re, folded));
            if kept.len() == count {
                break;
            }
        }
    }
    kept
}

/// blockdiag(M^-1) over the 2H + 1 slots.
fn block_inverse_mass(hb: &HarmonicBalance, size: usize) -> Result<Mat<f64>> {
    let mass = &hb.problem().matrices.mass;
    let n = mass.nrows();
    let mut inverse = Mat::<f64>::identity(n, n);
    faer::linalg::solvers::Solve::solve_in_place(&mass.partial_piv_lu(), inverse.as_mut());
    if (0..n).any(|i| (0..n).any(|j| !inverse[(i, j)].is_finite())) {
        return Err(Error::singular(
            "mass matrix",
            "Hill's method needs a nonsingular mass matrix".into(),
        ));
    }
    Ok(block_diagonal(&inverse, size))
}

/// The n x n matrix `a` repeated along the diagonal of a size x size matrix.
fn block_diagonal(a: &Mat<f64>, size: usize) -> Mat<f64> {
    let n = a.nrows();
    Mat::from_fn(size, size, |i, j| {
        if i / n == j / n {
            a[(i % n, j % n)]
        } else {
            0.0
        }
    })
}

/// The eigenvalues of Hill's matrix `a` by faer's Hessenberg reduction and multishift QR
/// with aggressive early deflation, with a smaller shift count and deflation window than
/// faer picks for 150 to 590 rows ([`hill_shift_count`]).
fn eigenvalues(a: &Mat<f64>) -> std::result::Result<Vec<(f64, f64)>, evd::EvdError> {
    let n = a.nrows();
    let mut params: Spec<evd::EvdParams, f64> = Default::default();
    params.schur.recommended_shift_count = hill_shift_count;
    params.schur.recommended_deflation_window = hill_deflation_window;
    let mut re = Diag::<f64>::zeros(n);
    let mut im = Diag::<f64>::zeros(n);
    let par = faer::get_global_parallelism();
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

/// Shifts per multishift QR sweep: 12, faer's choice for 60 to 150 rows, up to 590 rows
/// (Hill's matrix of the reference rotor, H = 5, has 176), where faer takes 32 with a
/// deflation window of n / log2 n (23). On the reference rotor's 1-750 Hz sweep with
/// stability the smaller pair cut the CPU time of the whole sweep by a sixth (21.2 to
/// 17.9 s): with the larger window, reordering the Schur form in the aggressive early
/// deflation took 13 % of it. The eigenvalues are the same to round-off, the QR converging
/// to working precision either way. Above 590 rows faer's values for 590 to 3000 rows.
extern "C" fn hill_shift_count(dimension: usize, _active_block: usize) -> usize {
    if dimension < 590 {
        12
    } else {
        64
    }
}

/// The deflation window going with [`hill_shift_count`].
extern "C" fn hill_deflation_window(dimension: usize, _active_block: usize) -> usize {
    if dimension < 590 {
        10
    } else {
        96
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::SystemMatrices;
    use crate::hbm::HbOptions;
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
        let stability = hill_stability(&mut hb, &solution.coefficients, w).unwrap();

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
            // Two eigen-solves of well-conditioned matrices with entries up to (H w)^2.
            assert!(nearest < 1e-10, "eigenvalue {re} + {im} i: {nearest:e}");
        }
        assert!(stability.stable);
    }
}
