//! The [`System`] of a model: assembled, optionally Craig-Bampton reduced, loaded with
//! gravity and unbalance, and given its nonlinear (contact) forces in the reduced
//! coordinates.

use super::System;
use crate::error::{Error, Result};
use crate::fe::{
    assemble_banded, gravity_force, unbalance_force, BandedSystem, Bearings, DofNames,
    SystemMatrices, MAX_DENSE_DOFS,
};
use crate::force::{ForceBuilder, NonlinearForce};
use crate::linalg::dot;
use crate::model::Model;
use crate::reduce::{boundary_dofs, CraigBampton};
use crate::squeeze_film::squeeze_film_forces;

/// A model's system and how its coordinates map to physical DOFs.
pub struct Built {
    /// The system in the solver's coordinates.
    pub system: System,
    /// The map between those coordinates and the physical DOFs.
    pub coordinates: Coordinates,
}

/// The solver's coordinates: the physical DOFs, or a Craig-Bampton reduction's.
#[derive(Clone)]
pub struct Coordinates {
    /// The reduction, `None` for the full model.
    pub reduction: Option<CraigBampton>,
    /// The physical DOFs' names (`n10.uy`, `<housing>.ux`).
    names: DofNames,
}

/// The error for a full model above [`MAX_DENSE_DOFS`]: its solvers (the static start, the
/// stability limit, the integrators' starting acceleration, harmonic balance) hold its four
/// matrices dense; larger models are marched reduced, whose cost is linear in the DOFs.
fn full_model_too_large(dofs: usize) -> Error {
    crate::fe::too_large_for_dense(
        dofs,
        "Reduce it (Craig-Bampton, e.g. `--reduce 12`, whose cost grows linearly with the \
         elements) or use fewer elements",
    )
}

/// Builds the system of `model`: full (`reduction` `None`) or Craig-Bampton reduced with
/// that many fixed-interface modes (the bearing nodes are the boundary), `bearings` saying
/// whether the roller bearings' linear stiffness is in the matrices, and the nonlinear
/// forces from `forces`, which receives the map from physical DOFs to the coordinates.
///
/// # Errors
/// Those of [`linear`], of `forces`, and of [`System::check`] ([`Error::InvalidOption`] for
/// a force on a coordinate outside the system).
pub fn build(
    model: &Model,
    reduction: Option<usize>,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<Built> {
    linear(model, reduction, bearings)?.into_built(model, forces)
}

/// The linear part of a model's [`System`]: its matrices and loads in the solver's
/// coordinates, before the nonlinear forces (which keep state, so each run makes its own).
/// Neither the reduction nor the loads depend on the spin speed (the gyroscopic matrix is
/// reduced once and scaled by the speed in the solvers), so runs of one model at many
/// speeds (a cascade's) share one.
#[derive(Clone)]
pub struct Linear {
    reduction: Option<usize>,
    bearings: Bearings,
    matrices: SystemMatrices,
    /// Gravity, the unbalance phasor's real and imaginary parts, in the coordinates.
    loads: [Vec<f64>; 3],
    coordinates: Coordinates,
}

/// Assembles `model` and reduces it as [`build`] does (`reduction`, `bearings`), without
/// the nonlinear forces.
///
/// # Errors
/// [`Error::Unsupported`] for a full model above [`MAX_DENSE_DOFS`]; those of
/// [`CraigBampton::new`] with `reduction`.
pub fn linear(model: &Model, reduction: Option<usize>, bearings: Bearings) -> Result<Linear> {
    let dofs = model.dof_count();
    if reduction.is_none() && dofs > MAX_DENSE_DOFS {
        return Err(full_model_too_large(dofs));
    }
    // Banded: a reduction never needs the full model's dense matrices. The solvers built
    // here take the squeeze-film dampers' own nonlinear force (added with the forces),
    // whatever the bearings: the matrices leave the films out.
    let full = assemble_banded(&without_films(model), bearings);
    let gravity = gravity_force(model, &full);
    let unbalance = unbalance_force(model, full.dofs());
    let ub_re: Vec<f64> = unbalance.iter().map(|c| c.re).collect();
    let ub_im: Vec<f64> = unbalance.iter().map(|c| c.im).collect();
    let (matrices, coordinates) = match reduction {
        None => (
            full.to_dense(),
            Coordinates {
                reduction: None,
                names: DofNames::of(model),
            },
        ),
        Some(modes) => {
            let cb = CraigBampton::new(&full, &boundary_dofs(model, &[]), modes)?;
            // The reduction keeps its own copy (its size is the few reduced coordinates)
            // for what reports on it; the solver owns this one.
            let reduced = cb.reduced.clone();
            (
                reduced,
                Coordinates {
                    reduction: Some(cb),
                    names: DofNames::of(model),
                },
            )
        }
    };
    Ok(Linear {
        reduction,
        bearings,
        matrices,
        loads: [&gravity, &ub_re, &ub_im].map(|f| coordinates.vector(f)),
        coordinates,
    })
}

/// The nonlinear forces of `model` in the coordinates `map` gives: those of `forces` and
/// the squeeze-film dampers' (which the matrices leave out).
fn nonlinear_forces(
    model: &Model,
    map: &dyn Fn(usize) -> Option<usize>,
    forces: ForceBuilder<'_>,
) -> Result<Vec<Box<dyn NonlinearForce>>> {
    let mut nonlinear = forces(model, map)?;
    nonlinear.extend(squeeze_film_forces(model, map)?);
    Ok(nonlinear)
}

/// The full model as [`build`] makes it unreduced, but on its bands: for the solvers that
/// work on bands (the static response), whose memory then grows linearly with the
/// elements at any mesh.
pub(crate) struct BandedModel {
    /// M, K, G and C without the squeeze films, as [`linear`] assembles them.
    pub(crate) matrices: BandedSystem,
    /// Gravity, N.
    pub(crate) constant_force: Vec<f64>,
    /// The nonlinear forces, on the physical DOFs.
    pub(crate) nonlinear: Vec<Box<dyn NonlinearForce>>,
}

/// [`build`] of the full model (`bearings`, `forces`) on its bands.
///
/// # Errors
/// Those of `forces`.
pub(crate) fn banded(
    model: &Model,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<BandedModel> {
    let matrices = assemble_banded(&without_films(model), bearings);
    let constant_force = gravity_force(model, &matrices);
    let nonlinear = nonlinear_forces(model, &Some, forces)?;
    Ok(BandedModel {
        matrices,
        constant_force,
        nonlinear,
    })
}

/// `model` without its squeeze-film dampers (borrowed when it has none): the matrices of
/// the nonlinear solvers, which take the films' force apart.
fn without_films(model: &Model) -> std::borrow::Cow<'_, Model> {
    if model.housings.iter().all(|h| h.squeeze_film.is_none()) {
        return std::borrow::Cow::Borrowed(model);
    }
    let mut bare = model.clone();
    for h in &mut bare.housings {
        h.squeeze_film = None;
    }
    std::borrow::Cow::Owned(bare)
}

impl Linear {
    /// Whether this is the linear part [`build`] would make with `reduction` and `bearings`.
    pub fn is_built_with(&self, reduction: Option<usize>, bearings: Bearings) -> bool {
        self.reduction == reduction && self.bearings == bearings
    }

    /// The whole system, with the nonlinear forces from `forces` (see [`build`]), keeping
    /// this linear part for other runs.
    ///
    /// # Errors
    /// Those of `forces` and of [`System::check`].
    pub fn with_forces(&self, model: &Model, forces: ForceBuilder<'_>) -> Result<Built> {
        self.clone().into_built(model, forces)
    }

    fn into_built(self, model: &Model, forces: ForceBuilder<'_>) -> Result<Built> {
        let Linear {
            matrices,
            loads: [constant_force, unbalance_re, unbalance_im],
            coordinates,
            ..
        } = self;
        let map = |physical: usize| coordinates.coordinate_of(physical);
        let nonlinear = nonlinear_forces(model, &map, forces)?;
        let system = System {
            constant_force,
            unbalance_re,
            unbalance_im,
            nonlinear,
            ..System::unloaded(matrices)
        };
        system.check()?;
        Ok(Built {
            system,
            coordinates,
        })
    }
}

impl Coordinates {
    /// The coordinate of physical DOF `physical`, when it is one (always unreduced; a
    /// boundary DOF of a reduction).
    pub fn coordinate_of(&self, physical: usize) -> Option<usize> {
        match &self.reduction {
            None => Some(physical),
            Some(cb) => cb.reduced_index(physical),
        }
    }

    /// A physical force vector in the coordinates (Psi^T f when reduced).
    pub fn vector(&self, physical: &[f64]) -> Vec<f64> {
        match &self.reduction {
            None => physical.to_vec(),
            Some(cb) => cb.reduce_vector(physical),
        }
    }

    /// The row that recovers physical DOF `physical`: one entry unreduced, every coordinate
    /// of a reduction (whose rows are nearly full: the boundary's few and every
    /// fixed-interface mode).
    pub(crate) fn recovery_row(&self, physical: usize) -> RecoveryRow {
        match &self.reduction {
            None => RecoveryRow::Entries(vec![(physical, 1.0)]),
            Some(cb) => RecoveryRow::Full(cb.recovery_row(physical)),
        }
    }

    /// What coordinate `c` is: a DOF (`n7.tx`) or a fixed-interface mode.
    pub fn coordinate_name(&self, c: usize) -> String {
        match &self.reduction {
            None => self.names.name(c),
            Some(cb) if c < cb.boundary.len() => self.names.name(cb.boundary[c]),
            Some(cb) => format!(
                "the amplitude of fixed-interface mode {} of the reduction",
                c - cb.boundary.len() + 1
            ),
        }
    }
}

/// A physical DOF as a combination of coordinates: its nonzero entries (unreduced: one), or
/// the full row of a reduction.
pub(crate) enum RecoveryRow {
    Entries(Vec<(usize, f64)>),
    Full(Vec<f64>),
}

impl RecoveryRow {
    /// The physical DOF's value at coordinates `q`. A full row in the eight partial sums of
    /// [`dot`]: one running sum was a chain of dependent additions (4 % of a cascade, which
    /// recovers its channels at every sample).
    pub(crate) fn dot(&self, q: &[f64]) -> f64 {
        match self {
            RecoveryRow::Entries(entries) => entries.iter().map(|&(j, a)| a * q[j]).sum(),
            RecoveryRow::Full(row) => dot(row, q),
        }
    }

    /// The row of this DOF minus `other`'s (a relative displacement).
    pub(crate) fn minus(self, other: &RecoveryRow) -> RecoveryRow {
        match (self, other) {
            (RecoveryRow::Entries(mut entries), RecoveryRow::Entries(o)) => {
                entries.extend(o.iter().map(|&(j, a)| (j, -a)));
                RecoveryRow::Entries(entries)
            }
            (RecoveryRow::Full(mut row), other) => {
                other.add_to(-1.0, &mut row);
                RecoveryRow::Full(row)
            }
            (RecoveryRow::Entries(entries), RecoveryRow::Full(o)) => {
                let mut row: Vec<f64> = o.iter().map(|a| -a).collect();
                RecoveryRow::Entries(entries).add_to(1.0, &mut row);
                RecoveryRow::Full(row)
            }
        }
    }

    /// row += factor * self.
    fn add_to(&self, factor: f64, row: &mut [f64]) {
        match self {
            RecoveryRow::Entries(entries) => {
                entries.iter().for_each(|&(j, a)| row[j] += factor * a)
            }
            RecoveryRow::Full(full) => row.iter_mut().zip(full).for_each(|(r, a)| *r += factor * a),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{dof, Direction};
    use crate::force::no_forces;

    #[test]
    fn a_full_model_too_large_to_hold_dense_is_refused_before_assembly() {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None)
            .unwrap()
            .remeshed(&[1000])
            .unwrap();
        match build(&model, None, Bearings::Linearised, &no_forces) {
            Err(Error::Unsupported(m)) => {
                assert!(m.contains("4004 DOFs") && m.contains("--reduce"), "{m}");
                assert!(!m.contains("  "), "{m}");
            }
            other => panic!("expected a refusal, got {:?}", other.err()),
        }
        // Reduced, the same model is built.
        let reduced = build(&model, Some(12), Bearings::Linearised, &no_forces).unwrap();
        assert_eq!(reduced.system.size(), 8 + 12);
    }

    #[test]
    fn coordinates_are_named_by_dof_or_mode() {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        let full = build(&model, None, Bearings::Linearised, &no_forces).unwrap();
        assert_eq!(
            full.coordinates.coordinate_name(dof(10, Direction::Uy)),
            "n10.uy"
        );
        let reduced = build(&model, Some(4), Bearings::Linearised, &no_forces).unwrap();
        let names = &reduced.coordinates;
        // Boundary: every DOF of nodes 0 and 20, then the modes.
        assert_eq!(names.coordinate_name(2), "n0.tx");
        assert_eq!(names.coordinate_name(4), "n20.ux");
        assert_eq!(
            names.coordinate_name(8),
            "the amplitude of fixed-interface mode 1 of the reduction"
        );
    }
}
