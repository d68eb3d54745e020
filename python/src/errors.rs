//! [`ridgeline::Error`] as Python exceptions, each carrying the library's message.
//!
//! The exception classes are Python classes (`ridgeline/_errors.py`): they inherit from both
//! `RidgelineError` and the built-in class a Python user expects (`ValueError` for a bad value),
//! and they pickle with their attributes, so an error raised in a worker process of Dask or Spark
//! arrives whole. An unreadable file is the built-in `OSError` subclass for its `errno`
//! (`FileNotFoundError`, ...), with the file name set.

use pyo3::exceptions::{PyOSError, PyRuntimeError};
use pyo3::prelude::*;

/// Builds `ridgeline._errors.<class>(*args)` as a `PyErr`.
fn raise<'py>(py: Python<'py>, class: &str, args: impl pyo3::call::PyCallArgs<'py>) -> PyErr {
    let built = py
        .import("ridgeline._errors")
        .and_then(|module| module.getattr(class))
        .and_then(|class| class.call1(args));
    match built {
        Ok(instance) => PyErr::from_value(instance),
        Err(err) => err,
    }
}

/// A `ParameterError` (a `ValueError`) about `field` (empty when no one field is to blame).
pub fn parameter(py: Python<'_>, message: String, field: &str) -> PyErr {
    raise(py, "ParameterError", (message, field))
}

/// An error of the library as the Python exception for its kind.
pub fn to_py(py: Python<'_>, err: ridgeline::Error) -> PyErr {
    let message = err.to_string();
    match err {
        ridgeline::Error::Io { path, source } => {
            let errno = source.raw_os_error().unwrap_or(0);
            PyOSError::new_err((errno, message, path.to_string_lossy().into_owned()))
        }
        ridgeline::Error::Decode(_) => raise(py, "DecodeError", (message,)),
        ridgeline::Error::Limit {
            what,
            actual,
            limit,
            field,
        } => {
            // The library names the field (`limits.max_pixels`); from Python it is a key of the
            // `limits` keyword.
            let key = field.trim_start_matches("limits.");
            let message = ridgeline::Error::limit_sentence(
                what,
                actual,
                limit,
                &format!("it with limits={{\"{key}\": ...}}"),
            );
            raise(py, "LimitError", (message, what, actual, limit, field))
        }
        ridgeline::Error::PointParse { line, .. } => raise(py, "PointListError", (message, line)),
        ridgeline::Error::InvalidParam { field, .. } => parameter(py, message, field),
        ridgeline::Error::InvalidParams(_) => parameter(py, message, ""),
        _ => raise(py, "RidgelineError", (message,)),
    }
}

/// A panic inside the library (a bug: it never panics on input) as a `RuntimeError` asking for a
/// report, instead of pyo3's `PanicException`, which is not an `Exception`.
pub fn internal(payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default();
    PyRuntimeError::new_err(format!(
        "internal error in ridgeline, please report it: {message}"
    ))
}
