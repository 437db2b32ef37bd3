//! Modal analyses of the linearised rotor: the model check, mesh convergence, the Campbell
//! diagram and the modes at a speed, each with the library's report (its summary and
//! tables, as the command line writes them) beside its arrays.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use pythonize::pythonize;
use whirl::fe::{assemble_banded, Bearings};
use whirl::modal::{check_model, modal_report, CampbellRequest, ModalRequest};

use crate::error::{keyword_lib, lib};
use crate::given::{fill, keyword_error};
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::stoppable;

/// The model checked (`whirl check`): its summary and tables, with its first six undamped
/// natural frequencies.
#[pyfunction]
pub fn check(py: Python<'_>, model: &PyModel) -> PyResult<PyReport> {
    let check = lib(py.detach(|| check_model(&model.model)))?;
    PyReport::with_figures(&check, whirl_figures::check(&check))
}

/// The Campbell diagram with the keyword arguments `options` (each read by the library by
/// its name, those left None at its default). The library's result as a dict, with the
/// branches' `labels` and its `report`.
#[pyfunction]
pub fn campbell<'py>(
    py: Python<'py>,
    model: &PyModel,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut request = CampbellRequest::default();
    fill(options, &mut request)?;
    let options = request.options(&model.model).map_err(keyword_error)?;
    let result = lib(stoppable(py, |progress| {
        let system = assemble_banded(&model.model, Bearings::Linearised);
        whirl::modal::campbell(&system, &options, Some(progress))
    })?)?;
    let report = PyReport::with_figures(&result, whirl_figures::campbell(&model.model, &result))?;
    let out = pythonize(py, &result)?.cast_into::<PyDict>()?;
    out.set_item("labels", result.labels())?;
    out.set_item("report", report)?;
    Ok(out)
}

/// Undamped frequencies of the first `modes` modes for each total element count `counts`:
/// the library's result as a dict, and its report.
#[pyfunction]
pub fn convergence<'py>(
    py: Python<'py>,
    model: &PyModel,
    counts: Vec<usize>,
    modes: Option<usize>,
) -> PyResult<(Bound<'py, PyAny>, PyReport)> {
    let result = keyword_lib(stoppable(py, |progress| {
        whirl::modal::convergence(&model.model, &counts, modes, Some(progress))
    })?)?;
    let figures = whirl_figures::convergence(&result);
    Ok((
        pythonize(py, &result)?,
        PyReport::with_figures(&result, figures)?,
    ))
}

/// The undamped modes and the damped modes at a speed with the keyword arguments
/// `options` (`speed`, `modes`; None at the library's default), as the library reports them
/// (`whirl modal`), and the speed, rad/s: its tables hold the frequencies, shapes and orbits
/// the Python result is read from.
#[pyfunction]
pub fn modal(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
) -> PyResult<(PyReport, f64)> {
    let mut request = ModalRequest::default();
    fill(options, &mut request)?;
    let (speed, modes) = request.resolved().map_err(keyword_error)?;
    let report = lib(py.detach(|| modal_report(&model.model, speed, modes, None)))?;
    let figures = whirl_figures::modal(&model.model, &report);
    Ok((PyReport::with_figures(&report, figures)?, speed))
}
