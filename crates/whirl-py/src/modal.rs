//! Modal analyses of the linearised rotor: the model check, mesh convergence, the Campbell
//! diagram and the modes at a speed, each with the library's report (its summary and
//! tables, as the command line writes them) beside its arrays.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pythonize::pythonize;
use whirl::fe::{assemble_banded, dof, Bearings, Direction, DOFS_PER_NODE};
use whirl::modal::{check_model, modal_report, CampbellOptions};

use crate::error::{keyword_lib, lib};
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

/// The Campbell diagram over `speeds` (rad/s): `modes` branches, critical speeds at the
/// excitation `orders`, on a basis of 2 x modes + 8 undamped modes unless `full`.
#[pyfunction]
pub fn campbell<'py>(
    py: Python<'py>,
    model: &PyModel,
    speeds: Vec<f64>,
    modes: usize,
    orders: Vec<f64>,
    full: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let options = CampbellOptions {
        speeds,
        modes,
        orders,
        basis_size: (!full).then(|| CampbellOptions::default_basis(modes)),
        ..CampbellOptions::new(Vec::new())
    };
    let result = lib(stoppable(py, |progress| {
        let system = assemble_banded(&model.model, Bearings::Linearised);
        whirl::modal::campbell(&system, &options, Some(progress))
    })?)?;
    let report = PyReport::with_figures(&result, whirl_figures::campbell(&model.model, &result))?;
    let labels = result.labels();
    let branches = PyList::empty(py);
    for (b, label) in result.branches.into_iter().zip(labels) {
        let d = PyDict::new(py);
        d.set_item("label", label)?;
        d.set_item("index", b.index)?;
        d.set_item("whirl", b.whirl.name())?;
        d.set_item("frequency_hz", b.frequency_hz.into_pyarray(py))?;
        d.set_item("damping_ratio", b.damping_ratio.into_pyarray(py))?;
        d.set_item("log_decrement", b.log_decrement.into_pyarray(py))?;
        let whirl_at: Vec<&str> = b.whirl_at.iter().map(|w| w.name()).collect();
        d.set_item("whirl_at", whirl_at)?;
        branches.append(d)?;
    }
    let critical = PyList::empty(py);
    for c in &result.critical_speeds {
        let d = PyDict::new(py);
        d.set_item("speed_hz", c.speed_hz)?;
        d.set_item("speed_rpm", c.speed_rpm)?;
        d.set_item("frequency_hz", c.frequency_hz)?;
        d.set_item("order", c.order)?;
        d.set_item("branch", c.branch)?;
        d.set_item("whirl", c.whirl.name())?;
        d.set_item("damping_ratio", c.damping_ratio)?;
        critical.append(d)?;
    }
    let out = PyDict::new(py);
    out.set_item("speeds_hz", result.speeds_hz.into_pyarray(py))?;
    out.set_item("orders", result.orders)?;
    out.set_item("basis_size", result.basis_size)?;
    out.set_item("branches", branches)?;
    out.set_item("critical_speeds", critical)?;
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
    modes: usize,
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

/// The `modes` undamped modes (frequencies, mass-normalised shapes `[dof, mode]`) and the
/// first `modes` damped modes at `speed` (rad/s) with their labels and, per node, the
/// amplitude and phase of ux and uy and the forward and backward orbit radii; with the
/// library's report (`whirl modal`).
#[pyfunction]
pub fn modal<'py>(
    py: Python<'py>,
    model: &PyModel,
    speed: f64,
    modes: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let report = lib(py.detach(|| modal_report(&model.model, speed, modes, None)))?;
    let (undamped, damped) = (&report.undamped, &report.damped);
    let nodes = model.model.node_count();
    let shapes = &undamped.shapes;
    let count = undamped.frequencies_hz.len();
    let flat: Vec<f64> = (0..DOFS_PER_NODE * nodes)
        .flat_map(|i| (0..count).map(move |j| shapes[(i, j)]))
        .collect();
    let shapes = numpy::ndarray::Array2::from_shape_vec((DOFS_PER_NODE * nodes, count), flat)
        .map_err(|e| crate::error::to_py(whirl::Error::Internal(e.to_string())))?;
    let list = PyList::empty(py);
    for (m, label) in damped.iter().zip(&report.labels) {
        let d = PyDict::new(py);
        d.set_item("label", label)?;
        d.set_item("damped_frequency_hz", m.damped_frequency_hz)?;
        d.set_item("natural_frequency_hz", m.natural_frequency_hz)?;
        d.set_item("damping_ratio", m.damping_ratio)?;
        d.set_item("log_decrement", m.log_decrement)?;
        d.set_item("whirl", m.whirl.name())?;
        d.set_item("eigenvalue", m.eigenvalue)?;
        let at = |n: usize, dir| m.shape[dof(n, dir)];
        let column =
            |f: &dyn Fn(usize) -> f64| (0..nodes).map(f).collect::<Vec<f64>>().into_pyarray(py);
        d.set_item("ux_amplitude", column(&|n| at(n, Direction::Ux).norm()))?;
        d.set_item(
            "ux_phase_deg",
            column(&|n| at(n, Direction::Ux).arg().to_degrees()),
        )?;
        d.set_item("uy_amplitude", column(&|n| at(n, Direction::Uy).norm()))?;
        d.set_item(
            "uy_phase_deg",
            column(&|n| at(n, Direction::Uy).arg().to_degrees()),
        )?;
        d.set_item("forward_radius", column(&|n| m.orbit_radii(n).0))?;
        d.set_item("backward_radius", column(&|n| m.orbit_radii(n).1))?;
        list.append(d)?;
    }
    let out = PyDict::new(py);
    out.set_item(
        "undamped_frequencies_hz",
        undamped.frequencies_hz.clone().into_pyarray(py),
    )?;
    out.set_item(
        "undamped_shapes",
        numpy::PyArray2::from_owned_array(py, shapes),
    )?;
    out.set_item("damped", list)?;
    let figures = whirl_figures::modal(&model.model, &report);
    out.set_item("report", PyReport::with_figures(&report, figures)?)?;
    Ok(out)
}
