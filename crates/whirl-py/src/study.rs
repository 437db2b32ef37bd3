//! Studies: every point a cascade, on this machine or with the points sent to a cluster's
//! workers by a Python runner, the finished points kept in the library's store.

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pyo3::prelude::*;
use whirl::progress::Progress;
use whirl::study::report::StudyReport;
use whirl::study::results::{analyse, run_points, PointResult};
use whirl::study::store::Store;
use whirl::study::{point, Point, Study};

use crate::error::{lib, to_py};
use crate::report::PyReport;
use crate::watch::{run_watched, Watch};

/// A point's cascade, its finished speeds kept in [`Point::partial_dir`] until the study
/// ends (as the command line does), so a point interrupted half-way, or whose worker died,
/// continues from its finished speeds, and a point sharing its cascade reads it whole.
fn compute_point(
    p: &Point,
    store_dir: &Path,
    watch: Option<&Arc<Watch>>,
) -> whirl::Result<PointResult> {
    let partial = p.partial_dir(store_dir);
    let watch = watch.cloned();
    let stop = Progress::new(
        move |_| match watch.as_deref().is_some_and(Watch::stopped) {
            true => ControlFlow::Break(()),
            false => ControlFlow::Continue(()),
        },
    );
    // Its speeds stay until the study ends, for a point that shares its cascade.
    point::compute(p, Some(&partial), Some(&stop))
}

/// Point `index` of the study file `path`, computed on a worker, as exact JSON; its
/// speeds are kept under `checkpoint` (a folder the workers share) while it runs.
#[pyfunction]
pub fn study_point(
    py: Python<'_>,
    path: PathBuf,
    index: usize,
    checkpoint: PathBuf,
) -> PyResult<String> {
    let study = lib(Study::from_file(&path))?;
    let p = study.points.get(index).ok_or_else(|| {
        to_py(whirl::Error::InvalidOption(format!(
            "the study has no point {index}"
        )))
    })?;
    let result = lib(py.detach(|| compute_point(p, &checkpoint, None)))?;
    serde_json::to_string(&result).map_err(|e| {
        to_py(whirl::Error::Internal(format!(
            "cannot encode a point: {e}"
        )))
    })
}

/// Runs the study file `path`, keeping finished points in `checkpoint` (`restart` empties
/// it first). With `runner`, the points not yet in the checkpoint go to `runner(indices)`,
/// which yields `(index, point_json)` as each arrives (from [`study_point`] on a worker).
/// Returns the library's report of the study (its summary, tables and figures, as the
/// command line writes them) and the checkpoint folder.
#[pyfunction]
#[pyo3(signature = (path, checkpoint, restart, progress = None, runner = None))]
pub fn study<'py>(
    py: Python<'py>,
    path: PathBuf,
    checkpoint: PathBuf,
    restart: bool,
    progress: Option<Bound<'py, PyAny>>,
    runner: Option<Py<PyAny>>,
) -> PyResult<(PyReport, PathBuf)> {
    let study = lib(Study::from_file(&path))?;
    let store = lib(Store::open(&checkpoint, &study.fingerprint, &path, restart))?;
    let total = study.points.len();
    let outcomes = run_watched(py, progress.as_ref(), |watch| -> whirl::Result<_> {
        if let Some(runner) = &runner {
            // One task per cascade: a point sharing another's cascade (another threshold)
            // resumes it here afterwards, where two tasks would race for its folder.
            let unfinished: Vec<usize> = (0..total)
                .filter(|&k| {
                    store
                        .load::<PointResult>(&study.points[k].key)
                        .is_none_or(|r| r.key != study.points[k].key)
                })
                .collect();
            let mut done = total - unfinished.len();
            let mut cascades = std::collections::HashSet::new();
            let missing: Vec<usize> = unfinished
                .into_iter()
                .filter(|&k| cascades.insert(study.points[k].cascade_key.clone()))
                .collect();
            watch.tell(done, total);
            if !missing.is_empty() {
                crate::cluster::run_on(runner, missing, "point", |k, result: PointResult| {
                    store.save(&study.points[k].key, &result)?;
                    done += 1;
                    watch.tell(done, total);
                    Ok(())
                })?;
            }
        }
        run_points(
            &study,
            &store,
            |p| match watch.stopped() {
                true => Err(whirl::Error::Interrupted("stopped".into())),
                false => compute_point(p, store.dir(), Some(watch)),
            },
            |k, _, _, _| {
                watch.tell(k + 1, total);
            },
        )
    })?
    .map_err(to_py)?;
    if outcomes
        .iter()
        .any(|o| o.as_ref().is_err_and(|e| e == "stopped"))
        || py.check_signals().is_err()
    {
        return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(format!(
            "the study was stopped; its finished points are kept in `{}`",
            store.dir().display()
        )));
    }
    let analysis = analyse(&study, &outcomes);
    let report = StudyReport {
        study,
        results: outcomes,
        outcome: analysis,
    };
    let figures = whirl_figures::study(&report);
    Ok((
        PyReport::with_figures(&report, figures)?,
        store.dir().to_path_buf(),
    ))
}
