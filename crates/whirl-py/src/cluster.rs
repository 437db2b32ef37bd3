//! A cluster's runner: a Python callable (the package's Dask helpers) handed a batch of
//! work, which yields `(index, json)` as each piece comes back from a worker. The library
//! types cross as exact JSON, so a result is the same to the bit wherever it ran.

use pyo3::prelude::*;
use serde::de::DeserializeOwned;

/// Hands `batch` to `runner` and each result it yields, read back as a `T`, to `done`;
/// `what` names a result in messages (`point`, `value`).
///
/// # Errors
/// [`whirl::Error::Internal`] when the runner fails or a result does not read back;
/// `done`'s errors.
pub fn run_on<B, T>(
    runner: &Py<PyAny>,
    batch: B,
    what: &str,
    mut done: impl FnMut(usize, T) -> whirl::Result<()>,
) -> whirl::Result<()>
where
    B: for<'py> IntoPyObject<'py>,
    T: DeserializeOwned,
{
    let failed = |e: PyErr| whirl::Error::Internal(format!("the cluster's runner failed: {e}"));
    Python::attach(|py| {
        let results = runner.call1(py, (batch,)).map_err(failed)?;
        for item in results.bind(py).try_iter().map_err(failed)? {
            let (k, json): (usize, String) = item.and_then(|x| x.extract()).map_err(failed)?;
            let result: T = serde_json::from_str(&json).map_err(|e| {
                whirl::Error::Internal(format!("a worker's {what} {k} does not read back: {e}"))
            })?;
            done(k, result)?;
        }
        Ok(())
    })
}
