//! Speeds written with their unit (`50Hz`, `3000rpm`, `0:800Hz:161`), read by the same
//! parser as the model file and the command line; a plain number is rad/s.

use numpy::{IntoPyArray, PyArray1};
use pyo3::prelude::*;
use whirl::units::{parse_quantity, parse_range, Dimension};

use crate::error::option;

/// One speed in rad/s from text such as `50Hz` or `3000rpm`.
#[pyfunction]
pub fn parse_speed(text: &str) -> PyResult<f64> {
    let w = parse_quantity(text, Dimension::AngularSpeed).map_err(|e| option("speed", e))?;
    if w < 0.0 {
        return Err(option(
            "speed",
            format!("`{text}`: the speed must not be negative"),
        ));
    }
    Ok(w)
}

/// Speeds in rad/s from a range `start:stop:count` such as `0:800Hz:161`.
#[pyfunction]
pub fn parse_speeds<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let w = parse_range(text, Dimension::AngularSpeed).map_err(|e| option("speeds", e))?;
    if w.first().is_some_and(|&w0| w0 < 0.0) {
        return Err(option(
            "speeds",
            format!("`{text}`: speeds must not be negative"),
        ));
    }
    Ok(w.into_pyarray(py))
}

/// The dimension named `time`, `length`, `force`, `frequency` or `speed`, and whether it is
/// given in Hz (a frequency).
fn dimension_of(name: &str) -> (Dimension, bool) {
    match name {
        "time" => (Dimension::Time, false),
        "length" => (Dimension::Length, false),
        "force" => (Dimension::Force, false),
        "frequency" => (Dimension::AngularSpeed, true),
        _ => (Dimension::AngularSpeed, false),
    }
}

/// A quantity in SI from text with a unit: `dimension` is `time`, `length`, `force`,
/// `frequency` (returned in Hz) or `speed` (rad/s); a plain number is SI (rad/s for a
/// frequency).
#[pyfunction(name = "parse_quantity")]
pub fn quantity(name: &str, text: &str, dimension: &str) -> PyResult<f64> {
    let (d, hz) = dimension_of(dimension);
    let x = parse_quantity(text, d).map_err(|e| option(name, e))?;
    Ok(if hz { whirl::units::rad_s_to_hz(x) } else { x })
}

/// Values in SI from a range `start:stop:count` such as `10um:120um:12`: `dimension` as for
/// [`quantity`] (`length`, `time`, `force`; a frequency range is in rad/s).
#[pyfunction(name = "parse_range")]
pub fn range<'py>(
    py: Python<'py>,
    name: &str,
    text: &str,
    dimension: &str,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = parse_range(text, dimension_of(dimension).0).map_err(|e| option(name, e))?;
    Ok(x.into_pyarray(py))
}
