//! Building fresh engine elements (initial state) from the Python elements a model holds,
//! for a run: the Python elements are kept aside to collect their exceptions.

use duhamel_core::elements::{Element as CoreElement, Shifted};
use pyo3::prelude::*;

use crate::callable::Built;
use crate::element_type::{Element, Kind};
use crate::error::core_err;

/// A fresh engine element of `element` (a Python one also kept in `built.python`).
pub(crate) fn make(
    py: Python<'_>,
    element: &Element,
    built: &mut Built,
) -> PyResult<Box<dyn CoreElement>> {
    Ok(match &element.kind {
        Kind::Builtin { runtime, .. } => Box::new((**runtime).clone()),
        Kind::Python(def) => def.make(py, built),
        Kind::Shifted { inner, k0, c0 } => {
            let inner = make(py, inner.get(), built)?;
            Box::new(Shifted::new(inner, k0.clone(), c0.clone()).map_err(core_err)?)
        }
    })
}

/// Builds fresh engine elements of the elements a model holds.
pub(crate) fn build_all(py: Python<'_>, elements: &[Py<Element>]) -> PyResult<Built> {
    let mut built = Built {
        elements: Vec::new(),
        python: Vec::new(),
    };
    for element in elements {
        element.get().check_runnable()?;
        let made = make(py, element.get(), &mut built)?;
        built.elements.push(made);
    }
    Ok(built)
}

/// Builds the engine elements of a sequence of elements (None: none).
pub(crate) fn build(py: Python<'_>, elements: &Bound<'_, PyAny>) -> PyResult<Built> {
    if elements.is_none() {
        return Ok(Built {
            elements: Vec::new(),
            python: Vec::new(),
        });
    }
    let list: Vec<Py<Element>> = elements
        .try_iter()?
        .map(|item| Ok(item?.cast::<Element>()?.clone().unbind()))
        .collect::<PyResult<_>>()?;
    build_all(py, &list)
}
