//! The one result type of the analyses: what the library reports for a result
//! ([`whirl::report::Report`]), its summary and its tables, as the command line writes them
//! (summary.json, one CSV per table). Each analysis is then a thin function that builds the
//! library's report and wraps it here.

use std::path::PathBuf;

use numpy::IntoPyArray;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pythonize::{depythonize, pythonize};
use whirl::report::{Report, Table, Values};
use whirl_plot::{NamedFigure, PlotError};

use crate::error::{to_py, InputError};

/// A library report: its summary and its tables.
#[pyclass(name = "Report", module = "whirl._whirl", frozen)]
pub struct PyReport {
    /// The summary as summary.json holds it (numbers that do not exist are null there).
    summary: serde_json::Value,
    tables: Vec<Table>,
    /// The command line's figures of the result (`whirl_figures`), in its order.
    figures: Vec<NamedFigure>,
}

impl PyReport {
    /// The summary and tables of `report`, with the command line's figures of it.
    pub fn with_figures<R: Report>(report: &R, figures: Vec<NamedFigure>) -> PyResult<PyReport> {
        Ok(PyReport {
            figures,
            ..PyReport::of(report)?
        })
    }

    /// The summary and tables of `report`, without figures.
    pub fn of<R: Report>(report: &R) -> PyResult<PyReport> {
        // Through JSON, as the command line writes it: a NaN is null in both.
        let summary = serde_json::to_value(report.summary()).map_err(|e| {
            to_py(whirl::Error::Internal(format!(
                "cannot encode the summary: {e}"
            )))
        })?;
        Ok(PyReport {
            summary,
            tables: report.tables(),
            figures: Vec::new(),
        })
    }
}

#[pymethods]
impl PyReport {
    /// The summary as a new dict: the analysis's part of summary.json.
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(pythonize(py, &self.summary)?)
    }

    /// The names of the tables, in the order the command line writes them.
    #[getter]
    fn tables(&self) -> Vec<String> {
        self.tables.iter().map(|t| t.name().to_string()).collect()
    }

    /// The command line's figures as specifications (dicts: `name`, `speeds` and `figure`,
    /// whose `kind` says which figure it is), in the order the command line writes them;
    /// [`save_figures`] draws them, `whirl.plot.draw` draws them with matplotlib.
    fn figures<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let specs = PyList::empty(py);
        for f in &self.figures {
            specs.append(pythonize(py, f)?)?;
        }
        Ok(specs)
    }

    /// Table `name` as a dict of its columns in order: numbers as a float array (NaN where
    /// a value does not exist), counts as an int64 array, text as a list (None where it
    /// does not exist).
    fn table<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyDict>> {
        let table = self
            .tables
            .iter()
            .find(|t| t.name() == name)
            .ok_or_else(|| {
                InputError::new_err(format!(
                    "no table `{name}`: the tables are {}",
                    self.tables().join(", ")
                ))
            })?;
        let out = PyDict::new(py);
        for c in table.columns() {
            match &c.values {
                Values::Numbers(v) => out.set_item(&c.name, v.clone().into_pyarray(py))?,
                // As numpy and pandas hold whole numbers by default (a count fits).
                Values::Counts(v) => out.set_item(
                    &c.name,
                    v.iter()
                        .map(|&n| n as i64)
                        .collect::<Vec<_>>()
                        .into_pyarray(py),
                )?,
                Values::Text(v) => out.set_item(
                    &c.name,
                    v.iter()
                        .map(|s| (!s.is_empty()).then_some(s.as_str()))
                        .collect::<Vec<_>>(),
                )?,
            }
        }
        Ok(out)
    }
}

/// Draws figure specifications (as [`PyReport::figures`] gives them) into `folder` as the
/// command line does, `<name>.png` and `<name>.svg` each, their speeds in rpm when `rpm`;
/// returns the paths written.
#[pyfunction]
pub fn save_figures(
    py: Python<'_>,
    specs: Vec<Bound<'_, PyAny>>,
    folder: PathBuf,
    rpm: bool,
) -> PyResult<Vec<PathBuf>> {
    let figures = specs
        .iter()
        .enumerate()
        .map(|(i, spec)| {
            depythonize::<NamedFigure>(spec)
                .map_err(|e| InputError::new_err(format!("figure specification {i}: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    py.detach(|| {
        let mut written = Vec::new();
        for figure in figures {
            let figure = if rpm { figure.in_rpm() } else { figure };
            written.extend(figure.save_in(&folder).map_err(|e| match e {
                PlotError::Io { .. } => PyOSError::new_err(e.to_string()),
                e => to_py(whirl::Error::Internal(format!(
                    "cannot draw the figure `{}`: {e}",
                    figure.name
                ))),
            })?);
        }
        Ok(written)
    })
}
