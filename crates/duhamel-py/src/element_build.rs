//! Building fresh core elements from their checked specifications ([`ElementSpec`]), for a
//! run: the Python elements are kept aside to collect their exceptions.

use pyo3::prelude::*;

use crate::callable::Built;
use crate::elements::{make, ElementSpec};

/// Builds fresh elements (initial state) of the specs a model holds.
pub(crate) fn build_all(py: Python<'_>, specs: &[Py<ElementSpec>]) -> PyResult<Built> {
    let mut built = Built {
        elements: Vec::new(),
        python: Vec::new(),
    };
    for spec in specs {
        let element = make(py, spec.get(), &mut built)?;
        built.elements.push(element);
    }
    Ok(built)
}

/// Builds the elements of a sequence of `_core.Element` specs.
pub(crate) fn build(py: Python<'_>, specs: &Bound<'_, PyAny>) -> PyResult<Built> {
    let mut built = Built {
        elements: Vec::new(),
        python: Vec::new(),
    };
    if specs.is_none() {
        return Ok(built);
    }
    for item in specs.try_iter()? {
        let item = item?;
        let element = make(py, item.cast::<ElementSpec>()?.get(), &mut built)?;
        built.elements.push(element);
    }
    Ok(built)
}
