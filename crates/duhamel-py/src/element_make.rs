//! An element made from a Python call: its arguments bound by the definition's signature,
//! the dofs and labels taken apart, the definition checked (serde, then the engine
//! element's own checks), the parameters kept for attributes and equality.

use duhamel_core::elements::{Defined, Definition};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use serde_json::{Map, Value};

use crate::arguments::{bind, Signature};
use crate::callable_class::CallableDef;
use crate::element_dofs::{dof_display, dof_value};
use crate::element_type::{Element, Kind, DOF_PARAMS};
use crate::error::core_err;
use crate::values::{to_python, to_value};

impl Element {
    /// A built-in element `D` from a Python call's arguments.
    pub(crate) fn builtin<D: Definition>(
        py: Python<'_>,
        args: &Bound<'_, PyTuple>,
        kwargs: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self>
    where
        Defined: From<D>,
    {
        let sig = Signature::parse(D::SIGNATURE);
        let given = bind(
            py,
            D::NAME,
            &sig,
            D::LEGACY,
            (D::rename, D::LEGACY_DEFAULTS),
            args,
            kwargs,
        )?;
        let mut map = Map::new();
        let mut labels: Vec<Bound<'_, PyAny>> = Vec::new();
        let mut parts = Vec::new();
        for (key, value) in given.iter() {
            let key: String = key.extract()?;
            if DOF_PARAMS.contains(&key.as_str()) {
                let v = dof_value(&value, &key, &mut labels)?;
                map.insert(key, v);
            } else if let Some(found) = elements_in(&value)? {
                parts.push((key, found));
            } else {
                let v = to_value(&value, &key)?;
                map.insert(key, v);
            }
        }
        for (key, found) in parts {
            let v = parts_value(D::NAME, &key, found, &given, &map)?;
            map.insert(key, v);
        }
        let def = Defined::from(definition::<D>(map)?);
        let runtime = def.build().map_err(core_err)?;
        let params = PyDict::new(py);
        let canonical = def.params();
        for p in &sig.params {
            let value = match (
                DOF_PARAMS.contains(&p.name.as_str()),
                given.get_item(&p.name)?,
            ) {
                (true, Some(v)) if !labels.is_empty() => dof_display(&v)?,
                (false, Some(v)) if elements_in(&v)?.is_some() => dof_display(&v)?,
                _ => match canonical.get(&p.name) {
                    Some(v) => to_python(py, v)?,
                    None => py.None().into_bound(py),
                },
            };
            params.set_item(&p.name, value)?;
        }
        let key = key_of(py, D::NAME, &params)?;
        Ok(Element {
            kind: Kind::Builtin {
                def: Box::new(def),
                runtime: Box::new(runtime),
            },
            params: params.unbind(),
            labelled: !labels.is_empty(),
            key,
        })
    }

    /// A Python `Callable` element.
    pub(crate) fn python(py: Python<'_>, def: CallableDef, params: Bound<'_, PyDict>) -> Self {
        let labelled = def.labelled;
        let key = format!("Callable@{:p}", def.func.as_ptr());
        let _ = py;
        Element {
            kind: Kind::Python(def),
            params: params.unbind(),
            labelled,
            key,
        }
    }
}

/// The elements `value` holds, when it is an element (`Some((vec![e], false))`) or a
/// non-empty sequence of elements only (`Some((items, true))`): the parts of a wrapper.
fn elements_in<'py>(
    value: &Bound<'py, PyAny>,
) -> PyResult<Option<(Vec<Bound<'py, Element>>, bool)>> {
    if let Ok(e) = value.cast::<Element>() {
        return Ok(Some((vec![e.clone()], false)));
    }
    if !(value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>()) {
        return Ok(None);
    }
    let items: Vec<Bound<'py, PyAny>> = value.try_iter()?.collect::<PyResult<_>>()?;
    if items.is_empty() || !items.iter().all(|v| v.cast::<Element>().is_ok()) {
        return Ok(None);
    }
    let items = items
        .into_iter()
        .map(|v| Ok(v.cast_into::<Element>()?))
        .collect::<PyResult<Vec<_>>>()?;
    Ok(Some((items, true)))
}

/// The definitions of the parts `found` of the wrapper `name` (parameter `key`), each
/// checked to act on the wrapper's dofs as given (indices or the same labels) and written
/// with the wrapper's dof values (`map`: its placeholders for labels), nested parts too.
fn parts_value(
    name: &str,
    key: &str,
    (found, sequence): (Vec<Bound<'_, Element>>, bool),
    given: &Bound<'_, PyDict>,
    map: &Map<String, Value>,
) -> PyResult<Value> {
    let py = given.py();
    let mut out = Vec::new();
    for (k, part) in found.iter().enumerate() {
        let label = if sequence {
            format!("{key}[{k}]")
        } else {
            key.to_string()
        };
        let this = part.get();
        let Kind::Builtin { def, .. } = &this.kind else {
            return Err(PyTypeError::new_err(format!(
                "{name}(): `{label}` must be a built-in uniaxial material element, got a {}",
                this.name()
            )));
        };
        let params = this.params.bind(py);
        for dof in ["i", "j"] {
            let mine = given
                .get_item(dof)?
                .unwrap_or_else(|| py.None().into_bound(py));
            let theirs = params
                .get_item(dof)?
                .unwrap_or_else(|| py.None().into_bound(py));
            if !mine.eq(&theirs)? {
                return Err(PyValueError::new_err(format!(
                    "{name}(): `{label}` acts on {dof}={}, the {name} on {dof}={}: a part acts \
                     on its wrapper's dofs `i, j`",
                    theirs.repr()?,
                    mine.repr()?
                )));
            }
        }
        let mut value =
            serde_json::to_value(&**def).map_err(|e| PyValueError::new_err(e.to_string()))?;
        retarget(&mut value, map);
        out.push(value);
    }
    Ok(if sequence {
        Value::Array(out)
    } else {
        out.pop().unwrap_or(Value::Null)
    })
}

/// Sets the dofs `i`, `j` of a part's definition (and of its own parts) to the wrapper's.
fn retarget(value: &mut Value, map: &Map<String, Value>) {
    match value {
        Value::Object(obj) if obj.contains_key("type") => {
            for dof in ["i", "j"] {
                obj.insert(dof.into(), map.get(dof).cloned().unwrap_or(Value::Null));
            }
            for (k, v) in obj.iter_mut() {
                if k != "i" && k != "j" {
                    retarget(v, map);
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(|v| retarget(v, map)),
        _ => {}
    }
}

/// `(got, expected)` of serde's "invalid length 2, expected an array of length 3", the
/// expected count in words.
fn lengths(message: &str) -> Option<(String, String)> {
    let rest = message.strip_prefix("invalid length ")?;
    let (got, tail) = rest.split_once(',')?;
    let want = tail.trim().rsplit(' ').next()?;
    let words = [
        "zero", "one", "two", "three", "four", "five", "six", "seven", "eight",
    ];
    let want = want
        .parse::<usize>()
        .ok()
        .and_then(|n| words.get(n).map(|w| w.to_string()))
        .unwrap_or_else(|| want.to_string());
    Some((got.to_string(), want))
}

/// The definition `D` from its parameters; a serde error names the parameter.
fn definition<D: Definition>(params: Map<String, Value>) -> PyResult<D> {
    let name = D::NAME;
    serde_path_to_error::deserialize::<_, D>(Value::Object(params)).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner().to_string();
        let text = match (path.as_str(), lengths(&inner)) {
            ("" | ".", _) => format!("{name}(): {inner}"),
            (p, Some((got, want))) => format!("{name}(): `{p}` must hold {want} values, got {got}"),
            (p, None) => format!("{name}(): `{p}`: {inner}"),
        };
        // a value of the right type outside the choices is a bad value, not a bad type
        let value = ["unknown variant", "invalid value", "invalid length"];
        if value.iter().any(|v| inner.starts_with(v)) {
            PyValueError::new_err(text)
        } else {
            PyTypeError::new_err(text)
        }
    })
}

/// The canonical text of `name` with `params` (equality and hashing).
fn key_of(py: Python<'_>, name: &str, params: &Bound<'_, PyDict>) -> PyResult<String> {
    let repr = params.repr()?;
    let _ = py;
    Ok(format!("{name}{repr}"))
}
