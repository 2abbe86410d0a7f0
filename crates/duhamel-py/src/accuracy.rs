//! The error estimate of semi-analytic runs (`duhamel._engine.accuracy`): the per-mode
//! bounds and the propagated errors from a run's saved modal history, computed in the core
//! (`duhamel_core::accuracy`) on views of the run's arrays; the estimates of a prepared
//! model's runs are made by [`crate::estimator::Estimator`] with them.

use duhamel_core::accuracy::{self, ModalRun};
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

use crate::arrays::f64_array1;
use crate::guard::guarded;

/// A read-only C-contiguous float64 matrix view of `obj`, or an error naming `name`.
pub(crate) fn matrix<'py>(
    obj: &Bound<'py, PyAny>,
    name: &str,
) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let arr = obj.cast::<PyArray2<f64>>().map_err(|_| {
        PyTypeError::new_err(format!("`{name}` must be a 2-D numpy array of float64"))
    })?;
    let ro = arr.readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "`{name}` must be C-contiguous (pass numpy.ascontiguousarray({name}))"
        )));
    }
    Ok(ro)
}

/// A C-contiguous view of a run's array (the core made it so).
pub(crate) fn view<'py>(
    py: Python<'py>,
    a: &Py<PyArray2<f64>>,
) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let ro = a.bind(py).readonly();
    if !ro.is_c_contiguous() {
        return Err(PyValueError::new_err("a run's history is not C-contiguous"));
    }
    Ok(ro)
}

pub(crate) fn shape_error(name: &str, want: String, got: &[usize]) -> PyErr {
    PyValueError::new_err(format!("`{name}` must have shape {want}, got {got:?}"))
}

/// Per mode, the largest accumulated bound of the modal displacement error over a run:
/// `pseudo` and `q` the saved modal pseudo-force and displacements `(rows, n)`, `omega` and
/// `c` per mode, `step` the run's stepping `(h, k, span)`: the internal step, the internal
/// steps between saved instants and the run's duration (they travel together, as in
/// [`bounds_of`]).
#[pyfunction]
pub(crate) fn mode_bounds<'py>(
    py: Python<'py>,
    pseudo: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    step: (f64, usize, f64),
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let (h, k, _) = step;
    guarded(|| {
        let (pseudo, q) = (matrix(pseudo, "pseudo")?, matrix(q, "q")?);
        let (omega, c) = (f64_array1(omega, "omega")?, f64_array1(c, "c")?);
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        check_step(h, k)?;
        let moments = accuracy::parabola_moments(omega, c, h);
        let bounds = bounds_of(py, &pseudo, &q, (omega, c), &moments, step)?;
        Ok(PyArray1::from_vec(py, bounds))
    })
}

/// Per mode, the end state `(q, v)` of the parabola `4 s (1 - s)` over one step `h` from
/// rest, `(n, 2)` (`duhamel_core::accuracy::parabola_moments`).
#[pyfunction]
pub(crate) fn parabola_moments<'py>(
    py: Python<'py>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    h: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    guarded(|| {
        let (omega, c) = (f64_array1(omega, "omega")?, f64_array1(c, "c")?);
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        check_step(h, 1)?;
        let n = omega.len();
        PyArray1::from_vec(py, accuracy::parabola_moments(omega, c, h)).reshape([n, 2])
    })
}

/// Per row of `x` `(n, len)`, the largest value of the recurrence
/// `acc_{i+1} = decay acc_i + x_i` from 0 (bounded as `duhamel_core::accuracy::decaying_max`
/// says).
#[pyfunction]
pub(crate) fn decaying_max<'py>(
    py: Python<'py>,
    x: &Bound<'py, PyAny>,
    decay: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        let x = matrix(x, "x")?;
        let decay = f64_array1(decay, "decay")?;
        if x.shape()[0] != decay.len() {
            return Err(shape_error(
                "x",
                format!("({}, len)", decay.len()),
                x.shape(),
            ));
        }
        let len = x.shape()[1];
        let best = accuracy::decaying_max(x.as_slice()?, len, decay.as_slice()?);
        Ok(PyArray1::from_vec(py, best))
    })
}

/// Per row of `g` `(n, len)`, the output of the oscillator of that row of `steps`
/// `(n, 9)` from rest under the row linear between samples
/// (`duhamel_core::truncation::hold_response`): the basis-truncation estimate's
/// left-out modes.
#[pyfunction]
pub(crate) fn hold_response<'py>(
    py: Python<'py>,
    steps: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    use duhamel_core::truncation::{self, STEP_VALUES};
    guarded(|| {
        let (steps, g) = (matrix(steps, "steps")?, matrix(g, "g")?);
        let n = g.shape()[0];
        if steps.shape() != [n, STEP_VALUES] {
            return Err(shape_error(
                "steps",
                format!("({n}, {STEP_VALUES})"),
                steps.shape(),
            ));
        }
        let len = g.shape()[1];
        let (steps, g) = (steps.as_slice()?, g.as_slice()?);
        // a pass over the whole history: other Python threads (solve_many) run meanwhile
        let y = py.detach(|| truncation::hold_response(steps, g, len));
        PyArray1::from_vec(py, y).reshape([n, len])
    })
}

pub(crate) fn check_step(h: f64, k: usize) -> PyResult<()> {
    if !(h.is_finite() && h > 0.0) || k == 0 {
        return Err(PyValueError::new_err(format!(
            "`h` must be positive and finite and `k` at least 1, got {h} and {k}"
        )));
    }
    Ok(())
}

/// The [`ModalRun`] of checked views: `pseudo` and `q` of one shape, `(rows, n)` with `n`
/// the modes of `modes = (omega, c)`; `step` is `(h, k, span)`.
fn modal_run<'a>(
    pseudo: &'a PyReadonlyArray2<'_, f64>,
    q: &'a PyReadonlyArray2<'_, f64>,
    modes: (&'a [f64], &'a [f64]),
    moments: &'a [f64],
    step: (f64, usize, f64),
) -> PyResult<ModalRun<'a>> {
    let (omega, c) = modes;
    let n = omega.len();
    if pseudo.shape()[1] != n {
        return Err(shape_error(
            "pseudo",
            format!("(rows, {n})"),
            pseudo.shape(),
        ));
    }
    if q.shape() != pseudo.shape() {
        return Err(shape_error("q", format!("{:?}", pseudo.shape()), q.shape()));
    }
    let (h, k, span) = step;
    Ok(ModalRun {
        pseudo: pseudo.as_slice()?,
        q: q.as_slice()?,
        rows: pseudo.shape()[0],
        omega,
        c,
        moments,
        h,
        k,
        span,
    })
}

/// Work on histories of fewer values than this keeps the GIL: releasing and taking it again
/// costs more than such a pass (microseconds), and no other thread gains from it.
const DETACH_FROM: usize = 20_000;

/// `f()`, with the GIL released when it passes over `values` history values (at least
/// [`DETACH_FROM`]), so that other Python threads (`solve_many`'s) run meanwhile.
fn detached<T: Send>(py: Python<'_>, values: usize, f: impl FnOnce() -> T + Send) -> T {
    if values >= DETACH_FROM {
        py.detach(f)
    } else {
        f()
    }
}

/// [`accuracy::mode_bounds`] of checked views, with the GIL released (a pass over the
/// whole history: other Python threads, as `solve_many`'s, run meanwhile); `step` is
/// `(h, k, span)`.
fn bounds_of(
    py: Python<'_>,
    pseudo: &PyReadonlyArray2<'_, f64>,
    q: &PyReadonlyArray2<'_, f64>,
    modes: (&[f64], &[f64]),
    moments: &[f64],
    step: (f64, usize, f64),
) -> PyResult<Vec<f64>> {
    let run = modal_run(pseudo, q, modes, moments, step)?;
    Ok(detached(py, run.rows * run.omega.len(), || {
        accuracy::mode_bounds(&run)
    }))
}

/// [`accuracy::row_errors`] of checked views, with the GIL released: `modes` is `(omega,
/// c)`, `signed` the `(g, n)` row-major shapes and `g`, `step` `(h, k, span)`; the rows'
/// estimates and bounds.
pub(crate) fn errors_of(
    py: Python<'_>,
    pseudo: &PyReadonlyArray2<'_, f64>,
    q: &PyReadonlyArray2<'_, f64>,
    modes: (&[f64], &[f64]),
    moments: &[f64],
    signed: (&[f64], usize),
    step: (f64, usize, f64),
) -> PyResult<(Vec<f64>, Vec<f64>)> {
    let run = modal_run(pseudo, q, modes, moments, step)?;
    let (shapes, g) = signed;
    let n = modes.0.len();
    if shapes.len() != g * n {
        return Err(shape_error(
            "signed",
            format!("({g}, {n})"),
            &[shapes.len()],
        ));
    }
    Ok(detached(py, run.rows * run.omega.len(), || {
        accuracy::row_errors(&run, shapes)
    }))
}

/// The run's error at each row of `signed` (`(g, n)`: mode shapes with their signs at the
/// quantities' components) from its modal history `pseudo` and `q` (`(rows, n)`), the modes
/// `omega`, `c` and `step = (h, k, span)` (`duhamel_core::accuracy::row_errors`).
#[pyfunction]
pub(crate) fn row_errors<'py>(
    py: Python<'py>,
    pseudo: &Bound<'py, PyAny>,
    q: &Bound<'py, PyAny>,
    omega: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    signed: &Bound<'py, PyAny>,
    step: (f64, usize, f64),
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    guarded(|| {
        check_step(step.0, step.1)?;
        let omega = f64_array1(omega, "omega")?;
        let c = f64_array1(c, "c")?;
        let (omega, c) = (omega.as_slice()?, c.as_slice()?);
        if c.len() != omega.len() {
            return Err(shape_error("c", format!("({},)", omega.len()), &[c.len()]));
        }
        let (pseudo, q, signed) = (
            matrix(pseudo, "pseudo")?,
            matrix(q, "q")?,
            matrix(signed, "signed")?,
        );
        let g = signed.shape()[0];
        let moments = accuracy::parabola_moments(omega, c, step.0);
        let shapes = (signed.as_slice()?, g);
        let (out, _) = errors_of(py, &pseudo, &q, (omega, c), &moments, shapes, step)?;
        Ok(PyArray1::from_vec(py, out))
    })
}
