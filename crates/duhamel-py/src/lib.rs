//! `duhamel._core`: the thin PyO3 binding of `duhamel-core`, module for module.
//!
//! Inputs are typed classes, checked when made and extracted into Rust values once
//! (`TimeFunction`, `SpeedLaw`, `MassLaw`, `Mass`, `Element`, `Load`, `Matrix`, `Method`; a
//! prepared `ModalModel` with its route — `FirstOrderRoute`, `PseudoForceRoute` — or a
//! `DirectModel`; per run a `RunSpec`/`DirectRun` on a `Grid`); the time loop then runs with the GIL released,
//! taking it back between blocks to check for Ctrl-C and report progress. A run returns a
//! `RunResult` (numpy arrays moved, not copied) whose `error` is None or a `RunError` with
//! the fields of the core's error; input errors raise `ValueError`/`TypeError` naming the
//! parameter ([`error`]). A panic (a bug) raises `duhamel.errors.InternalError` ([`guard`]).

mod accuracy;
mod arguments;
mod arrays;
mod background;
mod callable;
mod callable_class;
mod definitions;
mod direct;
mod drive;
mod driver;
mod element_build;
mod element_classes;
mod element_dofs;
mod element_make;
mod element_type;
mod error;
mod estimator;
mod guard;
mod history;
mod loads;
mod mass;
mod model;
mod problem;
mod pseudo;
mod spectra;
mod speed;
mod values;

use duhamel_core::Transfer;
use numpy::{PyArray1, PyArray3, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::vec_of;
use crate::guard::guarded;

/// `(A, B)` or `(A, M)` stacks returned to Python.
type MatrixPair<'py> = (Bound<'py, PyArray3<f64>>, Bound<'py, PyArray3<f64>>);

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
    let (a, b, bad) = py.detach(|| {
        let mut a = Vec::with_capacity(4 * x.len());
        let mut b: Vec<f64> = Vec::with_capacity(2 * width * x.len());
        let mut bad = None;
        for (i, (&u, &w)) in x.iter().zip(&y).enumerate() {
            let tr = make(u, w, dt);
            a.extend(tr.a.iter().flatten());
            if moments {
                b.extend(tr.m.iter().flatten());
            } else {
                b.extend(tr.b().iter().flatten());
            }
            let finite = tr.is_finite() && b[b.len() - 2 * width..].iter().all(|v| v.is_finite());
            if bad.is_none() && !finite {
                bad = Some(i);
            }
        }
        (a, b, bad)
    });
    // Never NaN or inf without an error: say which entry could not be represented.
    if let Some(i) = bad {
        return Err(PyValueError::new_err(format!(
            "the exact step matrices of `{n1}` = {:e}, `{n2}` = {:e}, `dt` = {dt:e} (entry {i}) \
             cannot be evaluated in double precision: they overflow, or an intermediate does \
             (extreme `{n1}` dt, damping or `dt`); use values of a physical oscillator and step",
            x[i], y[i]
        )));
    }
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
    guarded(|| {
        transfer_batch(
            py,
            (omega, "omega"),
            (zeta, "zeta"),
            dt,
            moments,
            Transfer::from_omega_zeta,
        )
    })
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
    guarded(|| transfer_batch(py, (k, "k"), (c, "c"), dt, moments, Transfer::new))
}

/// The native core of duhamel.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    guard::install_hook();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(transfer, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::mode_bounds, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::row_errors, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::decaying_max, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::hold_response, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::parabola_moments, m)?)?;
    m.add_class::<estimator::Estimator>()?;
    m.add_function(wrap_pyfunction!(transfer_kc, m)?)?;
    m.add_function(wrap_pyfunction!(direct::element_stiffness, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::elastic_spectra, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::rotd_peaks, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::ductility_spectrum, m)?)?;
    m.add_function(wrap_pyfunction!(spectra::bilinear_peak, m)?)?;
    m.add_function(wrap_pyfunction!(guard::_panic_for_tests, m)?)?;
    m.add_class::<speed::SpeedLaw>()?;
    m.add_class::<loads::TimeFunction>()?;
    m.add_class::<mass::MassLaw>()?;
    m.add_class::<element_type::Element>()?;
    element_classes::add_classes(m)?;
    m.add_class::<callable_class::Callable>()?;
    m.add_function(wrap_pyfunction!(element_classes::_element, m)?)?;
    m.add_function(wrap_pyfunction!(element_classes::_shifted, m)?)?;
    m.add_function(wrap_pyfunction!(element_classes::element_names, m)?)?;
    m.add_function(wrap_pyfunction!(drive::drive_element, m)?)?;
    m.add_class::<problem::EnergySpec>()?;
    m.add_class::<direct::Matrix>()?;
    m.add_class::<direct::Method>()?;
    m.add_class::<direct::ScaledCoupling>()?;
    m.add_class::<direct::Matrices>()?;
    m.add_class::<direct::DirectModel>()?;
    m.add_class::<direct::DirectRun>()?;
    m.add_class::<loads::Load>()?;
    m.add_class::<mass::Mass>()?;
    m.add_class::<problem::Grid>()?;
    m.add_class::<problem::RunSpec>()?;
    m.add_class::<background::Corrector>()?;
    m.add_class::<background::FirstOrderRoute>()?;
    m.add_class::<background::Outputs>()?;
    m.add_class::<pseudo::Options>()?;
    m.add_class::<pseudo::PseudoForceRoute>()?;
    m.add_class::<model::ModalModel>()?;
    m.add_class::<history::RunResult>()?;
    m.add_class::<error::RunError>()?;
    Ok(())
}
