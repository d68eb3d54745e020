//! Keyword arguments to [`Params`], derived from its serde representation rather than listed by
//! hand: a field added to `Params` becomes a keyword with its default without a change here.
//!
//! The names are the fields serde deserializes (in declaration order, read from the derived
//! `Deserialize` of each of `Params`' stage groups by [`field_names`]); the defaults are
//! `Params::default()` serialized, so every value looks exactly like the `parameters` object of
//! the JSON output (docs/json.md). A field serde leaves out of the serialized defaults (the
//! booleans written only when true) gets the value that deserializes back to `Params::default()`.

use std::sync::OnceLock;

use pyo3::exceptions::{PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyMapping, PyString};
use ridgeline::{ExperimentParams, FinishParams, FitParams, FrontEndParams, MethodParams, Params};
use serde::de::{self, Deserialize, Deserializer, Visitor};

use crate::errors;

/// The names of `T`'s fields, as its derived `Deserialize` hands them to `deserialize_struct`.
fn field_names<'de, T: Deserialize<'de>>() -> &'static [&'static str] {
    struct Probe(Option<&'static [&'static str]>);

    #[derive(Debug)]
    struct Stop;
    impl std::fmt::Display for Stop {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("field names read")
        }
    }
    impl std::error::Error for Stop {}
    impl de::Error for Stop {
        fn custom<M: std::fmt::Display>(_: M) -> Self {
            Stop
        }
    }

    impl<'de> Deserializer<'de> for &mut Probe {
        type Error = Stop;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Stop> {
            Err(Stop)
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Stop> {
            self.0 = Some(fields);
            Err(Stop)
        }
        serde::forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
            ignored_any
        }
    }

    let mut probe = Probe(None);
    let _ = T::deserialize(&mut probe);
    probe.0.unwrap_or(&[])
}

/// The keyword names, in `Params`' field order: the fields of its stage groups, which serde
/// flattens into one object (so `Params`' own `Deserialize` names no fields), then its own field
/// `fingerprint`.
pub fn names() -> &'static [&'static str] {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES.get_or_init(|| {
        [
            field_names::<FrontEndParams>(),
            field_names::<MethodParams>(),
            field_names::<FitParams>(),
            field_names::<FinishParams>(),
            field_names::<ExperimentParams>(),
            &["fingerprint"],
        ]
        .concat()
    })
}

/// `Params` from the dict of its serde representation. Each stage group is read from the whole
/// dict as a struct of its own (ignoring the other groups' keys), so each value is read as its
/// field asks, as for a flat struct: serde's flattening would first buffer every value by its
/// Python type and refuse what the field reads by conversion (a numpy integer for `k`, an int
/// for a boolean).
pub fn from_dict(dict: &Bound<'_, PyDict>) -> Result<Params, pythonize::PythonizeError> {
    let any = dict.as_any();
    let mut params = Params::default();
    params.front_end = pythonize::depythonize(any)?;
    params.method = pythonize::depythonize(any)?;
    params.fit = pythonize::depythonize(any)?;
    params.finish = pythonize::depythonize(any)?;
    params.experiments = pythonize::depythonize(any)?;
    params.fingerprint = match dict.get_item("fingerprint")? {
        Some(value) => pythonize::depythonize(&value)?,
        None => None,
    };
    Ok(params)
}

/// `params` as the dict of its serde representation, one key per keyword (fields serde skips
/// filled in from `fill`, the defaults).
pub fn to_dict<'py>(
    py: Python<'py>,
    params: &Params,
    fill: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let value = pythonize::pythonize(py, params)
        .map_err(|err| PyRuntimeError::new_err(format!("cannot convert parameters: {err}")))?;
    let serialized = value.cast_into::<PyDict>()?;
    let dict = PyDict::new(py);
    for &name in names() {
        if let Some(value) = serialized.get_item(name)? {
            dict.set_item(name, value)?;
        } else if let Some(value) = fill.map(|fill| fill.get_item(name)).transpose()?.flatten() {
            dict.set_item(name, value)?;
        }
    }
    Ok(dict)
}

/// The defaults, one entry per keyword (a fresh dict each call: callers may change it).
pub fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let dict = to_dict(py, &Params::default(), None)?;
    for &name in names() {
        if dict.contains(name)? {
            continue;
        }
        // Serde skipped the field because its value is the one the skip test passes: find the
        // value that deserializes back to the default. A field that reads 1 and 2 as different
        // values is a number (a boolean field reads any int by its truth, and a Python bool is
        // an int); the others are tried with booleans, None, the empty list and the empty string.
        let with = |candidate: &Bound<'_, PyAny>| -> Option<Params> {
            let trial = dict.copy().ok()?;
            trial.set_item(name, candidate).ok()?;
            from_dict(&trial).ok()
        };
        let reads = |candidate: &Bound<'_, PyAny>| {
            with(candidate).is_some_and(|params| params == Params::default())
        };
        let one = with(&1i64.into_pyobject(py)?.into_any());
        let two = with(&2i64.into_pyobject(py)?.into_any());
        let numeric = one.is_some() && two.is_some() && one != two;
        let candidates = if numeric {
            vec![
                0i64.into_pyobject(py)?.into_any(),
                0.0f64.into_pyobject(py)?.into_any(),
            ]
        } else {
            vec![
                PyBool::new(py, false).to_owned().into_any(),
                PyBool::new(py, true).to_owned().into_any(),
                py.None().into_bound(py),
                // The list before the string: a list field reads "" too, as an empty sequence.
                PyList::empty(py).into_any(),
                PyString::new(py, "").into_any(),
            ]
        };
        let found = candidates.into_iter().find(|candidate| reads(candidate));
        let Some(value) = found else {
            return Err(PyRuntimeError::new_err(format!(
                "no default found for parameter {name}"
            )));
        };
        dict.set_item(name, value)?;
    }
    Ok(dict)
}

/// The defaults, converted once per interpreter (not to be changed by callers).
pub fn cached_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    static DEFAULTS: pyo3::sync::PyOnceLock<Py<PyDict>> = pyo3::sync::PyOnceLock::new();
    let defaults = DEFAULTS.get_or_try_init(py, || defaults(py).map(Bound::unbind))?;
    Ok(defaults.bind(py).clone())
}

/// `Params` from keyword arguments over the defaults. A mapping given for a field whose value is a
/// mapping (`limits`, `threshold`) updates the default one, so `limits={"max_points": 10}` keeps
/// the other limits; for `fingerprint` (off by default) `True` is the preset's front end and a
/// mapping updates it, so `fingerprint={"enhancement": "smoothing"}` changes one setting. Unknown names are a `TypeError`, as for any Python function; values serde
/// cannot read, keys it would ignore and values out of range are a [`ParameterError`] naming the
/// field.
pub fn from_kwargs(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
    let defaults = cached_defaults(py)?;
    let Some(kwargs) = kwargs.filter(|kwargs| !kwargs.is_empty()) else {
        return Ok(Params::default());
    };
    let merged = defaults.copy()?;
    // (name, value merged over the default, value as given)
    let mut given = Vec::new();
    for (key, value) in kwargs.iter() {
        let name: String = key.extract()?;
        let Some(&name) = names().iter().find(|&&n| n == name) else {
            return Err(PyTypeError::new_err(format!(
                "unexpected keyword argument '{name}'{}",
                suggestion(&name)
            )));
        };
        let value = match (defaults.get_item(name)?, value.cast::<PyMapping>()) {
            (Some(default), Ok(mapping)) if default.is_instance_of::<PyDict>() => {
                let update = default.cast::<PyDict>()?.copy()?;
                update.update(mapping)?;
                update.into_any()
            }
            // A section that is off by default (`fingerprint`): `True` turns it on as its preset
            // has it, `False` off, and a mapping updates the preset's values.
            (Some(default), mapping) if default.is_none() => match preset_section(py, name)? {
                Some(preset) if value.is_instance_of::<PyBool>() => {
                    if value.is_truthy()? {
                        preset.into_any()
                    } else {
                        py.None().into_bound(py)
                    }
                }
                Some(preset) => match mapping {
                    Ok(mapping) => {
                        preset.update(mapping)?;
                        preset.into_any()
                    }
                    Err(_) => value.clone(),
                },
                None => value.clone(),
            },
            _ => value.clone(),
        };
        merged.set_item(name, &value)?;
        given.push((name, value, kwargs.get_item(name)?));
    }
    let params = match from_dict(&merged) {
        Ok(params) => params,
        Err(err) => return Err(locate(py, &defaults, &given, &err.to_string())),
    };
    check_keys(py, &params, &given)?;
    params.validate().map_err(|err| errors::to_py(py, err))?;
    Ok(params)
}

/// The preset's value of a section that is off by default, as a fresh dict: `fingerprint` from
/// [`Params::fingerprint`]; `None` for other fields.
fn preset_section<'py>(py: Python<'py>, name: &str) -> PyResult<Option<Bound<'py, PyDict>>> {
    let preset = to_dict(py, &Params::fingerprint(), None)?;
    match preset.get_item(name)? {
        Some(section) => Ok(section
            .cast::<PyDict>()
            .ok()
            .map(|dict| dict.copy())
            .transpose()?),
        None => Ok(None),
    }
}

/// The error for a set of keywords serde could not read, naming the first field that fails on
/// its own over the defaults.
fn locate(py: Python<'_>, defaults: &Bound<'_, PyDict>, given: &[Given<'_>], whole: &str) -> PyErr {
    for (name, value, _) in given {
        let trial = defaults.copy().and_then(|trial| {
            trial.set_item(name, value)?;
            Ok(trial)
        });
        if let Ok(trial) = trial {
            if let Err(err) = from_dict(&trial) {
                let shown = value
                    .repr()
                    .map_or_else(|_| String::from("?"), |repr| repr.to_string());
                return errors::parameter(
                    py,
                    format!("invalid parameter {name}: {err} (got {shown})"),
                    name,
                );
            }
        }
    }
    errors::parameter(py, format!("invalid parameters: {whole}"), "")
}

/// A keyword as given: its name, its value merged over the default, and the value itself.
type Given<'py> = (&'static str, Bound<'py, PyAny>, Option<Bound<'py, PyAny>>);

/// Refuses keys of a mapping that serde ignored (a misspelt `limits={"max_point": 10}` would
/// otherwise leave the limit at its default without a word).
fn check_keys(py: Python<'_>, params: &Params, given: &[Given<'_>]) -> PyResult<()> {
    let used = to_dict(py, params, None)?;
    for (name, _, original) in given {
        let Some(Ok(mapping)) = original.as_ref().map(|value| value.cast::<PyMapping>()) else {
            continue;
        };
        let Some(kept) = used.get_item(name)? else {
            continue;
        };
        let Ok(kept) = kept.cast::<PyDict>() else {
            continue;
        };
        for key in mapping.keys()?.iter() {
            if !kept.contains(&key)? {
                let known: Vec<String> = kept.keys().iter().map(|k| k.to_string()).collect();
                return Err(errors::parameter(
                    py,
                    format!(
                        "invalid parameter {name}.{key}: not a key of this {name} (its keys: {})",
                        known.join(", ")
                    ),
                    &format!("{name}.{key}"),
                ));
            }
        }
    }
    Ok(())
}

/// ", did you mean 'x'?" for the keyword closest to a misspelt one, when one is close.
fn suggestion(name: &str) -> String {
    fn distance(a: &str, b: &str) -> usize {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut previous = row[0];
            row[0] = i + 1;
            for (j, &cb) in b.iter().enumerate() {
                let substitution = previous + usize::from(ca != cb);
                previous = row[j + 1];
                row[j + 1] = substitution.min(row[j] + 1).min(row[j + 1] + 1);
            }
        }
        row[b.len()]
    }
    names()
        .iter()
        .map(|&known| (distance(name, known), known))
        .min()
        .filter(|&(d, _)| d <= 2)
        .map_or_else(String::new, |(_, known)| {
            format!("; did you mean '{known}'?")
        })
}
