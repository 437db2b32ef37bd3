//! Rotors saved by ROSS (`Rotor.save`) translated by the library's reader.

use pyo3::prelude::*;
use whirl::model::ross::from_ross_toml;

use crate::error::lib;

/// The whirl model file (TOML) of a ROSS file's text, and the notes on what the
/// translation dropped or changed; `name` names the model.
#[pyfunction]
pub fn ross_to_toml(text: &str, name: &str) -> PyResult<(String, Vec<String>)> {
    let import = lib(from_ross_toml(text, name))?;
    Ok((import.toml, import.notes))
}
