//! The analyses the library reports whole ([`whirl::report::Report`]): each a thin call
//! with the command line's options, its report wrapped as the one result type.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use whirl::bearing::stiffness::{stiffness_report, StiffnessRequest};
use whirl::fe::{assemble_banded, Bearings};
use whirl::modal::{critical_speed_map, UcsRequest};
use whirl::reduce::reduction_report;
use whirl::response::{frf_refined as receptances, FrfReport, FrfRequest};
use whirl::statics::static_response;
use whirl::time::{fit_forcing as fit, FitForcingRequest, ForcingFitReport};

use crate::error::{keyword_lib, lib};
use crate::given::{choice, fill, keyword_error};
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::{fraction_progress, run_watched, stoppable};

/// The Craig-Bampton reduction (`whirl reduce`): `modes` fixed-interface modes, every DOF
/// of the bearing nodes and of `nodes` on the boundary; the reduced model's natural
/// frequencies against the full model's, and the study over the number of modes.
#[pyfunction]
pub fn reduce(
    py: Python<'_>,
    model: &PyModel,
    modes: Option<usize>,
    nodes: Vec<usize>,
) -> PyResult<PyReport> {
    let report = keyword_lib(py.detach(|| reduction_report(&model.model, modes, &nodes, None)))?;
    PyReport::with_figures(&report, whirl_figures::reduce(&report))
}

/// The stiffness study (`whirl stiffness`) with the keyword arguments `options`, each read
/// by the library by its name, those left None at its default.
#[pyfunction]
pub fn stiffness(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
) -> PyResult<PyReport> {
    let mut request = StiffnessRequest::default();
    fill(options, &mut request)?;
    let report = keyword_lib(py.detach(|| stiffness_report(&model.model, &request)))?;
    PyReport::with_figures(&report, whirl_figures::stiffness(&report))
}

/// The static response under gravity (`whirl static`), the roller bearings carrying the
/// load by Hertz contact or by their linear stiffness (`rollers`; None for the library's
/// default).
#[pyfunction]
#[pyo3(signature = (model, rollers = None))]
pub fn statics(py: Python<'_>, model: &PyModel, rollers: Option<&str>) -> PyResult<PyReport> {
    let rollers = rollers
        .map(|r| choice("rollers", r))
        .transpose()?
        .unwrap_or_default();
    let result = lib(py.detach(|| static_response(&model.model, rollers)))?;
    PyReport::with_figures(&result, whirl_figures::statics(&model.model, &result))
}

/// The undamped critical-speed map with the keyword arguments `options` (`stiffness`,
/// `modes`, `at_rest`; each read by the library by its name, None at its default).
#[pyfunction]
pub fn ucs(py: Python<'_>, model: &PyModel, options: &Bound<'_, PyDict>) -> PyResult<PyReport> {
    let mut request = UcsRequest::default();
    fill(options, &mut request)?;
    let (stiffness, modes) = request.resolved(&model.model).map_err(keyword_error)?;
    let synchronous = !request.at_rest;
    let map = lib(stoppable(py, |progress| {
        critical_speed_map(&model.model, &stiffness, modes, synchronous, Some(progress))
    })?)?;
    PyReport::with_figures(&map, whirl_figures::ucs(&model.model, &map))
}

/// Frequency response functions (`whirl frf`) with the keyword arguments `options` (input,
/// output, speed, frequencies, force), each read by the library by its name, those left
/// None at its default.
#[pyfunction]
pub fn frf(py: Python<'_>, model: &PyModel, options: &Bound<'_, PyDict>) -> PyResult<PyReport> {
    let mut request = FrfRequest::default();
    fill(options, &mut request)?;
    let model = &model.model;
    let (input, outputs, speed, w, force) = keyword_lib(request.resolved(model))?;
    let result = lib(stoppable(py, |progress| {
        receptances(
            &assemble_banded(model, Bearings::Linearised),
            speed,
            input,
            &outputs,
            &w,
            Some(progress),
        )
    })?)?;
    let figures = whirl_figures::frf(model, &result);
    PyReport::with_figures(&FrfReport { result, force }, figures)
}

/// The forcing-function law fitted to a roller bearing's Hertz response over speed
/// (`whirl fit-forcing`) with the keyword arguments `options`, each read by the library by
/// its name, those left None at its default; `progress(done, 1000)` is told the share of
/// the simulated time done, and Ctrl-C or a true return stops it.
#[pyfunction]
#[pyo3(signature = (model, options, progress = None))]
pub fn fit_forcing(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<PyReport> {
    let mut request = FitForcingRequest::default();
    fill(options, &mut request)?;
    let (speeds, bearing, options) = request.resolved().map_err(keyword_error)?;
    let model = &model.model;
    let result = run_watched(py, progress.as_ref(), |watch| {
        let progress = fraction_progress(watch);
        fit(model, bearing, &speeds, &options, Some(&progress))
    })?;
    let report = ForcingFitReport::new(model, bearing, lib(result)?);
    PyReport::with_figures(&report, whirl_figures::fit_forcing(&report))
}
