//! What a mesh-convergence study reports ([`crate::report`]), as `whirl convergence`
//! writes it.

use serde::Serialize;

use super::ConvergenceResult;
use crate::report::{Report, Table};

/// The key numbers of a [`ConvergenceResult`].
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceSummary {
    /// Element counts meshed.
    pub element_counts: Vec<usize>,
    /// Modes asked for.
    pub modes_requested: usize,
    /// Modes each mesh has.
    pub modes_found: Vec<usize>,
    /// The meshes with fewer modes than asked for.
    pub meshes_with_fewer_modes: Vec<FewerModes>,
    /// Element counts left out (a feature would not sit on a node).
    pub skipped_element_counts: Vec<usize>,
    /// Frequencies per mesh and mode, Hz (null where a mesh lacks the mode).
    pub frequencies_hz: Vec<Vec<f64>>,
    /// Those of the finest mesh, Hz.
    pub finest_mesh_frequencies_hz: Option<Vec<f64>>,
    /// Their relative change from the mesh before.
    pub finest_mesh_relative_change: Option<Vec<f64>>,
}

/// A mesh with fewer modes than asked for.
#[derive(Debug, Clone, Serialize)]
pub struct FewerModes {
    /// Its element count.
    pub elements: usize,
    /// The modes it has.
    pub modes: usize,
}

impl ConvergenceResult {
    /// (element count, modes found) of each mesh with fewer modes than asked for.
    pub fn meshes_with_fewer_modes(&self) -> Vec<(usize, usize)> {
        self.element_counts
            .iter()
            .zip(&self.modes_found)
            .filter(|(_, &found)| found < self.modes_requested)
            .map(|(&n, &found)| (n, found))
            .collect()
    }
}

impl Report for ConvergenceResult {
    type Summary = ConvergenceSummary;

    fn summary(&self) -> ConvergenceSummary {
        ConvergenceSummary {
            element_counts: self.element_counts.clone(),
            modes_requested: self.modes_requested,
            modes_found: self.modes_found.clone(),
            meshes_with_fewer_modes: self
                .meshes_with_fewer_modes()
                .into_iter()
                .map(|(elements, modes)| FewerModes { elements, modes })
                .collect(),
            skipped_element_counts: self.skipped.clone(),
            frequencies_hz: self.frequencies_hz.clone(),
            finest_mesh_frequencies_hz: self.frequencies_hz.last().cloned(),
            finest_mesh_relative_change: self.relative_change.last().cloned(),
        }
    }

    /// `convergence`: per element count, each mode's frequency and its relative change
    /// from the previous mesh.
    fn tables(&self) -> Vec<Table> {
        let modes = self.frequencies_hz.first().map_or(0, |f| f.len());
        let mut t = Table::new("convergence");
        t.counts("elements", self.element_counts.iter().copied());
        for j in 0..modes {
            t.numbers(
                format!("mode{}_frequency_hz", j + 1),
                self.frequencies_hz.iter().map(|f| f[j]),
            );
        }
        for j in 0..modes {
            t.numbers(
                format!("mode{}_relative_change", j + 1),
                self.relative_change.iter().map(|c| c[j]),
            );
        }
        vec![t]
    }
}
