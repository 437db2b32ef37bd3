//! Run-up and coast-down (`whirl runup`): the keyword arguments fill the library's request,
//! every one left out (None) at the library's default.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use whirl::runup::{runup as sweep, RunupReport, RunupRequest};

use crate::error::{keyword_lib, lib};
use crate::given::fill;
use crate::model::PyModel;
use crate::report::PyReport;

/// The run-up's request from the keyword arguments, each read by the library by its name
/// (the command line's options with `_` for `-`), those left None at its default.
fn request(options: &Bound<'_, PyDict>) -> PyResult<RunupRequest> {
    let mut request = RunupRequest::default();
    fill(options, &mut request)?;
    Ok(request)
}

/// Computes the run-up (`whirl runup`) and returns its report: the summary and the tables
/// the command line writes.
#[pyfunction]
pub fn runup(py: Python<'_>, model: &PyModel, options: &Bound<'_, PyDict>) -> PyResult<PyReport> {
    let o = keyword_lib(request(options)?.options(&model.model))?;
    let result = lib(py.detach(|| sweep(&model.model, &o, None)))?;
    let report = RunupReport { runup: result };
    PyReport::with_figures(&report, whirl_figures::runup(&report, None))
}
