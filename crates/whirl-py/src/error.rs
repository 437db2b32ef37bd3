//! whirl's errors as Python exceptions, with the library's messages unchanged.

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyKeyboardInterrupt};
use pyo3::prelude::*;

create_exception!(
    _whirl,
    WhirlError,
    PyException,
    "Every error whirl raises: the message says what is wrong and how to fix it."
);
create_exception!(
    _whirl,
    InputError,
    WhirlError,
    "A model, model file or option that is wrong, located (`file:line:column: field:`) \
     when it comes from a file."
);
create_exception!(
    _whirl,
    NumericalError,
    WhirlError,
    "A computation that failed: a singular matrix, an iteration that did not converge, a \
     diverged simulation."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("WhirlError", py.get_type::<WhirlError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("NumericalError", py.get_type::<NumericalError>())?;
    Ok(())
}

/// A library error as the Python exception of its kind.
pub fn to_py(e: whirl::Error) -> PyErr {
    use whirl::Error as E;
    let message = e.to_string();
    match e {
        E::Input(_) | E::InvalidOption(_) | E::Unsupported(_) => InputError::new_err(message),
        E::Singular { .. } | E::NotConverged { .. } | E::Diverged { .. } => {
            NumericalError::new_err(message)
        }
        E::Interrupted(_) => PyKeyboardInterrupt::new_err(message),
        E::Io { .. } | E::Encode { .. } | E::Internal(_) => WhirlError::new_err(message),
    }
}

/// A library result with its error as a Python exception.
pub fn lib<T>(r: whirl::Result<T>) -> PyResult<T> {
    r.map_err(to_py)
}

/// An invalid option, named as the Python keyword: "invalid `speeds`: why".
pub fn option(name: &str, why: impl std::fmt::Display) -> PyErr {
    InputError::new_err(format!("invalid `{name}`: {why}"))
}

/// A library result whose errors about an option's field are named as the Python keyword
/// (the library names the field as the keyword: `cage_steps`): "invalid `cage_steps`: why".
pub fn keyword_lib<T>(r: whirl::Result<T>) -> PyResult<T> {
    r.map_err(|e| match &e {
        whirl::Error::Input(input) if input.file.is_none() && input.field.is_some() => {
            let help = input
                .help
                .as_ref()
                .map_or(String::new(), |h| format!("\n  help: {h}"));
            option(
                input.field.as_deref().unwrap_or_default(),
                format!("{}{help}", input.message),
            )
        }
        _ => to_py(e),
    })
}
