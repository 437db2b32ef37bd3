//! Craig-Bampton reduction (thesis 2.3, docs/theory.md section 4).
//!
//! DOFs split into boundary B (every DOF of the bearing nodes, plus nodes the user marks)
//! and internal I. The internal DOFs are described by static constraint modes and the N
//! lowest fixed-interface modes (thesis eqs. 2.32-2.41):
//!
//! ```text
//! q = Psi u,   Psi = [ I      0    ]   u = (q_B, eta)
//!                    [ Phi_c  Phi_N ]
//! Phi_c = -K_II^-1 K_IB,   K_II phi = w^2 M_II phi  (N lowest, M_II-normalised)
//! ```
//!
//! M, K, G and C are all reduced as Psi^T X Psi. The thesis reduces only M and K and
//! rebuilds damping as alpha M~ + beta K~ (eq. 2.42); that forgets the gyroscopic matrix
//! and mixes the bearings' stiffness into the rotor's Rayleigh damping, so whirl projects
//! each matrix instead. Boundary DOFs stay physical, so bearing forces act on the reduced
//! model directly.
//!
//! [`reduction_report`] compares a reduced model with the full one, as `whirl reduce` does.

mod report;

pub use report::{reduction_report, ReductionReport, ReductionSummary, StudyRow};

/// Default number of fixed-interface modes of the Craig-Bampton model of a run: 12 modes
/// keep the reference rotor's frequencies below 1 kHz within 0.1 % and raise the stable
/// step tenfold (`whirl reduce`).
pub const DEFAULT_MODES: usize = 12;

use faer::Mat;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::fe::{dof, BandedSystem, Direction, Matrices, SystemMatrices, DOFS_PER_NODE};
use crate::linalg::banded::BandedLu;
use crate::linalg::Band;
use crate::modal::{largest_eigenvalue, lowest_modes, solves_dense, symmetric_modes};
use crate::model::Model;
use crate::progress::{map_told, Progress};

/// A Craig-Bampton reduced model and the map back to physical DOFs.
#[derive(Debug, Clone)]
pub struct CraigBampton {
    /// Boundary DOFs (physical indices); reduced coordinate `i < boundary.len()` is `boundary[i]`.
    pub boundary: Vec<usize>,
    /// Number of fixed-interface modes kept.
    pub modes: usize,
    /// Psi: physical DOFs x reduced coordinates.
    pub transform: Mat<f64>,
    /// Reduced M, K, G, C.
    pub reduced: SystemMatrices,
    /// Natural frequencies of the fixed-interface modes kept, Hz.
    pub fixed_interface_hz: Vec<f64>,
}

/// All DOFs of the bearing nodes plus those of `extra_nodes`, then every housing's DOFs
/// (a housing is joined to the shaft only through bearings, whose forces act there),
/// ascending.
pub fn boundary_dofs(model: &Model, extra_nodes: &[usize]) -> Vec<usize> {
    let mut nodes = model.bearing_nodes();
    nodes.extend_from_slice(extra_nodes);
    nodes.sort_unstable();
    nodes.dedup();
    nodes
        .iter()
        .flat_map(|&n| Direction::ALL.map(|d| dof(n, d)))
        .chain((0..model.housings.len()).flat_map(|h| model.housing_dofs(h)))
        .collect()
}

fn sub(a: &Mat<f64>, rows: &[usize], cols: &[usize]) -> Mat<f64> {
    Mat::from_fn(rows.len(), cols.len(), |i, j| a[(rows[i], cols[j])])
}

/// The internal part of a reduction's basis: the constraint modes K_II^-1 K_IB (internal x
/// boundary, the sign not yet applied) and the fixed-interface modes with their w^2.
struct InternalModes {
    constraint: Mat<f64>,
    omega_squared: Vec<f64>,
    fixed_interface: Mat<f64>,
}

fn singular_internal_stiffness() -> Error {
    Error::singular(
        "internal stiffness K_II",
        "the internal stiffness K_II is singular: part of the shaft is not held by any \
         boundary node (mark a node there as boundary)"
            .into(),
    )
}

/// The internal modes from the dense matrices: an LU of K_II and every fixed-interface mode
/// of the dense solver, for the small models it is chosen for ([`crate::modal::solves_dense`]).
fn dense_internal_modes(
    system: &SystemMatrices,
    boundary: &[usize],
    internal: &[usize],
    modes: usize,
) -> Result<InternalModes> {
    let k_ii = sub(&system.stiffness, internal, internal);
    let mut constraint = sub(&system.stiffness, internal, boundary);
    let lu = k_ii.partial_piv_lu();
    faer::linalg::solvers::Solve::solve_in_place(&lu, constraint.as_mut());
    if constraint
        .col_iter()
        .any(|c| c.iter().any(|v| !v.is_finite()))
    {
        return Err(singular_internal_stiffness());
    }
    let (omega_squared, fixed_interface) = if modes > 0 {
        let m_ii = sub(&system.mass, internal, internal);
        symmetric_modes(&k_ii, &m_ii, modes)?
    } else {
        (Vec::new(), Mat::zeros(internal.len(), 0))
    };
    Ok(InternalModes {
        constraint,
        omega_squared,
        fixed_interface,
    })
}

/// The internal modes from the bands: K_II and M_II keep the band (removing whole rows and
/// columns only brings entries closer to the diagonal), so the constraint modes take a
/// band LU and the fixed-interface modes subspace iteration, both linear in the DOF count.
fn banded_internal_modes(
    system: &BandedSystem,
    boundary: &[usize],
    internal: &[usize],
    modes: usize,
) -> Result<InternalModes> {
    let (ni, nb) = (internal.len(), boundary.len());
    let within = |band: &Band| {
        let (lower, upper) = band.widths();
        Band::from_fn(ni, (lower, upper), |a, b| {
            band.get(internal[a], internal[b])
        })
    };
    let k_ii = within(&system.stiffness);
    let (lower, upper) = k_ii.widths();
    let lu = BandedLu::new(ni, lower, upper, |a, b| k_ii.get(a, b))
        .ok_or_else(singular_internal_stiffness)?;
    // K_IB row by row, as the band LU's solve takes its right-hand sides.
    let mut rows: Vec<f64> = (0..ni * nb)
        .map(|k| system.stiffness.get(internal[k / nb], boundary[k % nb]))
        .collect();
    lu.solve_rows(&mut rows, nb);
    if rows.iter().any(|v| !v.is_finite()) {
        return Err(singular_internal_stiffness());
    }
    let (omega_squared, fixed_interface) = if modes > 0 {
        lowest_modes(&k_ii, &within(&system.mass), modes, None)?
    } else {
        (Vec::new(), Mat::zeros(ni, 0))
    };
    Ok(InternalModes {
        constraint: Mat::from_fn(ni, nb, |a, j| rows[a * nb + j]),
        omega_squared,
        fixed_interface,
    })
}

impl CraigBampton {
    /// Reduces `system` keeping `boundary` DOFs and `modes` fixed-interface modes, with the
    /// dense or the banded solvers by the model's size ([`crate::modal::solves_dense`]).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for a boundary DOF outside the model, [`Error::Unsupported`]
    /// without boundary DOFs, [`Error::Singular`] when part of the shaft is held by no boundary
    /// node; the errors of [`crate::modal::undamped_modes`] for the fixed-interface modes.
    pub fn new(system: &impl Matrices, boundary: &[usize], modes: usize) -> Result<CraigBampton> {
        let n = system.dofs();
        let mut is_boundary = vec![false; n];
        for &b in boundary {
            if b >= n {
                return Err(Error::InvalidOption(format!(
                    "boundary DOF {b} is outside the model ({n} DOFs)"
                )));
            }
            is_boundary[b] = true;
        }
        let boundary: Vec<usize> = (0..n).filter(|&i| is_boundary[i]).collect();
        let internal: Vec<usize> = (0..n).filter(|&i| !is_boundary[i]).collect();
        if boundary.is_empty() {
            return Err(Error::Unsupported(
                "Craig-Bampton needs boundary DOFs: the model has no bearing; mark nodes as boundary".into(),
            ));
        }
        let modes = modes.min(internal.len());
        let nb = boundary.len();
        let dense = solves_dense(n, modes);
        let found = if dense {
            dense_internal_modes(&system.dense(), &boundary, &internal, modes)?
        } else {
            banded_internal_modes(&system.banded(), &boundary, &internal, modes)?
        };

        let mut psi = Mat::<f64>::zeros(n, nb + modes);
        for (j, &b) in boundary.iter().enumerate() {
            psi[(b, j)] = 1.0;
            for (i, &r) in internal.iter().enumerate() {
                psi[(r, j)] = -found.constraint[(i, j)];
            }
        }
        for j in 0..modes {
            for (i, &r) in internal.iter().enumerate() {
                psi[(r, nb + j)] = found.fixed_interface[(i, j)];
            }
        }
        let reduced = if dense {
            let full = system.dense();
            let project = |a: &Mat<f64>| psi.transpose() * a * &psi;
            SystemMatrices {
                mass: project(&full.mass),
                stiffness: project(&full.stiffness),
                gyroscopic: project(&full.gyroscopic),
                damping: project(&full.damping),
            }
        } else {
            let full = system.banded();
            SystemMatrices {
                mass: full.mass.project(&psi),
                stiffness: full.stiffness.project(&psi),
                gyroscopic: full.gyroscopic.project(&psi),
                damping: full.damping.project(&psi),
            }
        };
        Ok(CraigBampton {
            boundary,
            modes,
            reduced,
            fixed_interface_hz: found
                .omega_squared
                .iter()
                .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
                .collect(),
            transform: psi,
        })
    }

    /// Number of reduced coordinates.
    pub fn size(&self) -> usize {
        self.transform.ncols()
    }

    /// Psi^T f: a physical force vector in reduced coordinates.
    pub fn reduce_vector(&self, f: &[f64]) -> Vec<f64> {
        (0..self.size())
            .map(|j| {
                f.iter()
                    .enumerate()
                    .map(|(i, fi)| fi * self.transform[(i, j)])
                    .sum()
            })
            .collect()
    }

    /// Row of Psi that recovers physical DOF `dof` from the reduced coordinates.
    pub fn recovery_row(&self, dof: usize) -> Vec<f64> {
        (0..self.size()).map(|j| self.transform[(dof, j)]).collect()
    }

    /// q = Psi u: every physical DOF from the reduced coordinates.
    pub fn recover(&self, u: &[f64]) -> Vec<f64> {
        (0..self.transform.nrows())
            .map(|i| {
                (0..self.size())
                    .map(|j| self.transform[(i, j)] * u[j])
                    .sum()
            })
            .collect()
    }

    /// Reduced coordinate of a boundary DOF.
    pub fn reduced_index(&self, dof: usize) -> Option<usize> {
        self.boundary.binary_search(&dof).ok()
    }

    /// Shaft nodes on the boundary (of a model with `shaft_nodes` nodes: the housings'
    /// DOFs follow theirs).
    pub fn boundary_nodes(&self, shaft_nodes: usize) -> Vec<usize> {
        let mut nodes: Vec<usize> = self
            .boundary
            .iter()
            .map(|d| d / DOFS_PER_NODE)
            .filter(|&n| n < shaft_nodes)
            .collect();
        nodes.dedup();
        nodes
    }
}

/// Largest stable step of the explicit central difference, 2 / w_max, with w_max the
/// highest undamped natural frequency of (K + extra, M), rad/s. `extra` adds a tangent
/// stiffness (e.g. of contacts) on the given DOFs.
///
/// # Errors
/// The errors of [`crate::modal::undamped_modes`]: [`Error::Singular`] for a mass that is
/// not positive definite, [`Error::NotConverged`] when the eigen-solver fails.
pub fn explicit_stability_limit(
    system: &SystemMatrices,
    extra: Option<(&[usize], &Mat<f64>)>,
) -> Result<f64> {
    let mut k = system.stiffness.clone();
    if let Some((dofs, kt)) = extra {
        for (a, &i) in dofs.iter().enumerate() {
            for (b, &j) in dofs.iter().enumerate() {
                k[(i, j)] += kt[(a, b)];
            }
        }
    }
    let n = system.dofs();
    let (omega2, _) = symmetric_modes(&k, &system.mass, n)?;
    let w_max = omega2.last().copied().unwrap_or(0.0).max(0.0).sqrt();
    Ok(if w_max > 0.0 {
        2.0 / w_max
    } else {
        f64::INFINITY
    })
}

/// Accuracy of a reduction: reduced against full frequencies and stability limits.
#[derive(Debug, Clone, Serialize)]
pub struct ReductionStudy {
    /// Full model: DOF count, natural frequencies (Hz) and stable step (s).
    pub full_dofs: usize,
    /// Natural frequencies of the full model, Hz.
    pub full_frequencies_hz: Vec<f64>,
    /// Explicit stability limit of the full model, s.
    pub full_stable_step: f64,
    /// Boundary DOF count.
    pub boundary_dofs: usize,
    /// One row per number of fixed-interface modes.
    pub rows: Vec<ReductionRow>,
}

/// One reduced model of a [`ReductionStudy`].
#[derive(Debug, Clone, Serialize)]
pub struct ReductionRow {
    /// Fixed-interface modes kept.
    pub modes: usize,
    /// Reduced coordinates.
    pub size: usize,
    /// Natural frequencies of the reduced model (as many as the full list compares), Hz.
    pub frequencies_hz: Vec<f64>,
    /// Relative error of each against the full model.
    pub relative_error: Vec<f64>,
    /// Explicit stability limit, s.
    pub stable_step: f64,
}

/// Compares reduced models with `mode_counts` fixed-interface modes against the full one on
/// the first `compare` natural frequencies (the reduced models in parallel, `progress` told
/// after each). The full model's frequencies and its highest one (for the stable step) come
/// from every mode of the dense solver for a small model; above
/// ([`crate::modal::solves_dense`]), the lowest by subspace iteration on the bands and the
/// highest by bisection on the inertia of the band factors, both linear in the DOF count.
///
/// # Errors
/// The errors of [`CraigBampton::new`] and [`explicit_stability_limit`];
/// [`Error::Interrupted`] when `progress` stopped it.
pub fn reduction_study(
    system: &impl Matrices,
    boundary: &[usize],
    mode_counts: &[usize],
    compare: usize,
    progress: Option<&Progress>,
) -> Result<ReductionStudy> {
    let n = system.dofs();
    let to_hz = |w2: &f64| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI);
    let (lowest, highest) = if solves_dense(n, compare) {
        let dense = system.dense();
        let (all, _) = symmetric_modes(&dense.stiffness, &dense.mass, n)?;
        let highest = all.last().copied().unwrap_or(0.0);
        (all, highest)
    } else {
        let banded = system.banded();
        let (lowest, _) = lowest_modes(&banded.stiffness, &banded.mass, compare, None)?;
        (lowest, largest_eigenvalue(&banded.stiffness, &banded.mass)?)
    };
    let full_frequencies_hz: Vec<f64> = lowest.iter().take(compare).map(to_hz).collect();
    let rows = map_told(
        mode_counts,
        progress,
        (0, mode_counts.len()),
        ("the reduction study", "reduced models"),
        |&m| {
            let cb = CraigBampton::new(system, boundary, m)?;
            let (red2, _) = symmetric_modes(&cb.reduced.stiffness, &cb.reduced.mass, cb.size())?;
            let frequencies_hz: Vec<f64> = red2.iter().take(compare).map(to_hz).collect();
            let relative_error = frequencies_hz
                .iter()
                .zip(&full_frequencies_hz)
                .map(|(r, f)| if *f > 0.0 { (r - f) / f } else { 0.0 })
                .collect();
            Ok(ReductionRow {
                modes: cb.modes,
                size: cb.size(),
                frequencies_hz,
                relative_error,
                stable_step: explicit_stability_limit(&cb.reduced, None)?,
            })
        },
    )?;
    Ok(ReductionStudy {
        full_dofs: n,
        full_stable_step: 2.0 / highest.max(1e-300).sqrt(),
        full_frequencies_hz,
        boundary_dofs: boundary.len(),
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{assemble_banded, Bearings};

    #[test]
    fn the_banded_reduction_equals_the_dense_one() {
        // 160 elements (644 DOFs): CraigBampton::new takes the banded path; both are run on
        // the same matrices here.
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .remeshed(&[160])
            .unwrap();
        let banded = assemble_banded(&model, Bearings::Linearised);
        let boundary = boundary_dofs(&model, &[]);
        let internal: Vec<usize> = (0..banded.dofs())
            .filter(|i| !boundary.contains(i))
            .collect();
        let fast = banded_internal_modes(&banded, &boundary, &internal, 12).unwrap();
        let dense = dense_internal_modes(&banded.to_dense(), &boundary, &internal, 12).unwrap();
        // Constraint modes: two solves of one well-posed system (K_II holds the shaft between
        // its clamped ends, condition ~1e8 at this mesh), so agreement to round-off times
        // that.
        let largest = dense.constraint.norm_max();
        let difference = (&fast.constraint - &dense.constraint).norm_max();
        assert!(difference <= 1e-8 * largest, "{difference} of {largest}");
        // Fixed-interface modes: the dense solver's error is round-off of the largest
        // eigenvalue, eps lambda_max in lambda (see the undamped modes' test); the
        // iteration's is far below.
        let dense_ii = banded.to_dense();
        let k_ii = sub(&dense_ii.stiffness, &internal, &internal);
        let m_ii = sub(&dense_ii.mass, &internal, &internal);
        let (all, _) = symmetric_modes(&k_ii, &m_ii, internal.len()).unwrap();
        let largest = all[all.len() - 1];
        for (a, b) in fast.omega_squared.iter().zip(&dense.omega_squared) {
            assert!((a - b).abs() <= f64::EPSILON * largest, "{a} vs {b}");
        }
        let cb = CraigBampton::new(&banded, &boundary, 12).unwrap();
        assert_eq!(cb.size(), boundary.len() + 12);
    }
}
