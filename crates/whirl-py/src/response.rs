//! Steady responses of the linearised rotor: the unbalance response.

use pyo3::prelude::*;
use pythonize::pythonize;
use whirl::fe::{assemble_banded, Bearings};
use whirl::response::{default_unbalance_speeds, unbalance_response_refined};

use crate::error::lib;
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::stoppable;

/// The unbalance response at `nodes` over `speeds` (rad/s; `None` for the library's
/// default), with speeds added in each
/// peak's half-power band, as `whirl unbalance` computes it: the library's result as a
/// dict, and its report.
#[pyfunction]
pub fn unbalance<'py>(
    py: Python<'py>,
    model: &PyModel,
    speeds: Option<Vec<f64>>,
    nodes: Vec<usize>,
) -> PyResult<(Bound<'py, PyAny>, PyReport)> {
    let speeds = speeds.unwrap_or_else(|| default_unbalance_speeds(&model.model));
    let result = lib(stoppable(py, |progress| {
        let system = assemble_banded(&model.model, Bearings::Linearised);
        unbalance_response_refined(&model.model, &system, &speeds, &nodes, Some(progress))
    })?)?;
    let figures = whirl_figures::unbalance(&result);
    Ok((
        pythonize(py, &result)?,
        PyReport::with_figures(&result, figures)?,
    ))
}
