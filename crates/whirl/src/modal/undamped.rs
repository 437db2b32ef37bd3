//! Undamped modes: K v = w^2 M v with M = L L^T (Cholesky), solved as the symmetric
//! problem (L^-1 K L^-T) y = w^2 y, v = L^-T y. This avoids a general QZ solve and gives
//! mass-normalised shapes (v^T M v = 1) directly.
//!
//! That dense solve computes every mode, at a cost of the cube of the DOF count; above
//! [`DENSE_LIMIT`] DOFs the modes asked for are found by shift-invert subspace iteration on
//! the banded matrices instead ([`super::subspace`]), at a cost that grows linearly.
//!
//! Cross-coupled bearings make K non-symmetric; the undamped problem uses its symmetric
//! part, and the cross-coupling enters the damped analysis ([`super::complex_modes`]).

use faer::{Mat, Side};
use serde::Serialize;

use crate::error::{Error, Result};
use crate::fe::Matrices;
use crate::linalg::Band;
use crate::progress::Progress;

/// Undamped natural frequencies and mass-normalised mode shapes.
#[derive(Debug, Clone, Serialize)]
pub struct UndampedModes {
    /// Natural frequencies, Hz, ascending.
    pub frequencies_hz: Vec<f64>,
    /// Mode shapes, one per column, mass-normalised; rows are global DOFs.
    #[serde(skip)]
    pub shapes: Mat<f64>,
}

impl UndampedModes {
    /// The `count` lowest of these modes.
    pub fn lowest(&self, count: usize) -> UndampedModes {
        let m = count.min(self.frequencies_hz.len());
        UndampedModes {
            frequencies_hz: self.frequencies_hz[..m].to_vec(),
            shapes: self.shapes.subcols(0, m).to_owned(),
        }
    }
}

/// The largest model, in DOFs, whose modes are always found by the dense solver (every
/// mode, n^3) rather than by subspace iteration on the bands (the modes asked for, linear in
/// n). The dense solver wins on small models, where the iteration's fixed cost (a few tens of
/// iterations on 2p + 8 vectors) is not yet paid back: both took about 2 ms for 6 modes at
/// 164 DOFs (40 elements), and at 324 DOFs the dense solve took 4 times as long
/// (BENCHMARKS.md).
pub const DENSE_LIMIT: usize = 200;

/// The one rule that picks the solver, for the undamped modes, the modal basis and the
/// Craig-Bampton reduction alike: dense for a model of at most [`DENSE_LIMIT`] DOFs, or when
/// `modes` is a quarter of the DOFs or more (the iteration's 2 `modes` vectors would then
/// cost as much as the dense solve); otherwise subspace iteration.
pub fn solves_dense(dofs: usize, modes: usize) -> bool {
    dofs <= DENSE_LIMIT || 4 * modes >= dofs
}

/// The error for a mass matrix that is not positive definite.
pub(super) fn mass_not_definite() -> Error {
    Error::singular(
        "mass matrix",
        "the mass matrix is not positive definite: every node needs mass; check for \
         zero-length or zero-density shaft sections"
            .into(),
    )
}

/// Cholesky factor L of the mass matrix, with a clear error when M is not positive definite.
fn mass_cholesky(mass: &Mat<f64>) -> Result<faer::linalg::solvers::Llt<f64>> {
    mass.llt(Side::Lower).map_err(|_| mass_not_definite())
}

/// The most negative w^2 taken as round-off of a rigid-body (0 Hz) mode, (rad/s)^2: a mode
/// growing as exp(t sqrt(-w^2)) this slowly (0.1 Hz) is neutral for any practical purpose.
const NEUTRAL_OMEGA_SQUARED: f64 =
    -(2.0 * std::f64::consts::PI * 0.1) * (2.0 * std::f64::consts::PI * 0.1);

/// The error of a structure whose stiffness is not positive at rest: a negative w^2 is a
/// static divergence (buckling), which a frequency of 0 Hz would hide. `lowest` is the
/// lowest w^2 when it is known, else only that it lies below [`NEUTRAL_OMEGA_SQUARED`].
fn unstable_at_rest(lowest: Option<f64>) -> Error {
    let mode = match lowest {
        Some(w2) => format!(
            "the lowest mode has w^2 = {w2:.4e} (rad/s)^2, a static divergence growing at \
             {:.4} 1/s",
            (-w2).sqrt()
        ),
        None => format!(
            "a mode has w^2 below {NEUTRAL_OMEGA_SQUARED:.4} (rad/s)^2, a static divergence"
        ),
    };
    Error::singular(
        "stiffness matrix",
        format!(
            "the rotor is unstable at rest: its stiffness is not positive ({mode}); a \
             compressive axial load above the buckling load or a negative bearing stiffness \
             does this: check elements.axial_load and the bearings' stiffnesses"
        ),
    )
}

/// Refuses a structure whose lowest w^2 is below [`NEUTRAL_OMEGA_SQUARED`].
fn stable_at_rest(omega_squared: &[f64]) -> Result<()> {
    match omega_squared.first() {
        Some(&w2) if w2 < NEUTRAL_OMEGA_SQUARED => Err(unstable_at_rest(Some(w2))),
        _ => Ok(()),
    }
}

/// The `count` lowest undamped modes (all when `count` exceeds the DOF count), by the dense
/// solver or by subspace iteration ([`solves_dense`]).
///
/// # Errors
/// [`Error::Singular`] when the mass is not positive definite, or the stiffness is not
/// positive semi-definite (the rotor is unstable at rest); [`Error::NotConverged`] when the
/// eigen-solver fails.
pub fn undamped_modes(system: &impl Matrices, count: usize) -> Result<UndampedModes> {
    undamped_modes_told(system, count, None)
}

/// [`undamped_modes`], telling `progress` after every iteration of the subspace solver (the
/// dense solver is one step of a second or less: nothing to tell).
///
/// # Errors
/// As [`undamped_modes`]; [`Error::Interrupted`] when `progress` stopped it.
pub(crate) fn undamped_modes_told(
    system: &impl Matrices,
    count: usize,
    progress: Option<&Progress>,
) -> Result<UndampedModes> {
    let (omega_squared, shapes) = if solves_dense(system.dofs(), count) {
        let dense = system.dense();
        let modes = symmetric_modes(&dense.stiffness, &dense.mass, count)?;
        stable_at_rest(&modes.0)?;
        modes
    } else {
        let banded = system.banded();
        lowest_modes(&banded.stiffness, &banded.mass, count, progress)?
    };
    let frequencies_hz = omega_squared
        .iter()
        .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    Ok(UndampedModes {
        frequencies_hz,
        shapes,
    })
}

/// The `count` lowest modes of K v = w^2 M v given as bands, by subspace iteration,
/// shifted to [`NEUTRAL_OMEGA_SQUARED`] so that the factorisation itself refuses a structure
/// unstable at rest.
pub(crate) fn lowest_modes(
    stiffness: &Band,
    mass: &Band,
    count: usize,
    progress: Option<&Progress>,
) -> Result<(Vec<f64>, Mat<f64>)> {
    let unstable = || unstable_at_rest(None);
    super::subspace::lowest_modes(
        stiffness,
        mass,
        count,
        NEUTRAL_OMEGA_SQUARED,
        unstable,
        progress,
    )
}

/// The `count` lowest eigenpairs of K v = w^2 M v (K symmetrised, M symmetric positive
/// definite) by the dense solver: w^2 ascending and M-orthonormal vectors as columns.
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{assemble_banded, Bearings};
    use crate::model::Model;

    /// The reference rotor meshed with `elements` elements.
    fn reference_rotor(elements: usize) -> Model {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        model.remeshed(&[elements]).unwrap()
    }

    /// The `count` lowest modes of `model` by subspace iteration (the model must be past the
    /// dense limit), checked against the dense solver on the same matrices; returns them with
    /// the dense mass and mode shapes.
    fn iterated_modes_equal_the_dense_ones(
        model: &Model,
        count: usize,
    ) -> (UndampedModes, Mat<f64>, Mat<f64>) {
        let banded = assemble_banded(model, Bearings::Linearised);
        assert!(!solves_dense(banded.dofs(), count));
        let fast = undamped_modes(&banded, count).unwrap();
        let dense = banded.to_dense();
        let n = dense.dofs();
        let (all, shapes) = symmetric_modes(&dense.stiffness, &dense.mass, n).unwrap();
        let largest = all[n - 1];
        for (j, (f, w2)) in fast.frequencies_hz.iter().zip(&all).enumerate() {
            let exact = w2.sqrt() / (2.0 * std::f64::consts::PI);
            // The dense solver works on L^-1 K L^-T, whose eigenvalues it finds to round-off
            // of its largest: a relative error of eps lambda_max / lambda_j in lambda_j
            // (lambda_max / lambda_1 = 2.5e8 at 160 elements: 5.5e-8); the iteration's own
            // error is far smaller (the square of its vectors' error, below 1e-9). So the two
            // agree to the dense solver's bound, halved for the frequency (measured: 1e-9 to
            // 6e-9 on the first pair, within 3e-12 to 2e-10 of the bound's 3e-8 to 1e-10 on
            // the next three).
            let bound = 0.5 * f64::EPSILON * largest / w2;
            let error = (f - exact).abs() / exact;
            assert!(error <= bound, "mode {j}: {f} vs {exact}");
        }
        (fast, dense.mass, shapes)
    }

    #[test]
    fn subspace_iteration_finds_the_dense_solvers_lowest_modes() {
        // 160 elements, 644 DOFs: past the dense limit, so undamped_modes iterates.
        let (fast, m, shapes) = iterated_modes_equal_the_dense_ones(&reference_rotor(160), 8);
        // The shapes span the same modes: each iterated shape lies in the span of the dense
        // pair it belongs to (isotropic bearings make every frequency double), M-orthonormal.
        for j in 0..8 {
            let pair = [j - j % 2, j - j % 2 + 1];
            let x = fast.shapes.col(j);
            let along: f64 = pair
                .iter()
                .map(|&k| {
                    let v = shapes.col(k);
                    (x.transpose() * &m * v).powi(2)
                })
                .sum();
            // |x|_M = 1 and the pair's components carry all of it, to the vectors' error.
            assert!((along - 1.0).abs() < 1e-8, "mode {j}: {along}");
        }
    }

    #[test]
    fn soft_bearings_with_nearly_rigid_modes_converge_on_the_bands() {
        // Bearings of 1e4 N/m make the rotor's first modes nearly rigid (3.8 Hz), their w^2
        // far below the largest wanted one's; round-off in the solves moved those small
        // values by more than 1e-11 of themselves, so a stall test relative to each value
        // never held and the iteration gave up after its 300 iterations (NotConverged).
        let mut model = reference_rotor(160);
        for b in &mut model.roller_bearings {
            b.linear_stiffness = 1e4;
        }
        iterated_modes_equal_the_dense_ones(&model, 12);
    }

    #[test]
    fn a_large_rotor_unstable_at_rest_is_refused_by_the_banded_solver() {
        // A compression 17 times the Euler buckling load of the pinned shaft (pi^2 E I / L^2
        // = 5.9e5 N) makes K indefinite.
        let mut model = reference_rotor(80);
        model.options.axial_load = -1e7;
        let banded = assemble_banded(&model, Bearings::Linearised);
        assert!(!solves_dense(banded.dofs(), 8));
        let error = undamped_modes(&banded, 6).unwrap_err().to_string();
        assert!(error.contains("unstable at rest"), "{error}");
    }
}
