//! The front end's decisions (polarity and its confidence, threshold method and level or window,
//! dropout mode) and the library's warnings for one trace: the one place the Python result reads
//! them from.
//!
//! The library writes them into its JSON document, as top-level `decisions` (an object) and
//! `warnings` (a list of strings), and this reads them back from there; a document without them
//! gives an empty dict and an empty list. When `ridgeline::Trace` carries them as typed fields,
//! [`Report::of`] is the function to change (and it need not write the JSON any more).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde_json::Value;

/// Decisions and warnings of one trace.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Report {
    /// The `decisions` object, or an empty object.
    pub decisions: serde_json::Map<String, Value>,
    /// The `warnings`, each as its text.
    pub warnings: Vec<String>,
}

impl Report {
    /// Reads the report out of a JSON document written by the library.
    pub fn of(document: &str) -> Report {
        let Ok(Value::Object(mut top)) = serde_json::from_str::<Value>(document) else {
            return Report::default();
        };
        let decisions = match top.remove("decisions") {
            Some(Value::Object(decisions)) => decisions,
            _ => serde_json::Map::new(),
        };
        let warnings = match top.remove("warnings") {
            Some(Value::Array(items)) => items
                .into_iter()
                .map(|item| match item {
                    Value::String(text) => text,
                    // A structured warning: its message when it has one, else the whole object.
                    Value::Object(ref fields) => match fields.get("message") {
                        Some(Value::String(text)) => text.clone(),
                        _ => item.to_string(),
                    },
                    other => other.to_string(),
                })
                .collect(),
            _ => Vec::new(),
        };
        Report {
            decisions,
            warnings,
        }
    }

    /// The decisions as a Python dict.
    pub fn decisions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        match pythonize::pythonize(py, &self.decisions) {
            Ok(value) => Ok(value),
            Err(_) => Ok(PyDict::new(py).into_any()),
        }
    }
}
