//! Keyword arguments handed to the library's requests as given: each read by the library
//! by its name ([`whirl::given::Given`]), a keyword left None at the library's default.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};
use whirl::error::InputError;
use whirl::given::{Choice, Given, SetByName};

use crate::error::option;

/// A Python value as given: a bool, an int, a float, a str, or a list of them (a list, a
/// tuple, a numpy array).
fn given(name: &str, value: &Bound<'_, PyAny>) -> PyResult<Given> {
    // A bool is an int to Python: asked first.
    if let Ok(b) = value.cast::<PyBool>() {
        return Ok(Given::Flag(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return Ok(Given::Whole(value.extract()?));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(Given::Number(value.extract()?));
    }
    if let Ok(s) = value.cast::<PyString>() {
        return Ok(Given::Text(s.to_str()?.to_string()));
    }
    if let Ok(x) = value.extract::<f64>() {
        // numpy scalars.
        return Ok(Given::Number(x));
    }
    let not_an_option = || {
        option(
            name,
            format!(
                "expected a number, text or a list of them, got {}",
                value.get_type()
            ),
        )
    };
    let items = value.try_iter().map_err(|_| not_an_option())?;
    let list = items
        .map(|item| given(name, &item?))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(Given::List(list))
}

/// An error of the library about the keyword it names: "invalid `settle`: why", its help
/// on the next line.
pub fn keyword_error(e: InputError) -> PyErr {
    let help = e.help.map_or(String::new(), |h| format!("\n  help: {h}"));
    option(
        e.field.as_deref().unwrap_or_default(),
        format!("{}{help}", e.message),
    )
}

/// Sets each keyword of `options` that is not None on `request`, in order.
pub fn fill(options: &Bound<'_, PyDict>, request: &mut impl SetByName) -> PyResult<()> {
    for (key, value) in options.iter() {
        if value.is_none() {
            continue;
        }
        let name: String = key.extract()?;
        request
            .set(&name, &given(&name, &value)?)
            .map_err(keyword_error)?;
    }
    Ok(())
}

/// An option enum by the name every front end gives it, e.g. `hertz`.
pub fn choice<T: Choice>(name: &str, value: &str) -> PyResult<T> {
    T::from_name(name, value).map_err(keyword_error)
}
