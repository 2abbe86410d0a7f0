//! The Python `Callable` element: a function of the local state (and, with internal
//! variables, of the committed ones), called with the GIL once per evaluation.

use std::sync::Mutex;

use duhamel_core::elements::{Element, PathState, Tangent};
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

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
    /// The element of `func` (and `jacobian`) at `dofs`, with the initial internal
    /// variables `state0` if it has any.
    pub(crate) fn new(
        dofs: Vec<usize>,
        func: Py<PyAny>,
        jacobian: Option<Py<PyAny>>,
        state0: Option<Vec<f64>>,
    ) -> Self {
        PyElement {
            dofs,
            func,
            jacobian,
            state0,
            error: Mutex::new(None),
        }
    }

    fn call(
        &self,
        py: Python<'_>,
        (x, v, t): (&[f64], &[f64], f64),
        history: Option<PathState<'_>>,
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
        history: Option<PathState<'_>>,
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
                let history = PathState {
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
        history: PathState<'_>,
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

/// A shared Python element (the run keeps a handle to collect its exception).
pub(crate) struct ArcElement(pub(crate) std::sync::Arc<PyElement>);

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
    fn initial_time(&self, t0: f64, state: &mut [f64]) {
        self.0.initial_time(t0, state)
    }
    fn eval_path(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        history: PathState<'_>,
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
