//! Finite-element model of the rotor: element matrices, DOF numbering and assembly.
//!
//! Shaft elements follow Euler-Bernoulli ([`beam`], the default) or Timoshenko
//! ([`timoshenko`], shear deformation) beam theory, chosen per section.
//!
//! Equation of motion (thesis eq. 2.4, docs/theory.md section 1):
//! `M q'' + (Omega G + C) q' + K q = F_lin(t) + F_nl(q, q', t)`.
//!
//! Global DOF numbering: four DOFs per node, node by node from z = 0:
//! `q[4 n + 0] = ux`, `q[4 n + 1] = uy`, `q[4 n + 2] = tx`, `q[4 n + 3] = ty` with
//! `ty = d(ux)/dz`, `tx = -d(uy)/dz`. Results files name DOFs `n<node>.<dir>` (e.g.
//! `n10.uy`), never by raw index alone.

mod assembly;
pub mod beam;
pub mod timoshenko;

pub(crate) use assembly::stiffness_product;
pub use assembly::{
    assemble, assemble_banded, assemble_dense, band_reach, element_forces, element_matrices,
    gravity_force, too_large_for_dense, unbalance_force, BandedSystem, Bearings, Matrices,
    SystemMatrices, HALF_BANDWIDTH, MAX_DENSE_DOFS,
};

use serde::Serialize;

use crate::model::Model;

/// The four DOFs of a node.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Direction {
    /// Translation along x (horizontal).
    Ux = 0,
    /// Translation along y (vertical, up).
    Uy = 1,
    /// Rotation about x: -d(uy)/dz.
    Tx = 2,
    /// Rotation about y: d(ux)/dz.
    Ty = 3,
}

impl Direction {
    /// All four, in DOF order.
    pub const ALL: [Direction; 4] = [Direction::Ux, Direction::Uy, Direction::Tx, Direction::Ty];

    /// Short name used in results files.
    pub fn name(self) -> &'static str {
        match self {
            Direction::Ux => "ux",
            Direction::Uy => "uy",
            Direction::Tx => "tx",
            Direction::Ty => "ty",
        }
    }
}

/// DOFs per node (defined with the model, which numbers the housings' DOFs after the
/// shaft's).
pub use crate::model::DOFS_PER_NODE;

/// Global index of a node's DOF.
pub fn dof(node: usize, direction: Direction) -> usize {
    DOFS_PER_NODE * node + direction as usize
}

/// Name of a global DOF, `n<node>.<dir>`.
pub fn dof_name(index: usize) -> String {
    format!(
        "n{}.{}",
        index / DOFS_PER_NODE,
        Direction::ALL[index % DOFS_PER_NODE].name()
    )
}

/// The names of a model's DOFs: `n<node>.<dir>` on the shaft ([`crate::fe::dof_name`]),
/// `<housing>.ux` and `<housing>.uy` on the housings.
#[derive(Debug, Clone, PartialEq)]
pub struct DofNames {
    shaft_dofs: usize,
    housings: Vec<String>,
}

impl DofNames {
    /// The names of `model`'s DOFs.
    pub fn of(model: &Model) -> DofNames {
        DofNames {
            shaft_dofs: DOFS_PER_NODE * model.node_count(),
            housings: model.housings.iter().map(|h| h.name.clone()).collect(),
        }
    }

    /// The name of DOF `index`.
    pub fn name(&self, index: usize) -> String {
        match index.checked_sub(self.shaft_dofs) {
            Some(k) if k / 2 < self.housings.len() => {
                format!("{}.{}", self.housings[k / 2], ["ux", "uy"][k % 2])
            }
            _ => dof_name(index),
        }
    }
}
