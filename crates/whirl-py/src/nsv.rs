//! The NSV cascade: on this machine's threads, or with its speeds sent to a cluster's
//! workers by a Python runner (the Dask helpers of the package), with the same checkpoint,
//! refinement and result.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pythonize::pythonize;
use whirl::given::Choice;
use whirl::model::Model;
use whirl::nsv::{
    compare_starts as compare, other_start_options, Cascade, CascadeOptions, CascadePoint,
    CascadeReport, CascadeRequest, PreparedCascade,
};
use whirl::progress::Progress;

use crate::error::{keyword_lib, lib, to_py};
use crate::given::fill;
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::run_watched;

/// The cascade's request from the keyword arguments, each read by the library by its
/// name (the command line's options with `_` for `-`), those left None at its default.
fn request(options: &Bound<'_, PyDict>) -> PyResult<CascadeRequest> {
    let mut request = CascadeRequest::default();
    fill(options, &mut request)?;
    Ok(request)
}

/// The library's options for `model` from the keyword arguments.
fn cascade_options(model: &PyModel, options: &Bound<'_, PyDict>) -> PyResult<CascadeOptions> {
    keyword_lib(request(options)?.options(&model.model))
}

/// The cascade's options as the library resolves them for `model` (every default filled
/// in): a dict of [`CascadeOptions`].
#[pyfunction]
pub fn cascade_resolved<'py>(
    py: Python<'py>,
    model: &PyModel,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(pythonize(py, &cascade_options(model, options)?)?)
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

/// The last cascade prepared in this process (its model reduced, its step worked out), kept
/// for the next call on the same model and options: a cluster's worker computes many speeds
/// of one cascade, and a checkpointed run names its folder and then runs.
static PREPARED: Mutex<Option<Arc<PreparedCascade<'static>>>> = Mutex::new(None);

/// The cascade of `model` with `options` prepared, or the one kept when it is the same.
fn prepared(
    model: &Model,
    options: &CascadeOptions,
) -> whirl::Result<Arc<PreparedCascade<'static>>> {
    let mut kept = PREPARED
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some(p) = kept.as_ref().filter(|p| p.is_of(model, options)) {
        return Ok(Arc::clone(p));
    }
    let fresh = Arc::new(PreparedCascade::owned(model.clone(), options.clone())?);
    *kept = Some(Arc::clone(&fresh));
    Ok(fresh)
}

/// The checkpoint folder of this cascade inside `parent`: one folder per model and options.
#[pyfunction]
pub fn cascade_checkpoint(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    parent: PathBuf,
) -> PyResult<PathBuf> {
    let o = cascade_options(model, options)?;
    let key = py.detach(|| prepared(&model.model, &o)?.checkpoint_key());
    Ok(parent.join(lib(key)?))
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
    options: &Bound<'py, PyDict>,
    checkpoint: Option<PathBuf>,
    progress: Option<Bound<'py, PyAny>>,
    runner: Option<Py<PyAny>>,
) -> PyResult<(Bound<'py, PyAny>, RawCascade)> {
    let request = request(options)?;
    let o = keyword_lib(request.options(&model.model))?;
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
            None => prepared(&model.model, &o)?.run(checkpoint, Some(&report)),
            Some(runner) => {
                let run = |batch: &[(usize, f64)],
                           done: &mut dyn FnMut(usize, CascadePoint) -> whirl::Result<()>| {
                    crate::cluster::run_on(runner, batch.to_vec(), "point", done)
                };
                prepared(&model.model, &o)?.run_distributed(checkpoint, Some(&report), &run)
            }
        }
    })?
    .map_err(to_py)?;
    let threshold = request.threshold_m();
    Ok((pythonize(py, &result)?, RawCascade(result, threshold)))
}

/// A computed cascade as the library holds it, and the threshold (m) its summary reads it
/// at, kept to be reported and compared with another.
#[pyclass(frozen, module = "whirl._whirl")]
pub struct RawCascade(Cascade, f64);

/// The keyword arguments of the cascade that tests `first` (computed with `options`) from
/// the other start: `options` with exactly `first`'s speeds (rad/s, added ones too), the
/// other start and no refinement.
#[pyfunction]
pub fn other_start<'py>(
    first: &RawCascade,
    options: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyDict>> {
    let o = other_start_options(&first.0);
    let out = options.copy()?;
    out.del_item("no_refine").ok();
    out.set_item("speeds", o.speeds)?;
    out.set_item("start", o.initial.choice_name())?;
    out.set_item("refine", o.refine.enabled)?;
    Ok(out)
}

/// The library's report of cascade `first`, kept in `checkpoint_folder`; with `second`
/// (`first` from the other start, at its speeds) the two compared speed by speed: the
/// summary and tables the command line writes.
#[pyfunction]
#[pyo3(signature = (first, checkpoint_folder = None, second = None))]
pub fn cascade_report(
    first: &RawCascade,
    checkpoint_folder: Option<String>,
    second: Option<&RawCascade>,
) -> PyResult<PyReport> {
    let threshold = first.1;
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

/// One speed (rad/s) of the cascade, as the cascade computes it, as exact JSON: what a
/// cluster's worker runs.
#[pyfunction]
pub fn cascade_point(
    py: Python<'_>,
    model: &PyModel,
    options: &Bound<'_, PyDict>,
    speed: f64,
) -> PyResult<String> {
    let o = cascade_options(model, options)?;
    let point = lib(py.detach(|| prepared(&model.model, &o)?.point(speed)))?;
    serde_json::to_string(&point).map_err(|e| {
        to_py(whirl::Error::Internal(format!(
            "cannot encode a point: {e}"
        )))
    })
}
