//! The model: read from a model file, from TOML text or from JSON (a Python dict), and
//! edited by the parameter paths of the study files, always through the library's own
//! validation, so that a bad value gets the message it would get in a model file.

use std::path::PathBuf;

use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt, PyString};
use toml_edit::DocumentMut;
use whirl::model::Model;
use whirl::study::path::{ParameterPath, PATH_HELP};

use crate::error::{lib, InputError, WhirlError};

/// A validated rotor model and the TOML text it was read from.
#[pyclass(name = "Model", module = "whirl._whirl", frozen)]
pub struct PyModel {
    /// The validated model.
    pub model: Model,
    /// The model file's text (edits are made on it).
    text: String,
    /// The file it came from, when it came from one.
    file: Option<PathBuf>,
}

impl PyModel {
    /// Validates `text` as the command line does on loading a model: the schema and values,
    /// then that the rotor is held by two bearings at least.
    fn read(text: String, file: Option<PathBuf>) -> PyResult<PyModel> {
        let model = lib(Model::from_toml_str(&text, file.clone()))?;
        if let Err(whirl::Error::Input(mut e)) = model.check_supports() {
            e.file = file.clone();
            return Err(lib::<()>(Err(whirl::Error::Input(e))).unwrap_err());
        }
        Ok(PyModel { model, text, file })
    }

    /// The model file's text.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The file it came from, when it came from one.
    pub fn source(&self) -> Option<&PathBuf> {
        self.file.as_ref()
    }
}

#[pymethods]
impl PyModel {
    /// Reads and validates a model file.
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<PyModel> {
        let text = whirl::model::read_input(&path).map_err(|e| {
            WhirlError::new_err(format!(
                "cannot read the model file `{}`: {e}\n  help: check the path; \
                 examples/reference_rotor.toml is a complete model to start from",
                path.display()
            ))
        })?;
        PyModel::read(text, Some(path))
    }

    /// Validates a model given as TOML text; `file` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, file = None))]
    fn from_toml(text: String, file: Option<PathBuf>) -> PyResult<PyModel> {
        PyModel::read(text, file)
    }

    /// The same model with values set at parameter paths (`roller_bearing[*].clearance`),
    /// given as `(path, value)` pairs in order; a value is a number (SI), a bool, or text
    /// with a unit (`"20 um"`).
    fn with_values(&self, edits: Vec<(String, Bound<'_, PyAny>)>) -> PyResult<PyModel> {
        let mut doc: DocumentMut = self
            .text
            .parse()
            .map_err(|e| InputError::new_err(format!("the model's text is not TOML: {e}")))?;
        for (path, value) in &edits {
            let fail =
                |why: String| InputError::new_err(format!("`{path}`: {why}\n  help: {PATH_HELP}"));
            let parsed = ParameterPath::parse(path).map_err(fail)?;
            parsed
                .set(doc.as_table_mut(), &toml_value(path, value)?)
                .map_err(fail)?;
        }
        let text = doc.to_string();
        PyModel::read(text, None).map_err(|e| {
            let changes: Vec<String> = edits.iter().map(|(p, v)| format!("`{p}` = {v}")).collect();
            InputError::new_err(format!(
                "{} makes an invalid model: {}",
                changes.join(", "),
                e
            ))
        })
    }

    /// The model's name.
    #[getter]
    fn name(&self) -> &str {
        &self.model.name
    }

    /// The model file's text.
    #[getter]
    fn toml(&self) -> &str {
        &self.text
    }

    /// The file the model was read from, if any.
    #[getter]
    fn file(&self) -> Option<PathBuf> {
        self.file.clone()
    }

    /// The validated model in SI units, as JSON.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.model)
            .map_err(|e| WhirlError::new_err(format!("cannot encode the model: {e}")))
    }

    /// Valid but implausible values, one sentence each.
    fn warnings(&self) -> Vec<String> {
        self.model.warnings()
    }

    /// Number of nodes.
    #[getter]
    fn node_count(&self) -> usize {
        self.model.node_count()
    }

    /// Axial positions of the nodes, m.
    fn node_positions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.model.node_positions().into_pyarray(py)
    }

    /// What sits at each node, e.g. `disk; bearing A`.
    fn node_features(&self) -> Vec<String> {
        self.model.node_features()
    }

    /// Nodes that carry a bearing, ascending.
    fn bearing_nodes(&self) -> Vec<usize> {
        self.model.bearing_nodes()
    }

    /// Shaft length, m.
    #[getter]
    fn length(&self) -> f64 {
        self.model.length()
    }

    /// Mass of the shaft sections, kg.
    #[getter]
    fn shaft_mass(&self) -> f64 {
        self.model.shaft_mass()
    }

    fn __repr__(&self) -> String {
        format!(
            "Model({:?}: {} nodes, {} disks, {} linear and {} roller bearings)",
            self.model.name,
            self.model.node_count(),
            self.model.disks.len(),
            self.model.bearings.len(),
            self.model.roller_bearings.len()
        )
    }
}

/// A Python value as a TOML value for an edit: bool, whole number, number or text.
fn toml_value(path: &str, value: &Bound<'_, PyAny>) -> PyResult<toml_edit::Value> {
    if value.is_instance_of::<PyBool>() {
        Ok(value.extract::<bool>()?.into())
    } else if value.is_instance_of::<PyInt>() {
        Ok(value.extract::<i64>()?.into())
    } else if value.is_instance_of::<PyFloat>() {
        Ok(value.extract::<f64>()?.into())
    } else if value.is_instance_of::<PyString>() {
        Ok(value.extract::<String>()?.into())
    } else {
        Err(InputError::new_err(format!(
            "`{path}`: the value must be a number, a bool or text with a unit (\"20 um\"), not {}",
            value.get_type().name()?
        )))
    }
}
