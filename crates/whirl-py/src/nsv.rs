//! The NSV cascade: on this machine's threads, or with its speeds sent to a cluster's
//! workers by a Python runner (the Dask helpers of the package), with the same checkpoint,
//! refinement and result.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::Arc;

use clap::ValueEnum;
use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pythonize::pythonize;
use whirl::nsv::{
    checkpoint, compare_starts as compare, other_start_options, Cascade, CascadeOptions,
    CascadePoint, CascadeReport, CascadeRequest,
};
use whirl::progress::Progress;

use crate::error::{lib, option, to_py};
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::run_watched;

/// The cascade's options, resolved by the Python package from its keyword arguments (the
/// command line's options and defaults; speeds in rad/s, times in s, frequencies in Hz).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct CascadeArgs {
    speeds: Vec<f64>,
    settle: f64,
    settle_max: f64,
    start: String,
    refine: bool,
    refine_budget: usize,
    refine_spacing_hz: f64,
    record: f64,
    max_records: usize,
    average_tolerance: f64,
    contact: Option<String>,
    reduce: Option<usize>,
    step: Option<f64>,
    node: Option<usize>,
    component: String,
    window: String,
    max_frequency_hz: Option<f64>,
    tolerance: f64,
    full: bool,
}

/// An option enum by the name the command line gives it, e.g. `hertz`.
pub fn choice<T: ValueEnum>(name: &str, value: &str) -> PyResult<T> {
    T::from_str(value, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        option(
            name,
            format!("`{value}` is not one of {}", names.join(", ")),
        )
    })
}

/// The library's options from the keyword arguments (as the command line's from its flags).
fn cascade_options(model: &PyModel, a: &CascadeArgs) -> PyResult<CascadeOptions> {
    let request = CascadeRequest {
        speeds: Some(a.speeds.clone()),
        settle: Some(a.settle),
        settle_max: Some(a.settle_max),
        start: Some(choice("start", &a.start)?),
        refine: Some(a.refine),
        refine_budget: Some(a.refine_budget),
        refine_spacing_hz: Some(a.refine_spacing_hz),
        record: Some(a.record),
        max_records: Some(a.max_records),
        average_tolerance: Some(a.average_tolerance),
        contact: a
            .contact
            .as_deref()
            .map(|c| choice("contact", c))
            .transpose()?,
        reduce: Some(a.reduce),
        step: a.step,
        node: a.node,
        component: Some(choice("component", &a.component)?),
        window: Some(choice("window", &a.window)?),
        max_frequency_hz: a.max_frequency_hz,
        tolerance_bins: Some(a.tolerance),
        full: Some(a.full),
    };
    lib(request.options(&model.model))
}

/// The cascade's default speeds of `model`, rad/s: the library's (as on the command line and
/// in a study).
#[pyfunction]
pub fn cascade_default_speeds<'py>(
    py: Python<'py>,
    model: &PyModel,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    Ok(lib(whirl::nsv::default_speeds(&model.model))?.into_pyarray(py))
}

/// The checkpoint folder of this cascade inside `parent`: one folder per model and options.
#[pyfunction]
pub fn cascade_checkpoint(
    model: &PyModel,
    options: CascadeArgs,
    parent: PathBuf,
) -> PyResult<PathBuf> {
    let o = cascade_options(model, &options)?;
    Ok(parent.join(lib(checkpoint::key(&model.model, &o))?))
}

/// Computes the cascade (resuming from and saving to `checkpoint` when given), telling
/// `progress(done, total)` and stopping on Ctrl-C. With `runner`, the missing speeds of each
/// round go to `runner(batch)`, a Python callable given `[(index, speed)]` that yields
/// `(index, point_json)` as each point arrives (from [`cascade_point`] on a worker).
/// Returns the library's cascade as a dict (its speeds, spectra and per-speed NSV) and as
/// it is held, for [`cascade_report`].
#[pyfunction]
#[pyo3(signature = (model, options, checkpoint = None, progress = None, runner = None))]
pub fn cascade<'py>(
    py: Python<'py>,
    model: &PyModel,
    options: CascadeArgs,
    checkpoint: Option<PathBuf>,
    progress: Option<Bound<'py, PyAny>>,
    runner: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, RawCascade)> {
    let o = cascade_options(model, &options)?;
    let result = run_watched(py, progress.as_ref(), |watch| {
        let told = Arc::clone(watch);
        // Speeds computed of those to compute (the checkpoint's are in neither count).
        let report = Progress::new(move |p| {
            if told.tell(p.done as usize, p.total as usize) {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        });
        let checkpoint = checkpoint.as_deref();
        match &runner {
            None => whirl::nsv::cascade(&model.model, &o, checkpoint, Some(&report)),
            Some(runner) => {
                let run = |batch: &[(usize, f64)],
                           done: &mut dyn FnMut(usize, CascadePoint) -> whirl::Result<()>| {
                    run_batch(runner, batch, done)
                };
                whirl::nsv::distributed_cascade(&model.model, &o, checkpoint, Some(&report), &run)
            }
        }
    })?
    .map_err(to_py)?;
    Ok((pythonize(py, &result)?, RawCascade(result)))
}

/// A computed cascade as the library holds it, kept to be compared with another.
#[pyclass(frozen, module = "whirl._whirl")]
pub struct RawCascade(Cascade);

/// What the cascade that tests `first` from the other start changes in `first`'s options:
/// `speeds` (rad/s: exactly `first`'s, added ones too), `start` and `refine` (off).
#[pyfunction]
pub fn other_start<'py>(py: Python<'py>, first: &RawCascade) -> PyResult<Bound<'py, PyDict>> {
    let o = other_start_options(&first.0);
    let out = PyDict::new(py);
    out.set_item("speeds", o.speeds)?;
    out.set_item("start", name(&o.initial))?;
    out.set_item("refine", o.refine.enabled)?;
    Ok(out)
}

/// The library's report of cascade `first` read at `threshold` (m), kept in
/// `checkpoint_folder`; with `second` (`first` from the other start, at its speeds) the two
/// compared speed by speed: the summary and tables the command line writes.
#[pyfunction]
#[pyo3(signature = (first, threshold, checkpoint_folder = None, second = None))]
pub fn cascade_report(
    first: &RawCascade,
    threshold: f64,
    checkpoint_folder: Option<String>,
    second: Option<&RawCascade>,
) -> PyResult<PyReport> {
    let starts = second
        .map(|s| compare(&first.0, s.0.clone(), threshold))
        .transpose()
        .map_err(to_py)?;
    let report = CascadeReport {
        cascade: first.0.clone(),
        threshold_m: threshold,
        starts,
        checkpoint_folder,
    };
    PyReport::with_figures(&report, whirl_figures::cascade(&report, None))
}

/// An option's value by the name the command line gives it, e.g. `static`.
fn name<T: ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_string())
}

/// Hands a batch to the Python runner and each point it yields to `done`.
fn run_batch(
    runner: &Py<PyAny>,
    batch: &[(usize, f64)],
    done: &mut dyn FnMut(usize, CascadePoint) -> whirl::Result<()>,
) -> whirl::Result<()> {
    let failed = |e: PyErr| whirl::Error::Internal(format!("the cluster's runner failed: {e}"));
    Python::attach(|py| {
        let points = runner.call1(py, (batch.to_vec(),)).map_err(failed)?;
        for item in points.bind(py).try_iter().map_err(failed)? {
            let (i, json): (usize, String) = item.and_then(|x| x.extract()).map_err(failed)?;
            let point: CascadePoint = serde_json::from_str(&json).map_err(|e| {
                whirl::Error::Internal(format!("a worker's point {i} does not read back: {e}"))
            })?;
            done(i, point)?;
        }
        Ok(())
    })
}

/// One speed (rad/s) of the cascade, as the cascade computes it, as exact JSON: what a
/// cluster's worker runs.
#[pyfunction]
pub fn cascade_point(
    py: Python<'_>,
    model: &PyModel,
    options: CascadeArgs,
    speed: f64,
) -> PyResult<String> {
    let o = cascade_options(model, &options)?;
    let point = lib(py.detach(|| whirl::nsv::cascade_point(&model.model, &o, speed)))?;
    serde_json::to_string(&point).map_err(|e| {
        to_py(whirl::Error::Internal(format!(
            "cannot encode a point: {e}"
        )))
    })
}
