//! Elements: specifications as typed values (checked once, when made), and the Python
//! `Callable` element.

use std::sync::Mutex;

use duhamel_core::elements::{Contact, Damper, Element, History, Polynomial, Spring, Tangent};
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

use crate::arrays::vec_of;
use crate::error::core_err;
use crate::guard::guarded;

/// A Python function `fn(x, v, t) -> r` of an element's local state, with an optional
/// `jacobian(x, v, t) -> (dr/dx, dr/dv)`; called with the GIL, once per evaluation. With
/// internal variables (`state0`, their initial values): `fn(x, v, t, state) -> (r, trial)`
/// and `jacobian(x, v, t, state)`, `state` the variables committed at the start of the step.
pub(crate) struct PyElement {
    dofs: Vec<usize>,
    func: Py<PyAny>,
    jacobian: Option<Py<PyAny>>,
    state0: Option<Vec<f64>>,
    /// The first Python exception raised, re-raised after the run.
    pub(crate) error: Mutex<Option<PyErr>>,
}

impl PyElement {
    #[allow(clippy::too_many_arguments)]
    fn call(
        &self,
        py: Python<'_>,
        (x, v, t): (&[f64], &[f64], f64),
        history: Option<History<'_>>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> PyResult<()> {
        let n = self.dofs.len();
        let xa = PyArray1::from_slice(py, x);
        let va = PyArray1::from_slice(py, v);
        let bad = |what: String| {
            PyValueError::new_err(format!("the `Callable` element {what} at t = {t}"))
        };
        let state = history
            .as_ref()
            .map(|h| PyArray1::from_slice(py, h.committed));
        let out = match &state {
            Some(s) => self
                .func
                .call1(py, (xa.clone(), va.clone(), t, s.clone()))?,
            None => self.func.call1(py, (xa.clone(), va.clone(), t))?,
        };
        let f = match history {
            Some(h) => {
                let ns = h.trial.len();
                let (force, trial) = two(out.bind(py)).map_err(|got| {
                    bad(format!(
                        "returned {got}, expected a pair (r, state) of shapes ({n},) and ({ns},)"
                    ))
                })?;
                let s = vector(py, &trial, ns).map_err(|e| bad(format!("returned a state {e}")))?;
                h.trial.copy_from_slice(&s);
                vector(py, &force, n).map_err(|e| bad(format!("returned a force {e}")))?
            }
            None => vector(py, out.bind(py), n).map_err(|e| bad(format!("returned {e}")))?,
        };
        for (ri, fi) in r.iter_mut().zip(&f) {
            *ri += fi;
        }
        if let (Some(tan), Some(jac)) = (tangent, &self.jacobian) {
            let pair = match &state {
                Some(s) => jac.call1(py, (xa, va, t, s.clone()))?,
                None => jac.call1(py, (xa, va, t))?,
            };
            let pair = pair.bind(py);
            let (kx, cv) = two(pair).map_err(|got| {
                bad(format!(
                    "jacobian returned {got}, expected a pair (dr/dx, dr/dv) of ({n}, {n}) matrices"
                ))
            })?;
            for (m, dst, name) in [(kx, tan.kx, "dr/dx"), (cv, tan.cv, "dr/dv")] {
                let vals = matrix(py, &m, n).map_err(|e| bad(format!("jacobian {name}: {e}")))?;
                for (d, s) in dst.iter_mut().zip(&vals) {
                    *d += s;
                }
            }
        }
        Ok(())
    }

    /// Runs `call` with the GIL, keeping its Python exception for after the run.
    fn attached(
        &self,
        state: (&[f64], &[f64], f64),
        history: Option<History<'_>>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let t = state.2;
        Python::attach(|py| {
            self.call(py, state, history, r, tangent).map_err(|err| {
                let message = err.to_string();
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(err);
                CoreError::Callback {
                    time: t,
                    step: 0,
                    message,
                }
            })
        })
    }
}

/// The two items of a tuple or list of length two, or a description of what `obj` is.
fn two<'py>(obj: &Bound<'py, PyAny>) -> Result<(Bound<'py, PyAny>, Bound<'py, PyAny>), String> {
    let is_pair = (obj.cast::<PyTuple>().is_ok() || obj.cast::<PyList>().is_ok())
        && obj.len().is_ok_and(|n| n == 2);
    if !is_pair {
        let kind = obj.get_type().name().map_or("?".into(), |n| n.to_string());
        return Err(match obj.len() {
            Ok(n) if kind == "tuple" || kind == "list" => format!("a {kind} of {n} items"),
            _ => format!("a {kind}"),
        });
    }
    match (obj.get_item(0), obj.get_item(1)) {
        (Ok(a), Ok(b)) => Ok((a, b)),
        _ => Err("a pair that cannot be indexed".into()),
    }
}

/// `obj` as a float64 array: real numbers only (a complex value is refused, not truncated).
fn real_array<'py>(
    py: Python<'py>,
    obj: &Bound<'py, PyAny>,
    how: &str,
) -> Result<Bound<'py, PyAny>, String> {
    let np = py.import("numpy").map_err(|e| e.to_string())?;
    let raw = np
        .call_method1("asarray", (obj,))
        .map_err(|e| format!("a non-numeric value ({e})"))?;
    let kind: String = raw
        .getattr("dtype")
        .and_then(|d| d.getattr("kind"))
        .and_then(|k| k.extract())
        .map_err(|e| e.to_string())?;
    if !"iuf".contains(kind.as_str()) {
        let dtype = raw.getattr("dtype").map_or("?".into(), |d| d.to_string());
        return Err(format!("values of dtype {dtype}, expected real numbers"));
    }
    np.call_method1(how, (raw, "float64"))
        .map_err(|e| format!("a non-numeric value ({e})"))
}

/// A finite float vector of length `n`, or a description of what is wrong.
fn vector(py: Python<'_>, obj: &Bound<'_, PyAny>, n: usize) -> Result<Vec<f64>, String> {
    let arr = real_array(py, obj, "asarray")?;
    let arr = arr.cast::<PyArray1<f64>>().map_err(|_| {
        format!(
            "an array of ndim {}, expected shape ({n},)",
            arr.getattr("ndim").map_or("?".into(), |d| d.to_string())
        )
    })?;
    let ro = arr.readonly();
    let s = ro.as_slice().map_err(|e| e.to_string())?;
    if s.len() != n {
        return Err(format!("shape ({},), expected ({n},)", s.len()));
    }
    if s.iter().any(|x| !x.is_finite()) {
        return Err("NaN or inf".into());
    }
    Ok(s.to_vec())
}

/// A finite float `n x n` matrix, row-major.
fn matrix(py: Python<'_>, obj: &Bound<'_, PyAny>, n: usize) -> Result<Vec<f64>, String> {
    let arr = real_array(py, obj, "ascontiguousarray")?;
    let arr = arr
        .cast::<PyArray2<f64>>()
        .map_err(|_| format!("not a matrix, expected shape ({n}, {n})"))?;
    if arr.shape() != [n, n] {
        return Err(format!("shape {:?}, expected ({n}, {n})", arr.shape()));
    }
    let ro = arr.readonly();
    let s = ro.as_slice().map_err(|e| e.to_string())?;
    if s.iter().any(|x| !x.is_finite()) {
        return Err("NaN or inf".into());
    }
    Ok(s.to_vec())
}

impl Element for PyElement {
    fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    /// Without internal variables the function of the state; with them, the response from
    /// their initial values.
    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        match &self.state0 {
            None => self.attached((x, v, t), None, r, tangent),
            Some(s0) => {
                let mut trial = s0.clone();
                let history = History {
                    committed: s0,
                    trial: &mut trial,
                };
                self.attached((x, v, t), Some(history), r, tangent)
            }
        }
    }

    fn state_len(&self) -> usize {
        self.state0.as_ref().map_or(0, Vec::len)
    }

    fn initial_state(&self, _x: &[f64], _v: &[f64], state: &mut [f64]) {
        if let Some(s0) = &self.state0 {
            state.copy_from_slice(s0);
        }
    }

    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: History<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        let history = self.state0.is_some().then_some(history);
        self.attached((x, v, t), history, r, tangent)
    }

    fn polynomial_degree(&self) -> Option<u32> {
        None
    }

    fn uses_velocity(&self) -> bool {
        true
    }

    fn has_tangent(&self) -> bool {
        self.jacobian.is_some()
    }
}

/// What an element is, checked; the run builds a fresh element from it.
enum Spec {
    Polynomial(Polynomial),
    Spring(Spring),
    Damper(Damper),
    Contact(Contact),
    Callable {
        dofs: Vec<usize>,
        func: Py<PyAny>,
        jacobian: Option<Py<PyAny>>,
        state: Option<Vec<f64>>,
    },
}

/// A force element of `duhamel.elements`, checked.
#[pyclass(frozen, name = "Element", module = "duhamel._core")]
pub(crate) struct ElementSpec(Spec);

#[pymethods]
impl ElementSpec {
    /// `r = sum_k coefficients[k] x^k` at `dof`.
    #[staticmethod]
    fn polynomial(dof: usize, coefficients: &Bound<'_, PyAny>) -> PyResult<Self> {
        let coefficients = vec_of(coefficients, "coefficients")?;
        let e = guarded(|| Polynomial::new(dof, coefficients).map_err(core_err))?;
        Ok(ElementSpec(Spec::Polynomial(e)))
    }

    /// Spring `k d + k3 d^3` on `d = x_i - x_j` (`j` None: to ground).
    #[staticmethod]
    #[pyo3(signature = (i, j, k, k3))]
    fn spring(i: usize, j: Option<usize>, k: f64, k3: f64) -> PyResult<Self> {
        let e = guarded(|| Spring::new(i, j, k, k3).map_err(core_err))?;
        Ok(ElementSpec(Spec::Spring(e)))
    }

    /// Viscous damper `c d'` on `d = x_i - x_j`.
    #[staticmethod]
    #[pyo3(signature = (i, j, c))]
    fn damper(i: usize, j: Option<usize>, c: f64) -> PyResult<Self> {
        let e = guarded(|| Damper::new(i, j, c).map_err(core_err))?;
        Ok(ElementSpec(Spec::Damper(e)))
    }

    /// Radial rub contact with Coulomb friction.
    #[staticmethod]
    fn contact(
        dof_x: usize,
        dof_y: usize,
        clearance: f64,
        stiffness: f64,
        friction: f64,
        smoothing: f64,
        velocity_smoothing: f64,
    ) -> PyResult<Self> {
        let e = guarded(|| {
            Contact::new(
                dof_x,
                dof_y,
                clearance,
                stiffness,
                friction,
                smoothing,
                velocity_smoothing,
            )
            .map_err(core_err)
        })?;
        Ok(ElementSpec(Spec::Contact(e)))
    }

    /// A Python function `fn(x, v, t) -> r` of the local state at `dofs`, with an optional
    /// `jacobian(x, v, t) -> (dr/dx, dr/dv)`; with `state` (the initial internal variables)
    /// `fn(x, v, t, state) -> (r, trial_state)` and `jacobian(x, v, t, state)`.
    #[staticmethod]
    #[pyo3(signature = (dofs, func, jacobian=None, state=None))]
    fn callable(
        dofs: Vec<usize>,
        func: Py<PyAny>,
        jacobian: Option<Py<PyAny>>,
        state: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        if let Some(bad) = state
            .as_ref()
            .and_then(|s| s.iter().find(|x| !x.is_finite()))
        {
            return Err(PyValueError::new_err(format!(
                "`state` must be finite, got {bad}"
            )));
        }
        Ok(ElementSpec(Spec::Callable {
            dofs,
            func,
            jacobian,
            state,
        }))
    }
}

/// Built elements, and handles on the Python ones (to collect their exceptions).
#[derive(Default)]
pub(crate) struct Built {
    pub(crate) elements: Vec<Box<dyn Element>>,
    pub(crate) python: Vec<std::sync::Arc<PyElement>>,
}

impl Built {
    /// The elements as the core takes them.
    pub(crate) fn refs(&self) -> Vec<&dyn Element> {
        self.elements.iter().map(|b| b.as_ref()).collect()
    }

    /// The first exception a Python element raised, if any.
    pub(crate) fn take_error(&self) -> Option<PyErr> {
        self.python
            .iter()
            .find_map(|e| e.error.lock().unwrap_or_else(|p| p.into_inner()).take())
    }
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
        let spec = item.cast::<ElementSpec>()?;
        let element: Box<dyn Element> = match &spec.get().0 {
            Spec::Polynomial(e) => Box::new(e.clone()),
            Spec::Spring(e) => Box::new(e.clone()),
            Spec::Damper(e) => Box::new(e.clone()),
            Spec::Contact(e) => Box::new(e.clone()),
            Spec::Callable {
                dofs,
                func,
                jacobian,
                state,
            } => {
                let element = std::sync::Arc::new(PyElement {
                    dofs: dofs.clone(),
                    func: func.clone_ref(py),
                    jacobian: jacobian.as_ref().map(|j| j.clone_ref(py)),
                    state0: state.clone(),
                    error: Mutex::new(None),
                });
                built.python.push(element.clone());
                Box::new(ArcElement(element))
            }
        };
        built.elements.push(element);
    }
    Ok(built)
}

/// A shared Python element (the run keeps a handle to collect its exception).
struct ArcElement(std::sync::Arc<PyElement>);

impl Element for ArcElement {
    fn dofs(&self) -> &[usize] {
        self.0.dofs()
    }
    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.0.eval(x, v, t, r, tangent)
    }
    fn state_len(&self) -> usize {
        self.0.state_len()
    }
    fn initial_state(&self, x: &[f64], v: &[f64], state: &mut [f64]) {
        self.0.initial_state(x, v, state)
    }
    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: History<'_>,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        self.0.eval_path(x, v, t, history, r, tangent)
    }
    fn polynomial_degree(&self) -> Option<u32> {
        None
    }
    fn uses_velocity(&self) -> bool {
        true
    }
    fn has_tangent(&self) -> bool {
        self.0.has_tangent()
    }
}
