//! `duhamel._core`: the thin PyO3 binding of `duhamel-core`.
//!
//! Inputs are checked and copied into Rust values first; the time loop then runs with the
//! GIL released. A Python load callable is called with the GIL, once per evaluation time.

use duhamel_core::linear::{self, Failure, History, LinearProblem, ModalForcing};
use duhamel_core::loads::{ModalLoad, TimeFunction};
use duhamel_core::{CoreError, Transfer};
use numpy::{
    PyArray1, PyArray2, PyArray3, PyArrayMethods, PyReadonlyArray1, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// `(A, B)` or `(A, M)` stacks returned to Python.
type MatrixPair<'py> = (Bound<'py, PyArray3<f64>>, Bound<'py, PyArray3<f64>>);

/// A read-only float64 1-D view of `obj`, or a TypeError/ValueError naming `name`.
fn f64_array1<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<PyReadonlyArray1<'py, f64>> {
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

fn vec_of(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<f64>> {
    Ok(f64_array1(obj, name)?.as_slice()?.to_vec())
}

fn core_err(e: CoreError) -> PyErr {
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

/// Parses `(pattern, kind, params)` load tuples.
fn parse_loads(loads: &Bound<'_, PyAny>) -> PyResult<Vec<ModalLoad>> {
    let mut out = Vec::new();
    for item in loads.try_iter()? {
        let item = item?;
        let tup = item
            .cast::<PyTuple>()
            .map_err(|_| PyTypeError::new_err("load spec must be a tuple"))?;
        let pattern = vec_of(&tup.get_item(0)?, "load pattern")?;
        let kind: String = tup.get_item(1)?.extract()?;
        let params = tup.get_item(2)?;
        let time = match kind.as_str() {
            "step" => TimeFunction::Step {
                t0: params.get_item(0)?.extract()?,
            },
            "harmonic" => TimeFunction::Harmonic {
                omega: params.get_item(0)?.extract()?,
                phase: params.get_item(1)?.extract()?,
            },
            "table" => TimeFunction::Table {
                t: vec_of(&params.get_item(0)?, "t")?,
                v: vec_of(&params.get_item(1)?, "values")?,
                hold: params.get_item(2)?.extract()?,
            },
            other => {
                return Err(PyValueError::new_err(format!(
                    "unknown load kind {other:?}"
                )))
            }
        };
        time.validate().map_err(core_err)?;
        out.push(ModalLoad { pattern, time });
    }
    Ok(out)
}

/// Calls a Python function of time and projects its load vector on the modes.
struct PyForcing {
    func: Py<PyAny>,
    /// `phi_t[m * n_dof + d]`: mode shapes, transposed.
    phi_t: Vec<f64>,
    n_dof: usize,
    /// The Python exception that stopped the run, re-raised by the caller.
    error: Option<PyErr>,
}

impl PyForcing {
    fn eval(&self, py: Python<'_>, t: f64, out: &mut [f64]) -> PyResult<()> {
        let res = self.func.call1(py, (t,))?;
        let np = py.import("numpy")?;
        let arr = np.call_method1("asarray", (res.bind(py), "float64"))?;
        let n_dof = self.n_dof;
        let bad =
            |what: String| PyValueError::new_err(format!("the `Callable` load {what} at t = {t}"));
        let arr = arr
            .cast::<PyArray1<f64>>()
            .map_err(|_| bad(format!("returned a non-vector, expected shape ({n_dof},)")))?;
        let ro = arr.readonly();
        let f = ro.as_slice()?;
        if f.len() != n_dof {
            return Err(bad(format!(
                "returned shape ({},), expected ({n_dof},)",
                f.len()
            )));
        }
        if let Some(i) = f.iter().position(|x| !x.is_finite()) {
            return Err(bad(format!("returned a non-finite value at dof {i}")));
        }
        for (m, o) in out.iter_mut().enumerate() {
            let row = &self.phi_t[m * n_dof..(m + 1) * n_dof];
            *o = row.iter().zip(f).map(|(p, x)| p * x).sum();
        }
        Ok(())
    }
}

impl ModalForcing for PyForcing {
    fn modal_loads(&mut self, times: &[f64], out: &mut [f64]) -> Result<(), CoreError> {
        let n_modes = out.len() / times.len().max(1);
        Python::attach(|py| {
            for (j, &t) in times.iter().enumerate() {
                if let Err(err) = self.eval(py, t, &mut out[j * n_modes..(j + 1) * n_modes]) {
                    let message = err.to_string();
                    self.error = Some(err);
                    return Err(CoreError::Callback { time: t, message });
                }
            }
            Ok(())
        })
    }
}

fn history_dict<'py>(py: Python<'py>, h: History) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (nm, ns) = (h.n_modes, h.t.len());
    let n_loads = h.load_values.len() / ns.max(1);
    d.set_item("t", PyArray1::from_vec(py, h.t))?;
    let as2 = |v: Vec<f64>, cols: usize| -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray1::from_vec(py, v).reshape([ns, cols])
    };
    d.set_item("q", as2(h.q, nm)?)?;
    d.set_item("v", as2(h.v, nm)?)?;
    d.set_item("load_values", as2(h.load_values, n_loads)?)?;
    if h.forcing.is_empty() {
        d.set_item("forcing", py.None())?;
    } else {
        d.set_item("forcing", as2(h.forcing, nm)?)?;
    }
    Ok(d)
}

/// Integrates uncoupled modal oscillators exactly; see `duhamel.solve`.
///
/// Returns a dict with `t`, time-major `q` and `v` (`(n_saved, n_modes)`), `load_values`
/// (`(n_saved, n_loads)`: each load's time function at the saved instants), `forcing`
/// (modal forcing at the saved instants, or None) and `error`: None, or a dict with `kind`,
/// `message`, `time`, `step` when the run stopped early (the arrays then hold the history up
/// to the last good saved instant).
#[pyfunction]
#[pyo3(signature = (k, c, q0, v0, loads, dt, n_steps, save_every, threads=None, forcing=None, phi_t=None))]
#[allow(clippy::too_many_arguments)]
fn solve_linear<'py>(
    py: Python<'py>,
    k: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    q0: &Bound<'py, PyAny>,
    v0: &Bound<'py, PyAny>,
    loads: &Bound<'py, PyAny>,
    dt: f64,
    n_steps: usize,
    save_every: usize,
    threads: Option<usize>,
    forcing: Option<Py<PyAny>>,
    phi_t: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let k = vec_of(k, "omega2")?;
    let c = vec_of(c, "c")?;
    let q0 = vec_of(q0, "x0")?;
    let v0 = vec_of(v0, "v0")?;
    let loads = parse_loads(loads)?;
    let mut py_forcing = match forcing {
        Some(func) => {
            let phi_t =
                phi_t.ok_or_else(|| PyValueError::new_err("`phi_t` is needed with `forcing`"))?;
            let phi = vec_of(&phi_t.call_method0("ravel")?, "phi_t")?;
            let n_dof = if k.is_empty() { 0 } else { phi.len() / k.len() };
            if n_dof * k.len() != phi.len() {
                return Err(PyValueError::new_err("`phi_t` must have n_modes rows"));
            }
            Some(PyForcing {
                func,
                phi_t: phi,
                n_dof,
                error: None,
            })
        }
        None => None,
    };
    let problem = LinearProblem {
        k: &k,
        c: &c,
        q0: &q0,
        v0: &v0,
        loads: &loads,
        dt,
        n_steps,
        save_every,
        threads,
    };
    let result = py.detach(|| {
        let f = py_forcing.as_mut().map(|f| f as &mut dyn ModalForcing);
        linear::integrate(&problem, f)
    });
    match result {
        Ok(h) => {
            let d = history_dict(py, h)?;
            d.set_item("error", py.None())?;
            Ok(d)
        }
        Err(failure) => {
            let Failure { error, partial } = *failure;
            // A failing Python load function: re-raise its own exception, noting the time.
            if let (Some(err), CoreError::Callback { time, .. }) =
                (py_forcing.and_then(|f| f.error), &error)
            {
                let note = format!("raised by the `Callable` load at t = {time}");
                err.value(py).call_method1("add_note", (note,))?;
                return Err(err);
            }
            let (kind, time, step) = match &error {
                CoreError::NonFinite { time, step, .. } => ("nonfinite", *time, *step),
                CoreError::Callback { time, .. } => ("callback", *time, 0),
                _ => return Err(core_err(error)),
            };
            let d = history_dict(py, partial)?;
            let e = PyDict::new(py);
            e.set_item("kind", kind)?;
            e.set_item("message", error.to_string())?;
            e.set_item("time", time)?;
            e.set_item("step", step)?;
            d.set_item("error", e)?;
            Ok(d)
        }
    }
}

/// The native core of duhamel.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(transfer, m)?)?;
    m.add_function(wrap_pyfunction!(transfer_kc, m)?)?;
    m.add_function(wrap_pyfunction!(solve_linear, m)?)?;
    Ok(())
}
