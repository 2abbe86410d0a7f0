//! Where an element acts, as its Python arguments give it: dof indices, `None` for the
//! ground, dof labels (names, `(node, component)` pairs: placeholder indices until the
//! element is added to a system, which resolves them).

use pyo3::prelude::*;
use pyo3::types::PyTuple;
use serde_json::Value;

/// Placeholder indices of dof labels until the element is added to a system (far beyond
/// any model, distinct per label).
const LABEL_BASE: u64 = 1 << 40;

/// A dof parameter's value: an index, None (the ground), a label (a placeholder index
/// until resolved), or for `dofs` a sequence of them (an index alone is a 1-tuple).
pub(crate) fn dof_value<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
    labels: &mut Vec<Bound<'py, PyAny>>,
) -> PyResult<Value> {
    if name == "dofs" && !is_label(value)? && !value.is_none() && value.hasattr("__len__")? {
        let items = value
            .try_iter()?
            .enumerate()
            .map(|(k, item)| one_dof(&item?, &format!("dofs[{k}]"), labels))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    let one = one_dof(value, name, labels)?;
    Ok(if name == "dofs" {
        Value::Array(vec![one])
    } else {
        one
    })
}

fn one_dof<'py>(
    value: &Bound<'py, PyAny>,
    name: &str,
    labels: &mut Vec<Bound<'py, PyAny>>,
) -> PyResult<Value> {
    if value.is_none() {
        return Ok(Value::Null);
    }
    if is_label(value)? {
        let k = match labels.iter().position(|l| l.eq(value).unwrap_or(false)) {
            Some(k) => k,
            None => {
                labels.push(value.clone());
                labels.len() - 1
            }
        };
        return Ok(Value::Number((LABEL_BASE + k as u64).into()));
    }
    crate::arrays::dof_index(value, name).map(|d| Value::Number((d as u64).into()))
}

/// Whether `value` is a dof label: a string or a `(node, component)` pair.
pub(crate) fn is_label(value: &Bound<'_, PyAny>) -> PyResult<bool> {
    if value.is_instance_of::<pyo3::types::PyString>() {
        return Ok(true);
    }
    if let Ok(t) = value.cast::<PyTuple>() {
        if t.len() == 2 {
            let node = t.get_item(0)?;
            let comp = t.get_item(1)?;
            return Ok(node.is_instance_of::<pyo3::types::PyInt>()
                && !node.is_instance_of::<pyo3::types::PyBool>()
                && comp.is_instance_of::<pyo3::types::PyString>());
        }
    }
    Ok(false)
}

/// A dof parameter as the attribute shows it (`dofs` as a tuple).
pub(crate) fn dof_display<'py>(value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    if value.is_instance_of::<pyo3::types::PyList>() {
        return Ok(
            PyTuple::new(value.py(), value.try_iter()?.collect::<PyResult<Vec<_>>>()?)?.into_any(),
        );
    }
    Ok(value.clone())
}
