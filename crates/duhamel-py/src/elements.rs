//! Element specifications from Python, and the Python `Callable` element.

use std::sync::Mutex;

use duhamel_core::elements::{Contact, Damper, Element, Polynomial, Spring, Tangent};
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::{core_err, vec_of};

/// A Python function `fn(x, v, t) -> r` of an element's local state, with an optional
/// `jacobian(x, v, t) -> (dr/dx, dr/dv)`; called with the GIL, once per evaluation.
pub(crate) struct PyElement {
    dofs: Vec<usize>,
    func: Py<PyAny>,
    jacobian: Option<Py<PyAny>>,
    /// The first Python exception raised, re-raised after the run.
    pub(crate) error: Mutex<Option<PyErr>>,
}

impl PyElement {
    fn call(
        &self,
        py: Python<'_>,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> PyResult<()> {
        let n = self.dofs.len();
        let xa = PyArray1::from_slice(py, x);
        let va = PyArray1::from_slice(py, v);
        let bad = |what: String| {
            PyValueError::new_err(format!("the `Callable` element {what} at t = {t}"))
        };
        let out = self.func.call1(py, (xa.clone(), va.clone(), t))?;
        let f = vector(py, out.bind(py), n).map_err(|e| bad(format!("returned {e}")))?;
        for (ri, fi) in r.iter_mut().zip(&f) {
            *ri += fi;
        }
        if let (Some(tan), Some(jac)) = (tangent, &self.jacobian) {
            let pair = jac.call1(py, (xa, va, t))?;
            let pair = pair.bind(py);
            let (kx, cv) = (pair.get_item(0)?, pair.get_item(1)?);
            for (m, dst, name) in [(kx, tan.kx, "dr/dx"), (cv, tan.cv, "dr/dv")] {
                let vals = matrix(py, &m, n).map_err(|e| bad(format!("jacobian {name}: {e}")))?;
                for (d, s) in dst.iter_mut().zip(&vals) {
                    *d += s;
                }
            }
        }
        Ok(())
    }
}

/// A finite float vector of length `n`, or a description of what is wrong.
fn vector(py: Python<'_>, obj: &Bound<'_, PyAny>, n: usize) -> Result<Vec<f64>, String> {
    let np = py.import("numpy").map_err(|e| e.to_string())?;
    let arr = np
        .call_method1("asarray", (obj, "float64"))
        .map_err(|e| format!("a non-numeric value ({e})"))?;
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
    let np = py.import("numpy").map_err(|e| e.to_string())?;
    let arr = np
        .call_method1("ascontiguousarray", (obj, "float64"))
        .map_err(|e| format!("a non-numeric value ({e})"))?;
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

    fn eval(
        &self,
        x: &[f64],
        v: &[f64],
        t: f64,
        r: &mut [f64],
        tangent: Option<Tangent<'_>>,
    ) -> Result<(), CoreError> {
        Python::attach(|py| {
            self.call(py, x, v, t, r, tangent).map_err(|err| {
                let message = err.to_string();
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(err);
                CoreError::Callback { time: t, message }
            })
        })
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

fn usize_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<usize> {
    obj.extract::<usize>()
        .map_err(|_| PyTypeError::new_err(format!("`{name}` must be a non-negative integer")))
}

/// Parsed elements, and handles on the Python ones (to collect their exceptions).
pub(crate) type Parsed = (Vec<Box<dyn Element>>, Vec<std::sync::Arc<PyElement>>);

/// Parses `(kind, *params)` element tuples.
pub(crate) fn parse(specs: &Bound<'_, PyAny>) -> PyResult<Parsed> {
    let mut out: Vec<Box<dyn Element>> = Vec::new();
    let mut python = Vec::new();
    for item in specs.try_iter()? {
        let item = item?;
        let tup = item
            .cast::<PyTuple>()
            .map_err(|_| PyTypeError::new_err("element spec must be a tuple"))?;
        let kind: String = tup.get_item(0)?.extract()?;
        let arg = |i: usize| tup.get_item(i);
        let opt_j = |i: usize| -> PyResult<Option<usize>> {
            let o = tup.get_item(i)?;
            if o.is_none() {
                Ok(None)
            } else {
                Ok(Some(usize_of(&o, "j")?))
            }
        };
        let f = |i: usize| -> PyResult<f64> { tup.get_item(i)?.extract::<f64>() };
        let element: Box<dyn Element> = match kind.as_str() {
            "polynomial" => Box::new(
                Polynomial::new(
                    usize_of(&arg(1)?, "dof")?,
                    vec_of(&arg(2)?, "coefficients")?,
                )
                .map_err(core_err)?,
            ),
            "spring" => Box::new(
                Spring::new(usize_of(&arg(1)?, "i")?, opt_j(2)?, f(3)?, f(4)?).map_err(core_err)?,
            ),
            "damper" => {
                Box::new(Damper::new(usize_of(&arg(1)?, "i")?, opt_j(2)?, f(3)?).map_err(core_err)?)
            }
            "contact" => Box::new(
                Contact::new(
                    usize_of(&arg(1)?, "dof_x")?,
                    usize_of(&arg(2)?, "dof_y")?,
                    f(3)?,
                    f(4)?,
                    f(5)?,
                    f(6)?,
                    f(7)?,
                )
                .map_err(core_err)?,
            ),
            "callable" => {
                let dofs: Vec<usize> = arg(1)?.extract().map_err(|_| {
                    PyTypeError::new_err("`dofs` must be a list of non-negative integers")
                })?;
                let func: Py<PyAny> = arg(2)?.unbind();
                let jac = arg(3)?;
                let element = std::sync::Arc::new(PyElement {
                    dofs,
                    func,
                    jacobian: if jac.is_none() {
                        None
                    } else {
                        Some(jac.unbind())
                    },
                    error: Mutex::new(None),
                });
                python.push(element.clone());
                Box::new(ArcElement(element))
            }
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown element kind {other:?}"
                )))
            }
        };
        out.push(element);
    }
    Ok((out, python))
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
