//! Mesh convergence: natural frequencies versus the number of beam elements (thesis
//! fig. 2.8). Each section gets a share of the elements in proportion to its length (at
//! least one); a mesh on which a disk or bearing would not sit on a node is skipped and
//! reported, since moving a feature would change the rotor, not the mesh.

use serde::Serialize;

use super::undamped::undamped_modes;
use crate::error::Result;
use crate::fe::{assemble, Bearings};
use crate::model::Model;

/// Frequencies of the first modes for several meshes.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceResult {
    /// Total element counts that could be meshed, ascending.
    pub element_counts: Vec<usize>,
    /// `frequencies_hz[i][j]`: mode j on mesh i, Hz.
    pub frequencies_hz: Vec<Vec<f64>>,
    /// Relative change of each frequency from the previous mesh (0 for the first).
    pub relative_change: Vec<Vec<f64>>,
    /// Element counts left out because a feature would not sit on a node.
    pub skipped: Vec<usize>,
}

/// Elements per section for a total count, in proportion to the section lengths.
fn split(model: &Model, total: usize) -> Vec<usize> {
    let length = model.length();
    model
        .sections
        .iter()
        .map(|s| ((total as f64 * s.length / length).round() as usize).max(1))
        .collect()
}

/// Undamped frequencies of the first `modes` modes for each total element count.
///
/// # Errors
/// [`Error::InvalidOption`](crate::Error::InvalidOption) when a feature does not fall on
/// a node of a mesh (see [`Model::remeshed`]); the errors of [`undamped_modes`].
pub fn convergence(model: &Model, counts: &[usize], modes: usize) -> Result<ConvergenceResult> {
    let mut counts = counts.to_vec();
    counts.sort_unstable();
    counts.dedup();
    let mut out = ConvergenceResult {
        element_counts: Vec::new(),
        frequencies_hz: Vec::new(),
        relative_change: Vec::new(),
        skipped: Vec::new(),
    };
    for total in counts {
        let Ok(mesh) = model.remeshed(&split(model, total)) else {
            out.skipped.push(total);
            continue;
        };
        let system = assemble(&mesh, Bearings::Linearised);
        let f = undamped_modes(&system, modes)?.frequencies_hz;
        let change = match out.frequencies_hz.last() {
            Some(prev) => f
                .iter()
                .zip(prev)
                .map(|(a, b): (&f64, &f64)| if *b > 0.0 { (a - b).abs() / b } else { 0.0 })
                .collect(),
            None => vec![0.0; f.len()],
        };
        out.element_counts.push(total);
        out.frequencies_hz.push(f);
        out.relative_change.push(change);
    }
    Ok(out)
}
