//! `duhamel.elements.Callable`: the Python-defined element's class and definition.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::callable::{ArcElement, Built, PyElement};
use duhamel_core::elements::Element;

/// A Python element's definition: its dofs, functions and initial internal variables.
pub(crate) struct CallableDef {
    pub(crate) dofs: Vec<usize>,
    pub(crate) func: Py<PyAny>,
    pub(crate) jacobian: Option<Py<PyAny>>,
    pub(crate) state: Option<Vec<f64>>,
    /// Whether a dof is a label (a placeholder index until resolved).
    pub(crate) labelled: bool,
}

impl CallableDef {
    /// A fresh engine element of this definition (kept in `built.python` for its errors).
    pub(crate) fn make(&self, py: Python<'_>, built: &mut Built) -> Box<dyn Element> {
        let element = std::sync::Arc::new(PyElement::new(
            self.dofs.clone(),
            self.func.clone_ref(py),
            self.jacobian.as_ref().map(|j| j.clone_ref(py)),
            self.state.clone(),
        ));
        built.python.push(element.clone());
        Box::new(ArcElement(element))
    }
}

/// Escape hatch: ``fn(x, v, t)`` returns the restoring force at `dofs` (whole arrays of the
/// local displacements and velocities); ``jacobian(x, v, t)`` may return ``(dr/dx, dr/dv)``
/// (square matrices), otherwise tangents come from finite differences. Called with the GIL once
/// per evaluation, never per degree of freedom.
///
/// **Your own hysteresis** (internal variables, OpenSees' trial/commit protocol): give `state`,
/// the initial values of the element's internal variables (a 1-D array: plastic deformation,
/// back force, the deformation they were committed at, ...). Then ``fn(x, v, t, state)``
/// receives the variables *committed at the start of the current step* (a copy: do not keep
/// it) and returns ``(r, trial_state)``: the force at the trial state ``(x, v)`` reached from
/// them, and the variables there. ``jacobian(x, v, t, state)`` likewise. The integrator calls
/// `fn` as often as its Newton iterations need, always from the committed variables, and
/// commits the trial variables of the step's end state once per accepted step (also after every
/// substep of a subdivided step); so `fn` must be a pure function of its arguments. The
/// committed force history is in ``Solution.elements`` (docs/structural.md).
///
/// Parameters
/// ----------
/// dofs : int, dof label or sequence of them
///     The dofs the element acts on (its local order).
/// fn : callable
///     ``fn(x, v, t)`` (or ``fn(x, v, t, state)``): the local restoring force.
/// jacobian : callable, optional
///     Its tangents ``(dr/dx, dr/dv)``.
/// state : sequence of float, optional
///     The initial internal variables of a path-dependent element.
///
/// Examples
/// --------
/// >>> import numpy as np, duhamel
/// >>> hysteretic = duhamel.elements.Callable([0], lambda x, v, t: 0.1 * np.tanh(x / 1e-3))
/// >>> def elastoplastic(x, v, t, state, k=100.0, fy=1.0):
/// ...     x_c, plastic = state                    # committed deformation and plastic part
/// ...     trial = k * (x[0] - plastic)            # elastic predictor
/// ...     if abs(trial) > fy:                     # return to the yield surface
/// ...         plastic = x[0] - np.sign(trial) * fy / k
/// ...         trial = np.sign(trial) * fy
/// ...     return np.array([trial]), np.array([x[0], plastic])
/// >>> epp = duhamel.elements.Callable([0], elastoplastic, state=[0.0, 0.0])
#[pyclass(extends = crate::element_type::Element, frozen, module = "duhamel.elements")]
pub(crate) struct Callable;

#[pymethods]
impl Callable {
    #[new]
    #[pyo3(signature = (dofs, r#fn, jacobian=None, state=None))]
    fn new(
        py: Python<'_>,
        dofs: Bound<'_, PyAny>,
        r#fn: Bound<'_, PyAny>,
        jacobian: Option<Bound<'_, PyAny>>,
        state: Option<Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<Self>> {
        let (dofs, func) = if dofs.is_callable() && !r#fn.is_callable() {
            crate::arguments::warn(
                py,
                "Callable(fn, dofs) is deprecated: the dofs come first: \
                 Callable(dofs, fn, jacobian=None, state=None)",
            )?;
            (r#fn, dofs)
        } else {
            (dofs, r#fn)
        };
        if !func.is_callable() {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "`fn` must be callable, got {}",
                func.get_type().name()?
            )));
        }
        if let Some(j) = jacobian.as_ref().filter(|j| !j.is_none()) {
            if !j.is_callable() {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "`jacobian` must be callable, got {}",
                    j.get_type().name()?
                )));
            }
        }
        let jacobian = jacobian.filter(|j| !j.is_none());
        let (indices, shown, labelled) = callable_dofs(py, &dofs)?;
        let state_values = match state.as_ref().filter(|s| !s.is_none()) {
            None => None,
            Some(s) => {
                let values: Vec<f64> = crate::values::to_value(s, "state").and_then(|v| {
                    serde_json::from_value::<Vec<f64>>(v).map_err(|_| {
                        PyValueError::new_err("`state` must be a 1-D array of numbers")
                    })
                })?;
                if values.is_empty() {
                    return Err(PyValueError::new_err(
                        "`state` must have at least one internal variable (or be None)",
                    ));
                }
                Some(values)
            }
        };
        let params = pyo3::types::PyDict::new(py);
        params.set_item("dofs", shown)?;
        params.set_item("fn", &func)?;
        params.set_item("jacobian", jacobian.as_ref())?;
        params.set_item(
            "state",
            state_values
                .as_ref()
                .map(|s| PyTuple::new(py, s.iter().copied()))
                .transpose()?,
        )?;
        let def = CallableDef {
            dofs: indices,
            func: func.unbind(),
            jacobian: jacobian.map(|j| j.unbind()),
            state: state_values,
            labelled,
        };
        let base = crate::element_type::Element::python(py, def, params);
        Ok(PyClassInitializer::from(base).add_subclass(Callable))
    }
}

/// A `Callable`'s dofs: indices (labels as placeholders), the tuple shown, whether labelled.
fn callable_dofs<'py>(
    py: Python<'py>,
    dofs: &Bound<'py, PyAny>,
) -> PyResult<(Vec<usize>, Bound<'py, PyTuple>, bool)> {
    let items: Vec<Bound<'py, PyAny>> =
        if dofs.is_instance_of::<pyo3::types::PyString>() || !dofs.hasattr("__iter__")? {
            vec![dofs.clone()]
        } else {
            dofs.try_iter()?.collect::<PyResult<_>>()?
        };
    if items.is_empty() {
        return Err(PyValueError::new_err(
            "`dofs` must be a non-empty list of dof indices or labels",
        ));
    }
    let mut labels: Vec<Bound<'py, PyAny>> = Vec::new();
    let mut out = Vec::new();
    for (k, item) in items.iter().enumerate() {
        let is_label = item.is_instance_of::<pyo3::types::PyString>()
            || item.cast::<PyTuple>().is_ok_and(|t| t.len() == 2);
        if is_label {
            let p = labels.iter().position(|l| l.eq(item).unwrap_or(false));
            let p = p.unwrap_or_else(|| {
                labels.push(item.clone());
                labels.len() - 1
            });
            out.push((1usize << 40) + p);
        } else {
            out.push(crate::arrays::dof_index(item, &format!("dofs[{k}]"))?);
        }
    }
    let mut seen = out.clone();
    seen.sort_unstable();
    seen.dedup();
    if seen.len() != out.len() {
        return Err(PyValueError::new_err(format!(
            "`dofs` has duplicates: {}",
            PyTuple::new(py, &items)?.repr()?
        )));
    }
    Ok((out, PyTuple::new(py, items)?, !labels.is_empty()))
}
