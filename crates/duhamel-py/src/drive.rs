//! An element evaluated outside a run: its force and tangents at one state (`evaluate`, a
//! path-independent element), and along a history of states with a commit after each
//! (`drive`, the material driver of `duhamel.elements.drive`).

use duhamel_core::elements::{drive as core_drive, Tangent};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::vec_of;
use crate::callable::Built;
use crate::element_build::make;
use crate::element_type::Element;
use crate::error::core_err;
use crate::guard::guarded;

fn fresh(
    py: Python<'_>,
    element: &Element,
) -> PyResult<(Box<dyn duhamel_core::elements::Element>, Built)> {
    element.check_runnable()?;
    let mut built = Built {
        elements: Vec::new(),
        python: Vec::new(),
    };
    let made = make(py, element, &mut built)?;
    Ok((made, built))
}

/// A float64 1-D array of `obj` (any sequence of numbers), named `name` in errors.
fn floats(py: Python<'_>, obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    let np = py.import("numpy")?;
    let arr = np
        .call_method1("asarray", (obj, "float64"))
        .map_err(|_| PyValueError::new_err(format!("`{name}` must be a sequence of numbers")))?;
    let flat = np.call_method1("ascontiguousarray", (arr.call_method0("ravel")?,))?;
    vec_of(&flat, name)
}

/// The restoring force and its tangents `(r, dr/dx, dr/dx')` of a path-independent element
/// at local displacements `x`, velocities `v` (None: at rest), time `t`, as numpy arrays
/// (`(n,)`, `(n, n)`, `(n, n)`).
pub(crate) fn evaluate<'py>(
    slf: &Bound<'py, Element>,
    x: &Bound<'py, PyAny>,
    v: Option<&Bound<'py, PyAny>>,
    t: f64,
) -> PyResult<Bound<'py, PyTuple>> {
    let py = slf.py();
    let (element, built) = fresh(py, slf.get())?;
    let n = element.dofs().len();
    if element.state_len() > 0 {
        return Err(PyValueError::new_err(
            "evaluate: a path-dependent element's force depends on its history (use \
             duhamel.elements.drive)",
        ));
    }
    let x = floats(py, x, "x")?;
    let v = match v {
        Some(v) if !v.is_none() => floats(py, v, "v")?,
        _ => vec![0.0; n],
    };
    if x.len() != n || v.len() != n {
        return Err(PyValueError::new_err(format!(
            "evaluate: `x` and `v` must have the element's {n} local dofs, got {} and {}",
            x.len(),
            v.len()
        )));
    }
    if !t.is_finite() {
        return Err(PyValueError::new_err(format!(
            "`t` must be finite, got {t}"
        )));
    }
    let (mut r, mut kx, mut cv) = (vec![0.0; n], vec![0.0; n * n], vec![0.0; n * n]);
    let result = guarded(|| {
        let tangent = Tangent {
            kx: &mut kx,
            cv: &mut cv,
        };
        element
            .eval(&x, &v, t, &mut r, Some(tangent))
            .map_err(|e| match e {
                duhamel_core::CoreError::OutOfDomain { .. } => PyValueError::new_err(format!(
                    "`position` {x:?} is outside the element's domain: {e}"
                )),
                other => PyValueError::new_err(other.to_string()),
            })
    });
    if let Some(err) = built.take_error() {
        return Err(err);
    }
    result?;
    if r.iter().chain(&kx).chain(&cv).any(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "the force or its tangents of this {} are not finite at `x` = {x:?} (they \
             overflow the double range)",
            slf.get().name()
        )));
    }
    let r = PyArray1::from_vec(py, r);
    let kx = PyArray1::from_vec(py, kx).reshape([n, n])?;
    let cv = PyArray1::from_vec(py, cv).reshape([n, n])?;
    PyTuple::new(py, [r.into_any(), kx.into_any(), cv.into_any()])
}

/// Three flat float64 arrays.
type Arrays3<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
);

/// The forces and tangents of `element` driven from its virgin state through the local
/// displacements `x` and velocities `v` (1-D, row-major `n x n_local`) at times `t` (`n`),
/// committing after each instant: `(force, dr/dx, dr/dx')` as flat arrays.
#[pyfunction]
pub(crate) fn drive_element<'py>(
    py: Python<'py>,
    element: &Bound<'py, Element>,
    x: &Bound<'py, PyAny>,
    v: &Bound<'py, PyAny>,
    t: &Bound<'py, PyAny>,
) -> PyResult<Arrays3<'py>> {
    let (made, built) = fresh(py, element.get())?;
    let (x, v, t) = (vec_of(x, "x")?, vec_of(v, "v")?, vec_of(t, "t")?);
    let result = guarded(|| core_drive(&*made, &x, &v, &t).map_err(core_err));
    if let Some(err) = built.take_error() {
        return Err(err);
    }
    let d = result?;
    Ok((
        PyArray1::from_vec(py, d.force),
        PyArray1::from_vec(py, d.kx),
        PyArray1::from_vec(py, d.cv),
    ))
}
