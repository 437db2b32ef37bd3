//! Run-up and coast-down (`whirl runup`): the keyword arguments fill the library's request,
//! every one left out (None) at the library's default.

use pyo3::prelude::*;
use whirl::nsv::CascadeRequest;
use whirl::runup::{runup as sweep, RunupReport, RunupRequest};
use whirl::units::{parse_angular_acceleration, parse_speed_range};

use crate::error::{lib, option};
use crate::model::PyModel;
use crate::nsv::choice;
use crate::report::PyReport;

/// The run-up's options as the Python package resolves them (speeds in rad/s, rate in
/// rad/s^2, times in s, lengths in m, frequencies in Hz); None leaves the default.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct RunupArgs {
    speeds: Option<(f64, f64)>,
    rate: Option<f64>,
    direction: Option<String>,
    hold: Option<f64>,
    window_length: Option<f64>,
    overlap: Option<f64>,
    steady: Option<String>,
    steady_speeds: Option<usize>,
    hysteresis_ratio: Option<f64>,
    threshold: Option<f64>,
    smoothing: Option<f64>,
    steady_smoothing: Option<f64>,
    start: Option<String>,
    contact: Option<String>,
    reduce: Option<usize>,
    full_model: bool,
    step: Option<f64>,
    node: Option<usize>,
    component: Option<String>,
    window: Option<String>,
    max_frequency: Option<f64>,
    tolerance: Option<f64>,
}

/// An option enum by its command-line name, or None.
fn maybe<T: clap::ValueEnum>(name: &str, value: &Option<String>) -> PyResult<Option<T>> {
    value.as_deref().map(|v| choice(name, v)).transpose()
}

/// The library's request from the keyword arguments (as the command line's from its flags).
fn request(a: &RunupArgs) -> PyResult<RunupRequest> {
    Ok(RunupRequest {
        speeds: a.speeds,
        rate: a.rate,
        direction: maybe("direction", &a.direction)?,
        hold: a.hold,
        window_length: a.window_length,
        overlap: a.overlap,
        steady: maybe("steady", &a.steady)?,
        steady_speeds: a.steady_speeds,
        hysteresis_ratio: a.hysteresis_ratio,
        threshold_m: a.threshold,
        smoothing_hz: a.smoothing,
        steady_smoothing_hz: a.steady_smoothing,
        cascade: CascadeRequest {
            start: maybe("start", &a.start)?,
            contact: maybe("contact", &a.contact)?,
            reduce: if a.full_model {
                Some(None)
            } else {
                a.reduce.map(Some)
            },
            step: a.step,
            node: a.node,
            component: maybe("component", &a.component)?,
            window: maybe("window", &a.window)?,
            max_frequency_hz: a.max_frequency,
            tolerance_bins: a.tolerance,
            ..CascadeRequest::default()
        },
    })
}

/// Computes the run-up (`whirl runup`) and returns its report: the summary and the tables
/// the command line writes.
#[pyfunction]
pub fn runup(py: Python<'_>, model: &PyModel, options: RunupArgs) -> PyResult<PyReport> {
    let o = lib(request(&options)?.options(&model.model))?;
    let result = lib(py.detach(|| sweep(&model.model, &o, None)))?;
    let report = RunupReport { runup: result };
    PyReport::with_figures(&report, whirl_figures::runup(&report, None))
}

/// A speed range `low:high` such as `1:750Hz`, in rad/s.
#[pyfunction]
pub fn parse_speed_range_text(text: &str) -> PyResult<(f64, f64)> {
    parse_speed_range(text).map_err(|e| option("speeds", e))
}

/// An angular acceleration such as `20Hz/s`, in rad/s^2.
#[pyfunction]
pub fn parse_rate(text: &str) -> PyResult<f64> {
    parse_angular_acceleration(text).map_err(|e| option("rate", e))
}
