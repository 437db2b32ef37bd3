//! Mesh convergence: natural frequencies versus the number of beam elements (thesis
//! fig. 2.8). Each section gets a share of the elements in proportion to its length (at
//! least one); a mesh on which a disk or bearing would not sit on a node is skipped and
//! reported, since moving a feature would change the rotor, not the mesh. A coarse mesh
//! has fewer modes than a fine one (4 DOFs per node, less the constrained ones): the modes
//! it lacks are NaN, so that every mesh has the same columns.

mod report;

pub use report::ConvergenceSummary;

use serde::Serialize;

use super::undamped::undamped_modes;
use crate::error::{InputError, Result};
use crate::fe::{assemble_banded, Bearings};
use crate::given::mode_count;
use crate::model::{Model, MAX_ELEMENTS};
use crate::progress::{map_told, Progress};

/// Frequencies of the first modes for several meshes.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceResult {
    /// Total element counts that could be meshed, ascending.
    pub element_counts: Vec<usize>,
    /// `frequencies_hz[i][j]`: mode j on mesh i, Hz; NaN where mesh i has fewer than
    /// j + 1 modes. Every row has the same length: the modes asked for, or as many as the
    /// mesh with the most modes has, if fewer.
    pub frequencies_hz: Vec<Vec<f64>>,
    /// Relative change of each frequency from the previous mesh (0 for the first; NaN
    /// where either mesh lacks the mode).
    pub relative_change: Vec<Vec<f64>>,
    /// Number of modes each mesh has, at most the number asked for.
    pub modes_found: Vec<usize>,
    /// Element counts left out because a feature would not sit on a node.
    pub skipped: Vec<usize>,
    /// The number of modes asked for.
    pub modes_requested: usize,
}

/// Checks one total element count of a study, before anything is meshed: from 1 to
/// [`MAX_ELEMENTS`], the most a model may have. Each mesh is assembled on bands, so memory
/// grows linearly with the elements (about 140 MB at 10,000 elements, 6 modes).
///
/// # Errors
/// [`crate::Error::Input`] naming `counts` otherwise.
pub fn check_element_count(count: usize) -> Result<()> {
    if (1..=MAX_ELEMENTS).contains(&count) {
        return Ok(());
    }
    Err(InputError::field(
        "counts",
        format!("{count} elements: a mesh of the convergence study has from 1 to {MAX_ELEMENTS}"),
    )
    .help("e.g. 2,4,...,40, or multiples of the model's own count")
    .into())
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

/// Relative change from `previous` to `current`: NaN when either is missing (NaN), 0 from
/// a zero frequency (a rigid-body mode stays at zero).
fn change(current: f64, previous: f64) -> f64 {
    if previous == 0.0 {
        0.0
    } else {
        (current - previous).abs() / previous
    }
}

/// Modes followed when none are asked for.
pub const DEFAULT_CONVERGENCE_MODES: usize = 6;

/// The element counts meshed when none are given: 2, 4, ..., 40.
pub fn default_element_counts() -> Vec<usize> {
    (1..=20).map(|i| 2 * i).collect()
}

/// Undamped frequencies of the first `modes` modes (`None` for
/// [`DEFAULT_CONVERGENCE_MODES`]) for each total element count (none for
/// [`default_element_counts`]; the meshes in parallel), telling `progress` after every mesh.
///
/// # Errors
/// Those of [`check_element_count`] for any count and an error naming `modes` for a count
/// of modes out of range, before anything is meshed; an error naming `counts` when no mesh
/// puts every feature on a node; then the errors of [`undamped_modes`];
/// [`Error::Interrupted`](crate::Error::Interrupted) when `progress` stopped it.
pub fn convergence(
    model: &Model,
    counts: &[usize],
    modes: Option<usize>,
    progress: Option<&Progress>,
) -> Result<ConvergenceResult> {
    let modes = mode_count("modes", modes.unwrap_or(DEFAULT_CONVERGENCE_MODES))?;
    counts.iter().try_for_each(|&n| check_element_count(n))?;
    let mut counts = match counts.is_empty() {
        true => default_element_counts(),
        false => counts.to_vec(),
    };
    counts.sort_unstable();
    counts.dedup();
    // Per mesh its frequencies, or None for a mesh that would move a feature off a node.
    let meshes = map_told(
        &counts,
        progress,
        (0, counts.len()),
        ("the mesh convergence", "meshes"),
        |&total| {
            let Ok(mesh) = model.remeshed(&split(model, total)) else {
                return Ok(None);
            };
            let system = assemble_banded(&mesh, Bearings::Linearised);
            Ok(Some(undamped_modes(&system, modes)?.frequencies_hz))
        },
    )?;
    let mut out = ConvergenceResult {
        element_counts: Vec::new(),
        frequencies_hz: Vec::new(),
        relative_change: Vec::new(),
        modes_found: Vec::new(),
        skipped: Vec::new(),
        modes_requested: modes,
    };
    for (total, f) in counts.into_iter().zip(meshes) {
        let Some(mut f) = f else {
            out.skipped.push(total);
            continue;
        };
        out.modes_found.push(f.len());
        f.resize(modes, f64::NAN);
        let change = match out.frequencies_hz.last() {
            Some(prev) => f.iter().zip(prev).map(|(a, b)| change(*a, *b)).collect(),
            None => f
                .iter()
                .map(|a| if a.is_nan() { f64::NAN } else { 0.0 })
                .collect(),
        };
        out.element_counts.push(total);
        out.frequencies_hz.push(f);
        out.relative_change.push(change);
    }
    if out.element_counts.is_empty() {
        return Err(InputError::field(
            "counts",
            format!(
                "on none of the meshes {:?} do all disks, bearings and unbalances sit on a node",
                out.skipped
            ),
        )
        .help("choose element counts that put a node at every feature, e.g. multiples of the model's own count")
        .into());
    }
    // No column that no mesh can fill.
    let columns = out.modes_found.iter().copied().max().unwrap_or(0);
    for row in out
        .frequencies_hz
        .iter_mut()
        .chain(&mut out.relative_change)
    {
        row.truncate(columns);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn element_counts_outside_the_limit_are_refused_before_any_mesh() {
        let model = Model::from_toml_str(crate::examples::REFERENCE_ROTOR, None).unwrap();
        for bad in [0, MAX_ELEMENTS + 1, usize::MAX] {
            // A good count beside the bad one: the whole request is refused, none is meshed.
            let e = convergence(&model, &[20, bad], Some(2), None).unwrap_err();
            let text = e.to_string();
            assert!(
                text.starts_with(&format!("`counts`: {bad} elements"))
                    && text.contains(&format!("from 1 to {MAX_ELEMENTS}")),
                "{text}"
            );
        }
        // Both ends of the range are taken: 1 element (the mesh's nodes miss the disk, so it
        // is skipped) and the limit, which the reference rotor's features fall on.
        let r = convergence(&model, &[1, MAX_ELEMENTS], Some(1), None).unwrap();
        assert_eq!(r.skipped, vec![1]);
        assert_eq!(r.element_counts, vec![MAX_ELEMENTS]);
    }
}
