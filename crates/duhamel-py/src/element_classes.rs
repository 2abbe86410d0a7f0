//! The Python classes of the built-in elements, one per entry of the core's registry
//! (`for_each_element!`: no line per element here), with their documentation and
//! signature; the internal element less a linear part; pickling.

use duhamel_core::elements::{Defined, Definition, ELEMENTS};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use crate::element_type::{Element, Kind};
use crate::values::to_python;

/// `k` (row-major `n x n`) as a numpy array.
pub(crate) fn square<'py>(py: Python<'py>, k: Vec<f64>, n: usize) -> PyResult<Bound<'py, PyAny>> {
    use numpy::{PyArray1, PyArrayMethods};
    Ok(PyArray1::from_vec(py, k).reshape([n, n])?.into_any())
}

/// The internal element `inner` minus `k0 x + c0 x'`.
pub(crate) fn shifted(
    py: Python<'_>,
    inner: Py<Element>,
    k0: Vec<f64>,
    c0: Vec<f64>,
) -> PyResult<Py<Element>> {
    let n = inner.get().local_dofs().len();
    for (name, m) in [("k0", &k0), ("c0", &c0)] {
        if m.len() != n * n {
            return Err(PyValueError::new_err(format!(
                "`{name}` must hold {n} x {n} = {} entries, got {}",
                n * n,
                m.len()
            )));
        }
    }
    let key = format!("Shifted@{:p}", inner.as_ptr());
    Py::new(
        py,
        Element {
            kind: Kind::Shifted { inner, k0, c0 },
            params: PyDict::new(py).unbind(),
            labelled: false,
            key,
        },
    )
}

/// `_core._shifted(inner, k0, c0)`: an element minus a linear part (pickling, the store).
#[pyfunction]
pub(crate) fn _shifted(
    py: Python<'_>,
    inner: Py<Element>,
    k0: Vec<f64>,
    c0: Vec<f64>,
) -> PyResult<Py<Element>> {
    shifted(py, inner, k0, c0)
}

/// `_core._element(cls, params)`: the element of class `cls` with `params` (pickling).
#[pyfunction]
pub(crate) fn _element<'py>(
    cls: &Bound<'py, PyType>,
    params: &Bound<'py, PyDict>,
) -> PyResult<Bound<'py, PyAny>> {
    cls.call((), Some(params))
}

macro_rules! element_classes {
    ($($name:ident: $def:ty),* $(,)?) => {
        $(
            #[doc = concat!("`duhamel.elements.", stringify!($name), "`")]
            #[pyclass(extends = Element, frozen, module = "duhamel.elements")]
            pub(crate) struct $name;

            #[pymethods]
            impl $name {
                #[new]
                #[pyo3(signature = (*args, **kwargs))]
                fn new(
                    py: Python<'_>,
                    args: &Bound<'_, PyTuple>,
                    kwargs: Option<&Bound<'_, PyDict>>,
                ) -> PyResult<PyClassInitializer<Self>> {
                    let base = Element::builtin::<$def>(py, args, kwargs)?;
                    Ok(PyClassInitializer::from(base).add_subclass($name))
                }
            }
        )*

        /// Adds every element class to the module, with its documentation and signature.
        pub(crate) fn add_classes(m: &Bound<'_, PyModule>) -> PyResult<()> {
            $(
                m.add_class::<$name>()?;
                describe(m, stringify!($name), <$def>::SIGNATURE, <$def>::DOC)?;
            )*
            Ok(())
        }

        /// The Python element of a definition (an instance of its class).
        pub(crate) fn from_defined(py: Python<'_>, def: Defined) -> PyResult<Py<Element>> {
            let params = def.params();
            let kwargs = PyDict::new(py);
            for (k, v) in &params {
                kwargs.set_item(k, nested_python(py, v)?)?;
            }
            let empty = PyTuple::empty(py);
            match def {
                $(Defined::$name(_) => {
                    let base = Element::builtin::<$def>(py, &empty, Some(&kwargs))?;
                    let made = Py::new(py, PyClassInitializer::from(base).add_subclass($name))?;
                    Ok(made.into_bound(py).into_super().unbind())
                })*
            }
        }
    };
}

duhamel_core::for_each_element!(element_classes);

/// A parameter's JSON value as a Python value, a wrapper's parts (definitions, `"type"`
/// tagged) as their elements.
fn nested_python<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    let is_def = |v: &Value| matches!(v, Value::Object(o) if o.contains_key("type"));
    let element = |v: &Value| -> PyResult<Bound<'py, PyAny>> {
        let def: Defined = serde_json::from_value(v.clone())
            .map_err(|e| PyValueError::new_err(format!("a part's data: {e}")))?;
        Ok(from_defined(py, def)?.into_bound(py).into_any())
    };
    match v {
        v if is_def(v) => element(v),
        Value::Array(items) if !items.is_empty() && items.iter().all(is_def) => {
            let parts = items.iter().map(element).collect::<PyResult<Vec<_>>>()?;
            Ok(PyTuple::new(py, parts)?.into_any())
        }
        _ => to_python(py, v),
    }
}

/// Sets a class's `__doc__` and `__signature__` (from the signature's text).
fn describe(m: &Bound<'_, PyModule>, name: &str, signature: &str, doc: &str) -> PyResult<()> {
    let py = m.py();
    let cls = m.getattr(name)?;
    cls.setattr("__doc__", doc)?;
    let inner = signature
        .trim()
        .trim_start_matches('(')
        .trim_end_matches(')');
    let code = std::ffi::CString::new(format!(
        "__import__('inspect').signature(lambda {inner}: None)"
    ))?;
    let sig = py.eval(&code, None, None)?;
    cls.setattr("__signature__", sig)?;
    Ok(())
}

/// The names and signatures of the built-in elements.
#[pyfunction]
pub(crate) fn element_names() -> Vec<(&'static str, &'static str)> {
    ELEMENTS.iter().map(|(n, s, _, _)| (*n, *s)).collect()
}
