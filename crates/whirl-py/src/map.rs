//! The NSV map (`whirl map`): one harmonic-balance sweep with stability per value of a model
//! parameter, its unstable bands and resonance lines, and the check against cascades. The
//! options arrive as the library's request takes them: `None` is the library's default.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use whirl::hbm::HbmRequest;
use whirl::map::{
    distributed_map, map_value as value_run, map_with, MapRequest, Parallelism, ValueRun,
};

use crate::error::{keyword_lib, to_py};
use crate::given::fill;
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::{fraction_progress, run_watched};

/// The library's request for `model`: the map's own keywords `options` and the sweeps'
/// speeds and settings `sweep` (as `whirl.hbm` reads them, [`HbmRequest::set`]), each read
/// by the library by its name, those left None at its default.
fn request(
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    sweep: &Bound<'_, PyDict>,
) -> PyResult<MapRequest> {
    let mut hb = HbmRequest::default();
    fill(sweep, &mut hb)?;
    let range = keyword_lib(hb.sweep_options(&model.model, hb.settings.harmonics()))?;
    let mut request = MapRequest {
        model_text: model.text().to_string(),
        model_file: model.source().cloned(),
        from: range.from,
        to: range.to,
        settings: hb.sweep_settings(),
        ..MapRequest::default()
    };
    fill(options, &mut request)?;
    Ok(request)
}

/// The map as `whirl map` makes it, its sweeps one per thread; `progress(done, 1000)` is
/// told the share of the values done (a true return stops it, as Ctrl-C does). With
/// `runner`, the values' sweeps go to `runner(indices)`, a Python callable that yields
/// `(index, run_json)` as each arrives (from [`map_value`] on a worker).
#[pyfunction]
#[pyo3(signature = (model, options, sweep, progress = None, runner = None))]
pub fn map(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    sweep: &Bound<'_, PyDict>,
    progress: Option<Bound<'_, PyAny>>,
    runner: Option<Py<PyAny>>,
) -> PyResult<PyReport> {
    let request = request(model, options, sweep)?;
    let report = run_watched(py, progress.as_ref(), |watch| {
        let progress = fraction_progress(watch);
        match &runner {
            None => map_with(&request, Parallelism::default(), Some(&progress)),
            Some(runner) => {
                let run = |indices: &[usize],
                           done: &mut dyn FnMut(usize, ValueRun) -> whirl::Result<()>| {
                    crate::cluster::run_on(runner, indices.to_vec(), "value", done)
                };
                distributed_map(&request, Some(&progress), &run)
            }
        }
    })?
    .map_err(to_py)?;
    PyReport::with_figures(&report, whirl_figures::map(&report))
}

/// Value `index`'s sweep of the map, as the map computes it, as exact JSON: what a
/// cluster's worker runs.
#[pyfunction]
pub fn map_value(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    sweep: &Bound<'_, PyDict>,
    index: usize,
) -> PyResult<String> {
    let request = request(model, options, sweep)?;
    let run = py.detach(|| value_run(&request, index)).map_err(to_py)?;
    serde_json::to_string(&run).map_err(|e| {
        to_py(whirl::Error::Internal(format!(
            "cannot encode a value's run: {e}"
        )))
    })
}
