//! The element classes of `duhamel.elements`: each built-in element of the core's registry
//! (`registry.rs`) as a Python class, generated from the list (no line per element here),
//! all sharing the base class `Element` and its methods: parameters as attributes,
//! `replace`, pickling, equality, dof labels resolved when the element is added to a system,
//! and what the planner asks of an element (`_passive`, `_linear`, `_tangent_bound`,
//! `_directions`, `_remainder`, `_stored_energy`).

use duhamel_core::elements::{Defined, Element as CoreElement};
use pyo3::exceptions::{PyAttributeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple, PyType};

use crate::arguments::warn;
use crate::element_classes::{from_defined, shifted, square};
use crate::element_dofs::is_label;
use crate::element_type::{Element, Kind, DOF_PARAMS};

#[pymethods]
impl Element {
    /// The value of parameter `name`; old parameter names are still read, with a warning.
    fn __getattr__<'py>(slf: &Bound<'py, Self>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let this = slf.get();
        let params = this.params.bind(py);
        if let Some(v) = params.get_item(name)? {
            return Ok(v);
        }
        if let Some((new, position)) = Defined::rename(this.name(), name) {
            if let Some(v) = params.get_item(new)? {
                warn(py, &format!("`{name}` is deprecated, read `{new}`"))?;
                return match position {
                    Some(k) => Ok(v
                        .try_iter()?
                        .nth(k)
                        .transpose()?
                        .unwrap_or_else(|| py.None().into_bound(py))),
                    None => Ok(v),
                };
            }
        }
        Err(PyAttributeError::new_err(format!(
            "'{}' object has no attribute '{name}'",
            this.name()
        )))
    }

    /// The parameters, as given to the constructor (dof labels kept), in signature order.
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.params.bind(py).copy()
    }

    /// A copy with the parameters in `changes` replaced (checked as the constructor checks).
    #[pyo3(signature = (**changes))]
    fn replace<'py>(
        slf: &Bound<'py, Self>,
        changes: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let params = slf.get().params.bind(slf.py()).copy()?;
        if let Some(changes) = changes {
            for (k, v) in changes.iter() {
                let key: String = k.extract()?;
                if !params.contains(&key)? {
                    return Err(PyTypeError::new_err(format!(
                        "{}.replace() got an unexpected parameter `{key}`",
                        slf.get().name()
                    )));
                }
                params.set_item(key, v)?;
            }
        }
        slf.get_type().call((), Some(&params))
    }

    /// `copy.replace` (Python 3.13).
    #[pyo3(signature = (**changes))]
    fn __replace__<'py>(
        slf: &Bound<'py, Self>,
        changes: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        Self::replace(slf, changes)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let this = slf.get();
        if let Kind::Shifted { inner, k0, c0 } = &this.kind {
            let f = py.import("duhamel._core")?.getattr("_shifted")?;
            let args = (inner.clone_ref(py), k0.clone(), c0.clone()).into_pyobject(py)?;
            return PyTuple::new(py, [f, args.into_any()]);
        }
        let cls = slf.get_type();
        let params = this.params.bind(py).copy()?;
        let f = py.import("duhamel._core")?.getattr("_element")?;
        let args = PyTuple::new(py, [cls.into_any(), params.into_any()])?;
        PyTuple::new(py, [f, args.into_any()])
    }

    fn __eq__(slf: &Bound<'_, Self>, other: &Bound<'_, PyAny>) -> PyResult<bool> {
        let Ok(other) = other.cast::<Element>() else {
            return Ok(false);
        };
        Ok(slf.get_type().is(other.get_type()) && slf.get().key == other.get().key)
    }

    fn __hash__(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.key.hash(&mut h);
        h.finish()
    }

    fn __repr__(slf: &Bound<'_, Self>) -> PyResult<String> {
        let py = slf.py();
        let this = slf.get();
        let params = this.params.bind(py);
        let mut parts = Vec::new();
        for (k, v) in params.iter() {
            let k: String = k.extract()?;
            if DOF_PARAMS.contains(&k.as_str()) || k == "fn" {
                parts.push(v.repr()?.to_string());
            } else {
                parts.push(format!("{k}={}", v.repr()?));
            }
        }
        Ok(format!("{}({})", this.name(), parts.join(", ")))
    }

    /// Whether the element carries internal variables (a hysteretic element): the
    /// integrator commits them once per accepted step.
    #[getter]
    fn _path_dependent(&self) -> bool {
        match &self.kind {
            Kind::Builtin { runtime, .. } => runtime.state_len() > 0,
            Kind::Python(d) => d.state.is_some(),
            Kind::Shifted { inner, .. } => inner.get()._path_dependent(),
        }
    }

    /// The engine element's dofs, in its local order.
    #[getter]
    fn _dofs(&self) -> PyResult<Vec<usize>> {
        self.check_resolved()?;
        Ok(self.local_dofs())
    }

    /// Whether the element names a dof by a label (resolved by `System.add`).
    #[getter]
    fn _labelled(&self) -> bool {
        self.labelled
    }

    /// The element with its dof labels resolved by `resolve(label, parameter)` -> index.
    fn _resolved<'py>(
        slf: &Bound<'py, Self>,
        resolve: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let this = slf.get();
        if !this.labelled {
            return Ok(slf.clone().into_any());
        }
        let py = slf.py();
        let params = this.params.bind(py).copy()?;
        // a wrapper's parts act on its dofs: resolved with it
        for (name, value) in this.params.bind(py).iter() {
            if let Ok(part) = value.cast::<Element>() {
                params.set_item(&name, Self::_resolved(part, resolve)?)?;
            } else if value.is_instance_of::<PyTuple>()
                && value.len()? > 0
                && value
                    .try_iter()?
                    .all(|v| v.is_ok_and(|v| v.cast::<Element>().is_ok()))
            {
                let parts = value
                    .try_iter()?
                    .map(|v| Self::_resolved(v?.cast::<Element>()?, resolve))
                    .collect::<PyResult<Vec<_>>>()?;
                params.set_item(&name, PyTuple::new(py, parts)?)?;
            }
        }
        for name in DOF_PARAMS {
            let Some(value) = params.get_item(name)? else {
                continue;
            };
            let resolved = if name == "dofs" && !is_label(&value)? && value.hasattr("__len__")? {
                let items = value
                    .try_iter()?
                    .map(|item| {
                        let item = item?;
                        if is_label(&item)? {
                            resolve.call1((item, name))
                        } else {
                            Ok(item)
                        }
                    })
                    .collect::<PyResult<Vec<_>>>()?;
                PyTuple::new(py, items)?.into_any()
            } else if is_label(&value)? {
                resolve.call1((value, name))?
            } else {
                value
            };
            params.set_item(name, resolved)?;
        }
        slf.get_type().call((), Some(&params))
    }

    /// Checks the element's dofs against a system of `n_dof` dofs (errors name the
    /// parameter).
    fn _validate(&self, py: Python<'_>, system: &Bound<'_, PyAny>) -> PyResult<()> {
        self.check_resolved()?;
        let n: usize = system.getattr("n_dof")?.extract()?;
        let params = self.params.bind(py);
        for name in DOF_PARAMS {
            let Some(value) = params.get_item(name)? else {
                continue;
            };
            let items: Vec<Bound<'_, PyAny>> = if name == "dofs" {
                value.try_iter()?.collect::<PyResult<_>>()?
            } else {
                vec![value]
            };
            for (k, item) in items.iter().enumerate() {
                if item.is_none() {
                    continue;
                }
                let d: usize = item.extract()?;
                if d >= n {
                    let label = if name == "dofs" && items.len() > 1 {
                        format!("dofs[{k}]")
                    } else {
                        name.to_owned()
                    };
                    return Err(PyValueError::new_err(format!(
                        "`{label}` must be a degree-of-freedom index in [0, {}] (negative indices are not allowed), got {d}", n.saturating_sub(1)
                    )));
                }
            }
        }
        Ok(())
    }

    /// Whether the element only stores or dissipates the work done on it.
    fn _passive(&self) -> bool {
        self.definition().is_some_and(|d| d.passive())
    }

    /// The linear stiffness part `(dofs, k0)` the background takes over, or None.
    fn _linear<'py>(&self, py: Python<'py>) -> PyResult<Option<(Vec<usize>, Bound<'py, PyAny>)>> {
        let Some(k0) = self.definition().and_then(|d| d.linear_stiffness()) else {
            return Ok(None);
        };
        self.check_resolved()?;
        let dofs = self.local_dofs();
        Ok(Some((dofs.clone(), square(py, k0, dofs.len())?)))
    }

    /// Bounds `(k, c)` on the norms of the tangents as a pseudo-force, or None.
    fn _tangent_bound(&self) -> Option<(f64, f64)> {
        self.definition().and_then(|d| d.tangent_bound())
    }

    /// The directions the force acts along, each `(i, j)`.
    fn _directions(&self) -> PyResult<Vec<(usize, Option<usize>)>> {
        self.check_resolved()?;
        if let Some(dirs) = self.definition().and_then(|d| d.directions()) {
            return Ok(dirs);
        }
        Ok(self.local_dofs().into_iter().map(|d| (d, None)).collect())
    }

    /// The element without its linear part `k0` (from `_linear`) and with the damping `c0`
    /// (local, row-major; None: none) taken out too: what stays a pseudo-force.
    #[pyo3(signature = (c0=None))]
    fn _remainder(slf: &Bound<'_, Self>, c0: Option<&Bound<'_, PyAny>>) -> PyResult<Py<Element>> {
        let py = slf.py();
        let this = slf.get();
        let def = this.definition().ok_or_else(|| {
            PyValueError::new_err(format!("a {} has no linear part", this.name()))
        })?;
        let k0 = def.linear_stiffness().ok_or_else(|| {
            PyValueError::new_err(format!("this {} has no linear part", this.name()))
        })?;
        let c0 = match c0 {
            Some(c) => Some(crate::arrays::vec_of(c, "c0")?),
            None => None,
        };
        let zeros: Vec<f64> = k0.iter().map(|k| 0.0 * k).collect();
        match def.without_linear() {
            Some(rest) => {
                let plain = from_defined(py, rest)?;
                match c0 {
                    None => Ok(plain),
                    Some(c0) => shifted(py, plain, zeros, c0),
                }
            }
            None => {
                let inner: Py<Element> = slf.clone().unbind();
                let c0 = c0.unwrap_or_else(|| zeros.iter().map(|_| 0.0).collect());
                shifted(py, inner, k0, c0)
            }
        }
    }

    /// The recoverable energy along histories of the local displacements `u` and forces
    /// `f` (rows: instants); zeros where the element defines none.
    fn _stored_energy(&self, u: Vec<Vec<f64>>, f: Vec<Vec<f64>>) -> PyResult<Vec<f64>> {
        let Some(def) = self.definition() else {
            return Ok(vec![0.0; u.len()]);
        };
        Ok(u.iter()
            .zip(&f)
            .map(|(u, f)| def.stored_energy(u, f))
            .collect())
    }

    /// The exact local stiffness and damping matrices of a linear element; raises
    /// ValueError with the reason when it is not linear.
    fn _linear_matrices<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Vec<usize>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let def = self
            .definition()
            .ok_or_else(|| PyValueError::new_err(format!("is not linear (a {})", self.name())))?;
        self.check_resolved()?;
        let (k, c) = def.linear().map_err(PyValueError::new_err)?;
        let dofs = self.local_dofs();
        let n = dofs.len();
        Ok((dofs, square(py, k, n)?, square(py, c, n)?))
    }

    /// The definition as JSON text (the store's form).
    fn _to_value(&self) -> PyResult<String> {
        self.check_resolved()?;
        match &self.kind {
            Kind::Builtin { def, .. } => {
                serde_json::to_string(def).map_err(|e| PyValueError::new_err(e.to_string()))
            }
            _ => Err(PyValueError::new_err(format!(
                "a {} cannot be written as data",
                self.name()
            ))),
        }
    }

    /// The element of a definition's JSON text (`_to_value`).
    #[classmethod]
    fn _from_value(cls: &Bound<'_, PyType>, text: &str) -> PyResult<Py<Element>> {
        let py = cls.py();
        let def: Defined = serde_json::from_str(text)
            .map_err(|e| PyValueError::new_err(format!("an element's data: {e}")))?;
        from_defined(py, def)
    }

    /// The restoring force ``r`` and its tangents ``dr/dx``, ``dr/dx'`` (numpy arrays
    /// ``(n,)``, ``(n, n)``, ``(n, n)``) of a path-independent element at the local
    /// displacements `position` and velocities `velocity` (None: at rest) at time `t`.
    #[pyo3(signature = (position, velocity=None, t=0.0))]
    fn evaluate<'py>(
        slf: &Bound<'py, Self>,
        position: &Bound<'py, PyAny>,
        velocity: Option<&Bound<'py, PyAny>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyTuple>> {
        crate::drive::evaluate(slf, position, velocity, t)
    }
}
