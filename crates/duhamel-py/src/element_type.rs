//! The base class `Element` of `duhamel.elements`: what an element is (a built-in
//! definition with its engine element, a Python `Callable`, or an internal element less a
//! linear part), its parameters as given, and the checks every use of it shares. Its
//! Python methods are in `definitions.rs`.

use duhamel_core::elements::{Defined, Element as CoreElement, Runtime};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::callable_class::CallableDef;

/// The parameters that say where an element acts.
pub(crate) const DOF_PARAMS: [&str; 3] = ["i", "j", "dofs"];

/// What an element is.
pub(crate) enum Kind {
    /// A built-in element: its definition and engine element (checked when made).
    Builtin {
        def: Box<Defined>,
        runtime: Box<Runtime>,
    },
    /// A Python `Callable`.
    Python(CallableDef),
    /// An element without its linear part (made by the planner, never by users).
    Shifted {
        inner: Py<Element>,
        k0: Vec<f64>,
        c0: Vec<f64>,
    },
}

/// A force element of `duhamel.elements` (the base class).
#[pyclass(subclass, frozen, module = "duhamel.elements", name = "Element")]
pub(crate) struct Element {
    pub(crate) kind: Kind,
    /// The parameters (dof labels as given), in signature order.
    pub(crate) params: Py<PyDict>,
    /// Whether a dof is a label, not an index.
    pub(crate) labelled: bool,
    /// The parameters as canonical JSON (equality, hashing).
    pub(crate) key: String,
}

impl Element {
    /// The class name.
    pub(crate) fn name(&self) -> &'static str {
        match &self.kind {
            Kind::Builtin { def, .. } => def.name(),
            Kind::Python(_) => "Callable",
            Kind::Shifted { .. } => "Shifted",
        }
    }

    /// The engine element's dofs, in its local order.
    pub(crate) fn local_dofs(&self) -> Vec<usize> {
        match &self.kind {
            Kind::Builtin { runtime, .. } => runtime.dofs().to_vec(),
            Kind::Python(d) => d.dofs.clone(),
            Kind::Shifted { inner, .. } => inner.get().local_dofs(),
        }
    }

    /// An error unless the element can run (its dofs are indices).
    pub(crate) fn check_runnable(&self) -> PyResult<()> {
        self.check_resolved()
    }

    pub(crate) fn check_resolved(&self) -> PyResult<()> {
        if self.labelled {
            return Err(PyValueError::new_err(format!(
                "this {} names its dofs by labels: add it to a System (which resolves them) \
                 before it is run or evaluated",
                self.name()
            )));
        }
        Ok(())
    }

    pub(crate) fn definition(&self) -> Option<&Defined> {
        match &self.kind {
            Kind::Builtin { def, .. } => Some(def),
            _ => None,
        }
    }
}
