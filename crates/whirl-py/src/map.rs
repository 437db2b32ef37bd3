//! The NSV map (`whirl map`): one harmonic-balance sweep with stability per value of a model
//! parameter, its unstable bands and resonance lines, and the check against cascades. The
//! options arrive as the library's request takes them: `None` is the library's default.

use pyo3::prelude::*;
use whirl::hbm::{CageKind, CageModel, SweepSettings};
use whirl::map::{map_with, MapRequest, Parallelism};

use crate::error::to_py;
use crate::model::PyModel;
use crate::nsv::choice;
use crate::report::PyReport;
use crate::watch::{fraction_progress, run_watched};

/// The map's options from the Python package: speeds in rad/s, lengths in m, every
/// setting `None` for the library's default.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct MapArgs {
    parameter: Option<String>,
    values: Vec<String>,
    from: f64,
    to: f64,
    harmonics: Option<usize>,
    samples: Option<usize>,
    contact: Option<String>,
    cage: Option<String>,
    cage_positions: Option<usize>,
    contact_smoothing: Option<f64>,
    stability_modes: Option<usize>,
    reduce: Option<usize>,
    clear_below: Option<f64>,
    check: Vec<String>,
    check_level: Option<f64>,
    confirm: bool,
}

/// The library's request for `model` with these options.
fn request(model: &PyModel, a: MapArgs) -> PyResult<MapRequest> {
    let cage = match (&a.cage, a.cage_positions) {
        (None, None) => None,
        (kind, positions) => Some(CageModel::new(
            kind.as_deref()
                .map_or(Ok(CageKind::Passage), |c| choice("cage", c))?,
            positions,
        )),
    };
    Ok(MapRequest {
        model_text: model.text().to_string(),
        model_file: model.source().cloned(),
        parameter: a.parameter,
        values: a.values,
        from: a.from,
        to: a.to,
        settings: SweepSettings {
            harmonics: a.harmonics,
            samples: a.samples,
            contact: a.contact.map(|c| choice("contact", &c)).transpose()?,
            cage,
            contact_smoothing: a.contact_smoothing,
            stability: None,
            stability_modes: a.stability_modes,
            reduction: a.reduce,
        },
        clear_below: a.clear_below,
        check: a.check,
        check_level_m: a.check_level,
        confirm: a.confirm,
    })
}

/// The map as `whirl map` makes it, its sweeps one per thread; `progress(done, 1000)` is
/// told the share of the values done (a true return stops it, as Ctrl-C does).
#[pyfunction]
#[pyo3(signature = (model, options, progress = None))]
pub fn map(
    py: Python<'_>,
    model: &PyModel,
    options: MapArgs,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<PyReport> {
    let request = request(model, options)?;
    let report = run_watched(py, progress.as_ref(), |watch| {
        let progress = fraction_progress(watch);
        map_with(&request, Parallelism::default(), Some(&progress))
    })?
    .map_err(to_py)?;
    PyReport::with_figures(&report, whirl_figures::map(&report))
}
