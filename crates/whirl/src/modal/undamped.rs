//! Undamped modes: K v = w^2 M v with M = L L^T (Cholesky), solved as the symmetric
//! problem (L^-1 K L^-T) y = w^2 y, v = L^-T y. This avoids a general QZ solve and gives
//! mass-normalised shapes (v^T M v = 1) directly.
//!
//! Cross-coupled bearings make K non-symmetric; the undamped problem uses its symmetric
//! part, and the cross-coupling enters the damped analysis ([`super::complex_modes`]).

use faer::{Mat, Side};
use serde::Serialize;

use crate::error::{Error, Result};
use crate::fe::SystemMatrices;

/// Undamped natural frequencies and mass-normalised mode shapes.
#[derive(Debug, Clone, Serialize)]
pub struct UndampedModes {
    /// Natural frequencies, Hz, ascending.
    pub frequencies_hz: Vec<f64>,
    /// Mode shapes, one per column, mass-normalised; rows are global DOFs.
    #[serde(skip)]
    pub shapes: Mat<f64>,
}

/// Cholesky factor L of the mass matrix, with a clear error when M is not positive definite.
fn mass_cholesky(mass: &Mat<f64>) -> Result<faer::linalg::solvers::Llt<f64>> {
    mass.llt(Side::Lower).map_err(|_| {
        Error::singular(
            "mass matrix",
            "the mass matrix is not positive definite: every node needs mass; check for \
             zero-length or zero-density shaft sections"
                .into(),
        )
    })
}

/// The most negative w^2 taken as round-off of a rigid-body (0 Hz) mode, (rad/s)^2: a mode
/// growing as exp(t sqrt(-w^2)) this slowly (0.1 Hz) is neutral for any practical purpose.
const NEUTRAL_OMEGA_SQUARED: f64 =
    -(2.0 * std::f64::consts::PI * 0.1) * (2.0 * std::f64::consts::PI * 0.1);

/// Refuses a structure whose stiffness is not positive at rest: a negative w^2 is a static
/// divergence (buckling), which a frequency of 0 Hz would hide.
fn stable_at_rest(omega_squared: &[f64]) -> Result<()> {
    match omega_squared.first() {
        Some(&w2) if w2 < NEUTRAL_OMEGA_SQUARED => Err(Error::singular(
            "stiffness matrix",
            format!(
            "the rotor is unstable at rest: its stiffness is not positive (the lowest mode has \
             w^2 = {w2:.4e} (rad/s)^2, a static divergence growing at {:.4} 1/s); a compressive \
             axial load above the buckling load or a negative bearing stiffness does this: check \
             elements.axial_load and the bearings' stiffnesses",
            (-w2).sqrt()
        ),
        )),
        _ => Ok(()),
    }
}

/// The `count` lowest undamped modes (all when `count` exceeds the DOF count).
///
/// # Errors
/// [`Error::Singular`] when the mass is not positive definite, or the stiffness is not
/// positive semi-definite (the rotor is unstable at rest).
pub fn undamped_modes(system: &SystemMatrices, count: usize) -> Result<UndampedModes> {
    let (omega_squared, shapes) = symmetric_modes(&system.stiffness, &system.mass, count)?;
    stable_at_rest(&omega_squared)?;
    let frequencies_hz = omega_squared
        .iter()
        .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    Ok(UndampedModes {
        frequencies_hz,
        shapes,
    })
}

/// The `count` lowest eigenpairs of K v = w^2 M v (K symmetrised, M symmetric positive
/// definite): w^2 ascending and M-orthonormal vectors as columns.
pub(crate) fn symmetric_modes(
    stiffness: &Mat<f64>,
    mass: &Mat<f64>,
    count: usize,
) -> Result<(Vec<f64>, Mat<f64>)> {
    let n = mass.nrows();
    let llt = mass_cholesky(mass)?;
    let l = llt.L();
    let k = stiffness;
    let mut a = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (k[(i, j)] + k[(j, i)]));
    // A = L^-1 K L^-T: two triangular solves, the second on the transpose.
    l.solve_lower_triangular_in_place(a.as_mut());
    let mut a = a.transpose().to_owned();
    l.solve_lower_triangular_in_place(a.as_mut());
    let a = Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (a[(i, j)] + a[(j, i)]));
    let (values, vectors) = symmetric_eigen(&a)?;
    let m = count.min(n);
    let mut shapes = Mat::<f64>::from_fn(n, m, |i, j| vectors[(i, j)]);
    l.transpose()
        .solve_upper_triangular_in_place(shapes.as_mut());
    Ok((values[..m].to_vec(), shapes))
}

/// Eigen-decomposition of a symmetric matrix, eigenvalues ascending.
///
/// faer's default switches to divide and conquer on the tridiagonal matrix from 128 rows
/// on, and for rotor matrices (exactly repeated eigenvalues from isotropy) that path
/// returned wrong values: the 40-element reference rotor gave its first pair as 49.815 /
/// 49.829 Hz instead of two equal values. The implicit QR path has no such threshold
/// and is fast enough at the sizes whirl meets (a few hundred DOFs).
fn symmetric_eigen(a: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>)> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::evd::{self, ComputeEigenvectors, SelfAdjointEvdParams};
    let n = a.nrows();
    let params = SelfAdjointEvdParams {
        recursion_threshold: usize::MAX,
        ..<SelfAdjointEvdParams as faer::Auto<f64>>::auto()
    };
    let par = faer::Par::Seq;
    let mut values = faer::diag::Diag::<f64>::zeros(n);
    let mut vectors = Mat::<f64>::zeros(n, n);
    let scratch =
        evd::self_adjoint_evd_scratch::<f64>(n, ComputeEigenvectors::Yes, par, params.into());
    evd::self_adjoint_evd(
        a.as_ref(),
        values.as_mut(),
        Some(vectors.as_mut()),
        par,
        MemStack::new(&mut MemBuffer::new(scratch)),
        params.into(),
    )
    .map_err(|_| {
        Error::not_converged(
            "symmetric eigen-solver",
            None,
            None,
            "the symmetric eigen-solver did not converge".into(),
        )
    })?;
    let values = (0..n).map(|j| values.column_vector()[j]).collect();
    Ok((values, vectors))
}
