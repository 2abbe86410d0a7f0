//! `duhamel._core`: the thin PyO3 binding of `duhamel-core`.
//!
//! Inputs are checked and copied into Rust values first; the time loop then runs with the
//! GIL released. A Python load callable is called with the GIL, once per evaluation time.

mod coupled;
mod direct;
mod elements;
mod nonlinear;
mod run;

use duhamel_core::{CoreError, Transfer};
use numpy::{PyArray1, PyArray3, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

/// `(A, B)` or `(A, M)` stacks returned to Python.
type MatrixPair<'py> = (Bound<'py, PyArray3<f64>>, Bound<'py, PyArray3<f64>>);

/// A read-only float64 1-D view of `obj`, or a TypeError/ValueError naming `name`.
pub(crate) fn f64_array1<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let arr = obj.cast::<PyArray1<f64>>().map_err(|_| {
        let what = match obj.getattr("dtype") {
            Ok(dt) => format!(
                "an array of dtype {dt} (ndim {})",
                obj.getattr("ndim").map_or("?".into(), |n| n.to_string())
            ),
            Err(_) => obj.get_type().name().map_or("?".into(), |n| n.to_string()),
        };
        PyTypeError::new_err(format!(
            "`{name}` must be a 1-D numpy array of float64, got {what}"
        ))
    })?;
    let ro = arr.readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be C-contiguous (pass numpy.ascontiguousarray({name}))"
        )));
    }
    Ok(ro)
}

pub(crate) fn vec_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    Ok(f64_array1(obj, name)?.as_slice()?.to_vec())
}

pub(crate) fn core_err(e: CoreError) -> PyErr {
    match e {
        CoreError::InvalidInput { .. } | CoreError::LengthMismatch { .. } => {
            PyValueError::new_err(e.to_string())
        }
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

/// Exact matrices for arrays of two oscillator parameters; `make` builds one `Transfer`.
fn transfer_batch<'py>(
    py: Python<'py>,
    p1: (&Bound<'py, PyAny>, &str),
    p2: (&Bound<'py, PyAny>, &str),
    dt: f64,
    moments: bool,
    make: fn(f64, f64, f64) -> Transfer,
) -> PyResult<MatrixPair<'py>> {
    let (n1, n2) = (p1.1, p2.1);
    let x = vec_of(p1.0, n1)?;
    let y = vec_of(p2.0, n2)?;
    if x.len() != y.len() {
        return Err(PyValueError::new_err(format!(
            "`{n1}` and `{n2}` must have the same length, got {} and {}",
            x.len(),
            y.len()
        )));
    }
    if !(dt.is_finite() && dt > 0.0) {
        return Err(PyValueError::new_err(format!(
            "`dt` must be a positive finite number, got {dt}"
        )));
    }
    if x.iter().any(|&v| !(v.is_finite() && v >= 0.0)) {
        return Err(PyValueError::new_err(format!(
            "`{n1}` must be finite and >= 0"
        )));
    }
    if y.iter().any(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!("`{n2}` must be finite")));
    }
    let width = if moments { 4 } else { 3 };
    let (a, b) = py.detach(|| {
        let mut a = Vec::with_capacity(4 * x.len());
        let mut b = Vec::with_capacity(2 * width * x.len());
        for (&u, &w) in x.iter().zip(&y) {
            let tr = make(u, w, dt);
            a.extend(tr.a.iter().flatten());
            if moments {
                b.extend(tr.m.iter().flatten());
            } else {
                b.extend(tr.b().iter().flatten());
            }
        }
        (a, b)
    });
    let n = x.len();
    let a = PyArray1::from_vec(py, a).reshape([n, 2, 2])?;
    let b = PyArray1::from_vec(py, b).reshape([n, 2, width])?;
    Ok((a, b))
}

/// Exact matrices for arrays of natural frequency `omega` and damping ratio `zeta`.
///
/// Returns `(A, B)` shaped `(n, 2, 2)` and `(n, 2, 3)`, or `(A, M)` with the cubic moments
/// `(n, 2, 4)` when `moments` is true.
#[pyfunction]
#[pyo3(signature = (omega, zeta, dt, moments=false))]
fn transfer<'py>(
    py: Python<'py>,
    omega: &Bound<'py, PyAny>,
    zeta: &Bound<'py, PyAny>,
    dt: f64,
    moments: bool,
) -> PyResult<MatrixPair<'py>> {
    transfer_batch(
        py,
        (omega, "omega"),
        (zeta, "zeta"),
        dt,
        moments,
        Transfer::from_omega_zeta,
    )
}

/// As `transfer`, from modal stiffness `k = omega^2` and damping `c = 2 zeta omega` per unit
/// modal mass (the form modal analysis delivers; allows damped rigid-body modes).
#[pyfunction]
#[pyo3(signature = (k, c, dt, moments=false))]
fn transfer_kc<'py>(
    py: Python<'py>,
    k: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    dt: f64,
    moments: bool,
) -> PyResult<MatrixPair<'py>> {
    transfer_batch(py, (k, "k"), (c, "c"), dt, moments, Transfer::new)
}

/// The native core of duhamel.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(transfer, m)?)?;
    m.add_function(wrap_pyfunction!(transfer_kc, m)?)?;
    m.add_function(wrap_pyfunction!(run::solve_linear, m)?)?;
    m.add_function(wrap_pyfunction!(coupled::solve_coupled, m)?)?;
    m.add_function(wrap_pyfunction!(nonlinear::solve_nonlinear, m)?)?;
    m.add_function(wrap_pyfunction!(direct::solve_direct, m)?)?;
    m.add_function(wrap_pyfunction!(direct::element_stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(run::speed_law, m)?)?;
    m.add_function(wrap_pyfunction!(run::time_function, m)?)?;
    Ok(())
}
