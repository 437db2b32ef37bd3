//! Time simulation (`whirl simulate`): the library's run with the command line's settings,
//! its progress shown and Ctrl-C ending it.

use std::ops::ControlFlow;

use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use whirl::progress::Progress;
use whirl::time::{
    simulate_with, Hooks, SimulationOptions, SimulationReport, SimulationRequest, Until,
};

use crate::error::{keyword_lib, lib, to_py, NumericalError};
use crate::given::fill;
use crate::model::PyModel;
use crate::report::PyReport;
use crate::watch::run_watched;

/// Progress steps reported per run.
const STEPS: f64 = 1000.0;

/// The library's settings from the keyword arguments, each read by the library by its
/// name (the command line's options with `_` for `-`), those left None at its default.
fn simulation_options(options: &Bound<'_, PyDict>) -> PyResult<SimulationOptions> {
    let mut request = SimulationRequest::default();
    fill(options, &mut request)?;
    keyword_lib(request.options())
}

/// Simulates the model; `progress(done, 1000)` is told the fraction of simulated time done.
/// Returns the recorded channels as arrays (`time`, `values[channel, sample]`, `names`,
/// `nodes`, and the `settle`, `step` and `record_every` that place them) and the library's
/// report (summary and tables, as the command line writes them).
#[pyfunction]
#[pyo3(signature = (model, options, progress = None))]
pub fn simulate<'py>(
    py: Python<'py>,
    model: &PyModel,
    options: &Bound<'py, PyDict>,
    progress: Option<Bound<'py, PyAny>>,
) -> PyResult<(Bound<'py, PyDict>, PyReport)> {
    let mut o = simulation_options(options)?;
    let result = run_watched(py, progress.as_ref(), |watch| {
        let told = watch.clone();
        o.progress = Some(Progress::new(move |r| {
            told.tell((r.fraction() * STEPS).round() as usize, STEPS as usize);
            ControlFlow::Continue(())
        }));
        // Ctrl-C ends the run at the next recorded sample; it is then reported as stopped.
        let mut stop = |_: &[Vec<f64>]| match watch.stopped() {
            true => ControlFlow::Break(()),
            false => ControlFlow::Continue(()),
        };
        let hooks = Hooks {
            until: Some(Until {
                every: 1,
                decide: &mut stop,
            }),
            ..Hooks::default()
        };
        let result = simulate_with(&model.model, &o, hooks);
        (result, watch.stopped())
    })?;
    let (result, stopped) = (keyword_lib(result.0)?, result.1);
    if stopped {
        return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(format!(
            "the simulation was stopped at {} s of {} s",
            result.time.last().copied().unwrap_or(0.0),
            o.duration
        )));
    }
    let result = result
        .completed()
        .map_err(|e| NumericalError::new_err(format!("{e}\n  help: nothing was kept")))?;
    let samples = result.time.len();
    let values: Vec<f64> = result
        .channels
        .iter()
        .flat_map(|c| c.values.iter().copied())
        .collect();
    let values = numpy::ndarray::Array2::from_shape_vec((result.channels.len(), samples), values)
        .map_err(|e| {
        to_py(whirl::Error::Internal(format!(
            "channels of unequal length: {e}"
        )))
    })?;
    let out = PyDict::new(py);
    out.set_item("time", result.time.clone().into_pyarray(py))?;
    out.set_item("values", PyArray2::from_owned_array(py, values))?;
    out.set_item(
        "names",
        result
            .channels
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>(),
    )?;
    out.set_item(
        "nodes",
        result.channels.iter().map(|c| c.node).collect::<Vec<_>>(),
    )?;
    out.set_item("settle", result.settle)?;
    out.set_item("step", result.step)?;
    out.set_item("record_every", result.record_every)?;
    let report = lib(SimulationReport::new(&model.model, &o, result))?;
    let figures = whirl_figures::simulate(&model.model, &report);
    Ok((out, PyReport::with_figures(&report, figures)?))
}
