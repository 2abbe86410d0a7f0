//! Python values and the JSON values of the element definitions (serde), both ways: the
//! parameters a Python call gives become the definition's fields, and back for attributes.

use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::{Map, Number, Value};

/// `obj` as a JSON value; `name` (the parameter) names what is wrong. Numbers must be
/// finite; sequences (tuples, lists, arrays) become arrays; an object with a `_to_value()`
/// method (an element, a speed law) gives its own.
pub(crate) fn to_value(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Value> {
    nested(obj, name, 0)
}

/// How deep parameters nest (a list of tables of rows...): deeper is refused, never a stack
/// overflow.
const DEPTH: usize = 16;

fn nested(obj: &Bound<'_, PyAny>, name: &str, depth: usize) -> PyResult<Value> {
    if depth > DEPTH {
        return Err(PyValueError::new_err(format!(
            "`{name}` nests more than {DEPTH} levels of sequences"
        )));
    }
    let to_value = |o: &Bound<'_, PyAny>, n: &str| nested(o, n, depth + 1);
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        return int(obj, name);
    }
    if obj.is_instance_of::<PyFloat>() {
        return float(obj.extract::<f64>()?, name);
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.to_str()?.to_owned()));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut map = Map::new();
        for (k, v) in d.iter() {
            let key: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("`{name}`: keys must be strings")))?;
            let value = to_value(&v, &format!("{name}[{key:?}]"))?;
            map.insert(key, value);
        }
        return Ok(Value::Object(map));
    }
    if obj.hasattr("_to_value")? {
        let text: String = obj.call_method0("_to_value")?.extract()?;
        return serde_json::from_str(&text)
            .map_err(|e| PyValueError::new_err(format!("`{name}`: {e}")));
    }
    if obj.hasattr("tolist")? && obj.hasattr("dtype")? {
        // a numpy array or scalar
        let kind: String = obj.getattr("dtype")?.getattr("kind")?.extract()?;
        if !matches!(kind.as_str(), "f" | "i" | "u" | "b") {
            return Err(PyTypeError::new_err(format!(
                "`{name}` must hold numbers, got an array of dtype {}",
                obj.getattr("dtype")?.str()?
            )));
        }
        // as float64 first: a wider float (longdouble) lists as itself
        let plain = if kind == "f" {
            obj.py()
                .import("numpy")?
                .call_method1("asarray", (obj, "float64"))?
                .call_method0("tolist")?
        } else {
            obj.call_method0("tolist")?
        };
        if plain.hasattr("dtype")? {
            return Err(PyTypeError::new_err(format!(
                "`{name}` must hold numbers, got {}",
                obj.get_type().name()?
            )));
        }
        return to_value(&plain, name);
    }
    if obj.hasattr("__index__")? && !obj.hasattr("__float__")? {
        return int(obj, name);
    }
    if obj.is_instance_of::<PyTuple>() || obj.is_instance_of::<PyList>() {
        let items = obj
            .try_iter()?
            .map(|item| to_value(&item?, name))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    if let Ok(v) = obj.extract::<f64>() {
        return float(v, name);
    }
    Err(PyTypeError::new_err(format!(
        "`{name}` must be a number, a sequence of numbers or None, got {}",
        obj.get_type().name()?
    )))
}

fn int(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Value> {
    if let Ok(v) = obj.extract::<u64>() {
        return Ok(Value::Number(v.into()));
    }
    if let Ok(v) = obj.extract::<i64>() {
        return Ok(Value::Number(v.into()));
    }
    Err(PyValueError::new_err(format!(
        "`{name}` is out of range: {}",
        obj.repr()?
    )))
}

fn float(v: f64, name: &str) -> PyResult<Value> {
    Number::from_f64(v)
        .map(Value::Number)
        .ok_or_else(|| PyValueError::new_err(format!("`{name}` must be finite, got {v}")))
}

/// A JSON value as a Python value: arrays as tuples, objects as dicts.
pub(crate) fn to_python<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(items) => {
            let items = items
                .iter()
                .map(|v| to_python(py, v))
                .collect::<PyResult<Vec<_>>>()?;
            PyTuple::new(py, items)?.into_any()
        }
        Value::Object(map) => {
            let d = PyDict::new(py);
            for (k, v) in map {
                d.set_item(k, to_python(py, v)?)?;
            }
            d.into_any()
        }
    })
}

/// `value` as JSON text (floats written to round-trip exactly).
pub(crate) fn to_json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The value of JSON text written by [`to_json`]; `what` names it in the error.
pub(crate) fn from_json<T: serde::de::DeserializeOwned>(text: &str, what: &str) -> PyResult<T> {
    serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("{what}'s data: {e}")))
}
