//! Harmonic balance (`whirl hbm`): the periodic response followed over speed, with Floquet
//! stability, the time-marching comparisons and the harmonic-count study: the library's
//! workflow ([`HbmRequest::run`]), its request filled from the keyword arguments by name.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use whirl::hbm::{sweep_with_progress, HbmRequest};

use crate::error::keyword_lib;
use crate::given::fill;
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::{fraction_progress, run_watched};

/// The harmonic-balance run as `whirl hbm` makes it, from the keyword arguments (the
/// command line's options with `_` for `-`, those left None at the library's default);
/// `progress(done, 1000)` is told each sweep's fraction of the speed range.
#[pyfunction]
#[pyo3(signature = (model, options, progress = None))]
pub fn hbm(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<PyReport> {
    let mut request = HbmRequest::default();
    fill(options, &mut request)?;
    let model = &model.model;
    let report = run_watched(py, progress.as_ref(), |watch| {
        request.run(model, &mut |o| {
            sweep_with_progress(model, o, Some(&fraction_progress(watch)))
        })
    })?;
    let report = keyword_lib(report)?;
    PyReport::with_figures(&report, whirl_figures::harmonic_balance(&report))
}
