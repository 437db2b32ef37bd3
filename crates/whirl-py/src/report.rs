//! The one result type of the analyses: what the library reports for a result
//! ([`whirl::report::Report`]), its summary and its tables, as the command line writes them
//! (summary.json, one CSV per table). Each analysis is then a thin function that builds the
//! library's report and wraps it here.

use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pythonize::pythonize;
use whirl::report::{Report, Table, Values};

use crate::error::{to_py, InputError};

/// A library report: its summary and its tables.
#[pyclass(name = "Report", module = "whirl._whirl", frozen)]
pub struct PyReport {
    /// The summary as summary.json holds it (numbers that do not exist are null there).
    summary: serde_json::Value,
    tables: Vec<Table>,
}

impl PyReport {
    /// The summary and tables of `report`.
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
