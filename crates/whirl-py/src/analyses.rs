//! The analyses the library reports whole ([`whirl::report::Report`]): each a thin call
//! with the command line's options, its report wrapped as the one result type.

use pyo3::prelude::*;
use whirl::reduce::reduction_report;

use crate::error::lib;
use crate::model::PyModel;
use crate::report::PyReport;

/// The Craig-Bampton reduction (`whirl reduce`): `modes` fixed-interface modes, every DOF
/// of the bearing nodes and of `nodes` on the boundary; the reduced model's natural
/// frequencies against the full model's, and the study over the number of modes.
#[pyfunction]
pub fn reduce(
    py: Python<'_>,
    model: &PyModel,
    modes: usize,
    nodes: Vec<usize>,
) -> PyResult<PyReport> {
    let report = lib(py.detach(|| reduction_report(&model.model, modes, &nodes)))?;
    PyReport::of(&report)
}
