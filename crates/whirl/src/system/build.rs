//! The [`System`] of a model: assembled, optionally Craig-Bampton reduced, loaded with
//! gravity and unbalance, and given its nonlinear (contact) forces in the reduced
//! coordinates.

use super::System;
use crate::error::Result;
use crate::fe::{assemble_banded, dof_name, gravity_force, unbalance_force, Bearings};
use crate::force::ForceBuilder;
use crate::model::Model;
use crate::reduce::{boundary_dofs, CraigBampton};

/// A model's system and how its coordinates map to physical DOFs.
pub struct Built {
    /// The system in the solver's coordinates.
    pub system: System,
    /// The map between those coordinates and the physical DOFs.
    pub coordinates: Coordinates,
}

/// The solver's coordinates: the physical DOFs, or a Craig-Bampton reduction's.
pub struct Coordinates {
    /// The reduction, `None` for the full model.
    pub reduction: Option<CraigBampton>,
}

/// Builds the system of `model`: full (`reduction` `None`) or Craig-Bampton reduced with
/// that many fixed-interface modes (the bearing nodes are the boundary), `bearings` saying
/// whether the roller bearings' linear stiffness is in the matrices, and the nonlinear
/// forces from `forces`, which receives the map from physical DOFs to the coordinates.
///
/// # Errors
/// Those of [`CraigBampton::new`] with `reduction`, of `forces`, and of [`System::check`]
/// ([`crate::error::Error::InvalidOption`] for a force on a coordinate outside the system).
pub fn build(
    model: &Model,
    reduction: Option<usize>,
    bearings: Bearings,
    forces: ForceBuilder<'_>,
) -> Result<Built> {
    // Banded: a reduction never needs the full model's dense matrices.
    let full = assemble_banded(model, bearings);
    let gravity = gravity_force(model, &full);
    let unbalance = unbalance_force(model, full.dofs());
    let ub_re: Vec<f64> = unbalance.iter().map(|c| c.re).collect();
    let ub_im: Vec<f64> = unbalance.iter().map(|c| c.im).collect();
    let (matrices, coordinates) = match reduction {
        None => (full.to_dense(), Coordinates { reduction: None }),
        Some(modes) => {
            let cb = CraigBampton::new(&full, &boundary_dofs(model, &[]), modes)?;
            // The reduction keeps its own copy (its size is the few reduced coordinates)
            // for what reports on it; the solver owns this one.
            let reduced = cb.reduced.clone();
            (
                reduced,
                Coordinates {
                    reduction: Some(cb),
                },
            )
        }
    };
    let map = |physical: usize| coordinates.coordinate_of(physical);
    let nonlinear = forces(model, &map)?;
    let system = System {
        constant_force: coordinates.vector(&gravity),
        unbalance_re: coordinates.vector(&ub_re),
        unbalance_im: coordinates.vector(&ub_im),
        nonlinear,
        ..System::unloaded(matrices)
    };
    system.check()?;
    Ok(Built {
        system,
        coordinates,
    })
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

    /// The nonzero entries of the row that recovers physical DOF `physical`.
    pub(crate) fn recovery_row(&self, physical: usize) -> SparseRow {
        match &self.reduction {
            None => SparseRow(vec![(physical, 1.0)]),
            Some(cb) => SparseRow(
                cb.recovery_row(physical)
                    .into_iter()
                    .enumerate()
                    .filter(|(_, a)| *a != 0.0)
                    .collect(),
            ),
        }
    }

    /// What coordinate `c` is: a DOF (`n7.tx`) or a fixed-interface mode.
    pub fn coordinate_name(&self, c: usize) -> String {
        match &self.reduction {
            None => dof_name(c),
            Some(cb) if c < cb.boundary.len() => dof_name(cb.boundary[c]),
            Some(cb) => format!(
                "the amplitude of fixed-interface mode {} of the reduction",
                c - cb.boundary.len() + 1
            ),
        }
    }
}

/// A physical DOF as a combination of coordinates (one entry unreduced).
pub(crate) struct SparseRow(Vec<(usize, f64)>);

impl SparseRow {
    /// The physical DOF's value at coordinates `q`.
    pub(crate) fn dot(&self, q: &[f64]) -> f64 {
        self.0.iter().map(|&(j, a)| a * q[j]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fe::{dof, Direction};
    use crate::force::no_forces;

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
