//! The front end's decisions (polarity and its confidence, the threshold used, the stroke width,
//! dropout mode) and the warnings of one trace, as the Python result gives them: the one place
//! that turns the library's typed fields into Python values.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use ridgeline::{Decisions, Warning};

/// The decisions as a dict shaped like the JSON's `decisions` (unrounded); `None` when the
/// library made none (a mask or a point list, which are not thresholded).
pub fn decisions<'py>(
    py: Python<'py>,
    decisions: Option<&Decisions>,
) -> PyResult<Bound<'py, PyAny>> {
    match decisions {
        Some(decisions) => pythonize::pythonize(py, decisions)
            .map_err(|err| pyo3::exceptions::PyRuntimeError::new_err(err.to_string())),
        None => Ok(py.None().into_bound(py)),
    }
}

/// The warnings as dicts `{"code", "message"}`, as in the JSON's `warnings`.
pub fn warnings<'py>(py: Python<'py>, warnings: &[Warning]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for warning in warnings {
        let dict = PyDict::new(py);
        dict.set_item("code", warning.code)?;
        dict.set_item("message", &warning.message)?;
        list.append(dict)?;
    }
    Ok(list)
}
