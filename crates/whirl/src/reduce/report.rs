//! What a Craig-Bampton reduction reports ([`crate::report`]): the reduced model's natural
//! frequencies against the full model's, and a study over the number of fixed-interface
//! modes, as `whirl reduce` writes them.

use serde::Serialize;

use super::{boundary_dofs, reduction_study, ReductionRow, ReductionStudy};
use crate::error::{Error, Result};
use crate::fe::{assemble_banded, Bearings, DofNames};
use crate::model::Model;
use crate::progress::Progress;
use crate::report::{Report, Table};

/// The study runs to at least this many fixed-interface modes.
const STUDY_MODES: usize = 24;

/// At least this many frequencies are compared (the first four show how the error falls).
const MIN_COMPARED: usize = 4;

/// A reduced model with a chosen number of fixed-interface modes, and the study around it.
#[derive(Debug, Clone)]
pub struct ReductionReport {
    /// The study over 1 to max(24, 2 x modes) fixed-interface modes.
    pub study: ReductionStudy,
    /// Names of the boundary DOFs, e.g. `n0.ux`.
    pub boundary: Vec<String>,
    /// Index in `study.rows` of the chosen reduced model.
    chosen: usize,
}

/// The key numbers of a [`ReductionReport`].
#[derive(Debug, Clone, Serialize)]
pub struct ReductionSummary {
    /// DOFs of the full model.
    pub full_dofs: usize,
    /// Names of the boundary DOFs.
    pub boundary_dofs: Vec<String>,
    /// Fixed-interface modes of the chosen model.
    pub fixed_interface_modes: usize,
    /// Its coordinates.
    pub reduced_coordinates: usize,
    /// Natural frequencies of the full model, Hz.
    pub full_frequencies_hz: Vec<f64>,
    /// Those of the chosen reduced model, Hz.
    pub reduced_frequencies_hz: Vec<f64>,
    /// Their relative errors.
    pub relative_errors: Vec<f64>,
    /// The largest relative error in magnitude.
    pub max_relative_error: f64,
    /// Stable step of the explicit central difference on the full model, s.
    pub full_stable_step_s: f64,
    /// The same on the chosen reduced model, s.
    pub reduced_stable_step_s: f64,
    /// Every reduced model of the study.
    pub study: Vec<StudyRow>,
    /// What the numbers are.
    pub notes: [&'static str; 2],
}

/// One reduced model of the study.
#[derive(Debug, Clone, Serialize)]
pub struct StudyRow {
    /// Fixed-interface modes.
    pub fixed_interface_modes: usize,
    /// Coordinates.
    pub coordinates: usize,
    /// Stable step of the explicit central difference, s.
    pub stable_step_s: f64,
    /// Relative errors of the natural frequencies.
    pub relative_errors: Vec<f64>,
}

/// Reduces `model` (linearised bearings) with every DOF of the bearing nodes and of
/// `extra_nodes` on the boundary and `modes` fixed-interface modes (`None` for
/// [`crate::reduce::DEFAULT_MODES`]; at most the internal
/// DOFs), and compares the undamped natural frequencies at rest, the first max(`modes`, 4),
/// with the full model's, for it and for 1 to max(24, 2 `modes`) modes; `progress` is told
/// after each reduced model of the study.
///
/// # Errors
/// [`Error::InvalidOption`] when every DOF is on the boundary; the errors of
/// [`reduction_study`].
pub fn reduction_report(
    model: &Model,
    modes: Option<usize>,
    extra_nodes: &[usize],
    progress: Option<&Progress>,
) -> Result<ReductionReport> {
    let modes = crate::given::mode_count("modes", modes.unwrap_or(crate::reduce::DEFAULT_MODES))?;
    let system = assemble_banded(model, Bearings::Linearised);
    let boundary = boundary_dofs(model, extra_nodes);
    let internal = system.dofs() - boundary.len();
    if internal == 0 {
        return Err(Error::InvalidOption(
            "every DOF is on the boundary: nothing is left to reduce; mark fewer nodes as \
             boundary"
                .into(),
        ));
    }
    // A reduced model cannot keep more modes than it has internal DOFs.
    let modes = modes.min(internal);
    let counts: Vec<usize> = (1..=STUDY_MODES.max(2 * modes).min(internal)).collect();
    let compared = modes.max(MIN_COMPARED).min(system.dofs());
    let study = reduction_study(&system, &boundary, &counts, compared, progress)?;
    let chosen = study
        .rows
        .iter()
        .position(|r| r.modes == modes)
        .ok_or_else(|| Error::InvalidOption(format!("the study has no row with {modes} modes")))?;
    Ok(ReductionReport {
        study,
        boundary: {
            let names = DofNames::of(model);
            boundary.iter().map(|&d| names.name(d)).collect()
        },
        chosen,
    })
}

impl ReductionReport {
    /// The chosen reduced model.
    pub fn chosen(&self) -> &ReductionRow {
        &self.study.rows[self.chosen]
    }

    /// How many natural frequencies are compared.
    fn compared(&self) -> usize {
        self.study.full_frequencies_hz.len()
    }
}

impl Report for ReductionReport {
    type Summary = ReductionSummary;

    fn summary(&self) -> ReductionSummary {
        let (study, chosen) = (&self.study, self.chosen());
        ReductionSummary {
            full_dofs: study.full_dofs,
            boundary_dofs: self.boundary.clone(),
            fixed_interface_modes: chosen.modes,
            reduced_coordinates: chosen.size,
            full_frequencies_hz: study.full_frequencies_hz.clone(),
            reduced_frequencies_hz: chosen.frequencies_hz.clone(),
            relative_errors: chosen.relative_error.clone(),
            max_relative_error: chosen
                .relative_error
                .iter()
                .map(|e| e.abs())
                .fold(0.0, f64::max),
            full_stable_step_s: study.full_stable_step,
            reduced_stable_step_s: chosen.stable_step,
            study: study
                .rows
                .iter()
                .map(|r| StudyRow {
                    fixed_interface_modes: r.modes,
                    coordinates: r.size,
                    stable_step_s: r.stable_step,
                    relative_errors: r.relative_error.clone(),
                })
                .collect(),
            notes: [
                "undamped natural frequencies at rest, linearised bearings",
                "stable step of the explicit central difference, 2 / w_max, without contact \
                 stiffness",
            ],
        }
    }

    /// `reduce` (mode, full and reduced frequency, relative error) and `study` (one row per
    /// mode count: coordinates, stable step, each mode's relative error).
    fn tables(&self) -> Vec<Table> {
        let (study, chosen) = (&self.study, self.chosen());
        let modes = 0..self.compared();
        let mut reduce = Table::new("reduce");
        reduce
            .counts("mode", modes.clone().map(|j| j + 1))
            .numbers(
                "full_frequency_hz",
                study.full_frequencies_hz.iter().copied(),
            )
            .optional(
                "reduced_frequency_hz",
                modes.clone().map(|j| chosen.frequencies_hz.get(j).copied()),
            )
            .optional(
                "relative_error",
                modes.map(|j| chosen.relative_error.get(j).copied()),
            );
        let rows = &study.rows;
        let mut table = Table::new("study");
        table
            .counts("fixed_interface_modes", rows.iter().map(|r| r.modes))
            .counts("coordinates", rows.iter().map(|r| r.size))
            .numbers("stable_step_s", rows.iter().map(|r| r.stable_step));
        for j in 0..self.compared() {
            table.optional(
                format!("mode{}_relative_error", j + 1),
                rows.iter().map(|r| r.relative_error.get(j).copied()),
            );
        }
        vec![reduce, table]
    }
}
