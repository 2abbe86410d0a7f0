//! The linear time loop's binding and what every run shares: loads, Python load functions,
//! and the conversion of a history or a failure into Python objects.

use duhamel_core::linear::{self, Failure, History, LinearProblem, ModalForcing};
use duhamel_core::loads::{Axis, ModalLoad, TimeFunction};
use duhamel_core::speed::SpeedLaw;
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::{core_err, vec_of};

/// Parses a speed law spec `("constant", (omega,))` or `("runup", (omega0, omega1, t1))`
/// and checks it (errors name the parameter).
pub(crate) fn parse_speed(spec: &Bound<'_, PyAny>) -> PyResult<SpeedLaw> {
    let kind: String = spec.get_item(0)?.extract()?;
    let p = spec.get_item(1)?;
    let law = match kind.as_str() {
        "constant" => SpeedLaw::Constant(p.get_item(0)?.extract()?),
        "runup" => SpeedLaw::LinearRunUp {
            omega0: p.get_item(0)?.extract()?,
            omega1: p.get_item(1)?.extract()?,
            t1: p.get_item(2)?.extract()?,
        },
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown speed law {other:?}"
            )))
        }
    };
    law.validate().map_err(core_err)?;
    Ok(law)
}

/// The speed law `spec` (see [`parse_speed`]) at the times `t`: `(omega, omega', theta)`
/// arrays, `omega'` right-continuous.
#[pyfunction]
pub(crate) fn speed_law<'py>(
    py: Python<'py>,
    spec: &Bound<'py, PyAny>,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyTuple>> {
    let law = parse_speed(spec)?;
    let t = vec_of(t, "t")?;
    let omega: Vec<f64> = t.iter().map(|&x| law.omega(x)).collect();
    let domega: Vec<f64> = t.iter().map(|&x| law.domega(x)).collect();
    let theta: Vec<f64> = t.iter().map(|&x| law.theta(x)).collect();
    PyTuple::new(
        py,
        [
            PyArray1::from_vec(py, omega),
            PyArray1::from_vec(py, domega),
            PyArray1::from_vec(py, theta),
        ],
    )
}

/// The values of the time function of load spec `(kind, params)` at the times `t` (right
/// limits at jumps), as the engine evaluates them.
#[pyfunction]
pub(crate) fn time_function<'py>(
    py: Python<'py>,
    kind: &str,
    params: &Bound<'py, PyAny>,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let f = parse_time(kind, params)?;
    let t = vec_of(t, "t")?;
    Ok(PyArray1::from_vec(
        py,
        t.iter().map(|&x| f.eval(x)).collect(),
    ))
}

/// The time function of a load spec, checked.
fn parse_time(kind: &str, params: &Bound<'_, PyAny>) -> PyResult<TimeFunction> {
    let time = match kind {
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
        "unbalance" => TimeFunction::Unbalance {
            law: parse_speed(&params.get_item(0)?)?,
            phase: params.get_item(1)?.extract()?,
            axis: match params.get_item(2)?.extract::<String>()?.as_str() {
                "x" => Axis::X,
                "y" => Axis::Y,
                other => {
                    return Err(PyValueError::new_err(format!(
                        "unbalance axis must be 'x' or 'y', got {other:?}"
                    )))
                }
            },
        },
        other => {
            return Err(PyValueError::new_err(format!(
                "unknown load kind {other:?}"
            )))
        }
    };
    time.validate().map_err(core_err)?;
    Ok(time)
}

/// The modal stiffness, damping, initial state and loads every modal run takes.
pub(crate) type ModalInputs = (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<ModalLoad>);

/// Extracts [`ModalInputs`], naming the Python parameter on a bad array.
pub(crate) fn modal_inputs(
    k: &Bound<'_, PyAny>,
    c: &Bound<'_, PyAny>,
    q0: &Bound<'_, PyAny>,
    v0: &Bound<'_, PyAny>,
    loads: &Bound<'_, PyAny>,
) -> PyResult<ModalInputs> {
    Ok((
        vec_of(k, "omega2")?,
        vec_of(c, "c")?,
        vec_of(q0, "x0")?,
        vec_of(v0, "v0")?,
        parse_loads(loads)?,
    ))
}

/// Parses `(pattern, kind, params)` load tuples.
pub(crate) fn parse_loads(loads: &Bound<'_, PyAny>) -> PyResult<Vec<ModalLoad>> {
    let mut out = Vec::new();
    for item in loads.try_iter()? {
        let item = item?;
        let tup = item
            .cast::<PyTuple>()
            .map_err(|_| PyTypeError::new_err("load spec must be a tuple"))?;
        let pattern = vec_of(&tup.get_item(0)?, "load pattern")?;
        let kind: String = tup.get_item(1)?.extract()?;
        let time = parse_time(&kind, &tup.get_item(2)?)?;
        out.push(ModalLoad { pattern, time });
    }
    Ok(out)
}

/// Calls a Python function of time and projects its load vector on the modes (or, for the
/// direct integrators, passes the physical load vector on as it is).
pub(crate) struct PyForcing {
    func: Py<PyAny>,
    /// `phi_t[m * n_dof + d]`: mode shapes, transposed; `None` for physical loads (no
    /// projection: the direct integrators).
    phi_t: Option<Vec<f64>>,
    n_dof: usize,
    /// The Python exception that stopped the run, re-raised by the caller.
    pub(crate) error: Option<PyErr>,
}

impl PyForcing {
    /// The forcing of a Python function of time, projected with `phi_t` (`n_modes x n_dof`).
    pub(crate) fn new(
        func: Option<Py<PyAny>>,
        phi_t: Option<&Bound<'_, PyAny>>,
        n_modes: usize,
    ) -> PyResult<Option<Self>> {
        let Some(func) = func else {
            return Ok(None);
        };
        let phi_t =
            phi_t.ok_or_else(|| PyValueError::new_err("`phi_t` is needed with `forcing`"))?;
        let phi = vec_of(&phi_t.call_method0("ravel")?, "phi_t")?;
        let n_dof = phi.len().checked_div(n_modes).unwrap_or(0);
        if n_dof * n_modes != phi.len() {
            return Err(PyValueError::new_err("`phi_t` must have n_modes rows"));
        }
        Ok(Some(PyForcing {
            func,
            phi_t: Some(phi),
            n_dof,
            error: None,
        }))
    }

    /// The forcing of a Python function of time returning physical loads, used as they are.
    pub(crate) fn physical(func: Option<Py<PyAny>>, n_dof: usize) -> Option<Self> {
        func.map(|func| PyForcing {
            func,
            phi_t: None,
            n_dof,
            error: None,
        })
    }
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
        match &self.phi_t {
            Some(phi_t) => {
                for (m, o) in out.iter_mut().enumerate() {
                    let row = &phi_t[m * n_dof..(m + 1) * n_dof];
                    *o = row.iter().zip(f).map(|(p, x)| p * x).sum();
                }
            }
            None => out.copy_from_slice(f),
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

/// A saved history that becomes the dict `duhamel.solve` reads.
pub(crate) trait IntoDict {
    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>>;
}

impl IntoDict for History {
    fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
        history_dict(py, self)
    }
}

pub(crate) fn history_dict<'py>(py: Python<'py>, h: History) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (nm, ns) = (h.n_modes, h.t.len());
    let n_loads = h.load_values.len() / ns.max(1);
    d.set_item("t", PyArray1::from_vec(py, h.t))?;
    let as2 = |v: Vec<f64>, cols: usize| -> PyResult<Bound<'py, PyArray2<f64>>> {
        PyArray1::from_vec(py, v).reshape([ns, cols])
    };
    if h.eta.is_empty() {
        d.set_item("q", as2(h.q, nm)?)?;
        d.set_item("v", as2(h.v, nm)?)?;
    } else {
        // A coupled run: first-order coordinates instead of q, v.
        let width = h.eta.len() / ns.max(1);
        d.set_item("eta", as2(h.eta, width)?)?;
        d.set_item("q", py.None())?;
        d.set_item("v", py.None())?;
    }
    if !h.out.is_empty() {
        let width = h.out.len() / ns.max(1);
        d.set_item("out", as2(h.out, width)?)?;
    }
    d.set_item("load_values", as2(h.load_values, n_loads)?)?;
    for (key, values) in [("forcing", h.forcing), ("pseudo", h.pseudo)] {
        if values.is_empty() {
            d.set_item(key, py.None())?;
        } else {
            d.set_item(key, as2(values, nm)?)?;
        }
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
pub(crate) fn solve_linear<'py>(
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
    let (k, c, q0, v0, loads) = modal_inputs(k, c, q0, v0, loads)?;
    let mut py_forcing = PyForcing::new(forcing, phi_t, k.len())?;
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
    finish(py, result, py_forcing.and_then(|f| f.error))
}

/// The Python result of a run: the history dict, with `error` None or describing why the run
/// stopped early (the arrays then hold what was computed). A failing Python callback
/// re-raises its own exception, noting the time; input errors raise ValueError.
pub(crate) fn finish<'py, H: IntoDict>(
    py: Python<'py>,
    result: Result<H, Box<Failure<H>>>,
    py_error: Option<PyErr>,
) -> PyResult<Bound<'py, PyDict>> {
    match result {
        Ok(h) => {
            let d = h.into_dict(py)?;
            d.set_item("error", py.None())?;
            Ok(d)
        }
        Err(failure) => {
            let Failure { error, partial } = *failure;
            // A failing Python load function: re-raise its own exception, noting the time.
            if let (Some(err), CoreError::Callback { time, .. }) = (py_error, &error) {
                let note = format!("raised by the `Callable` load at t = {time}");
                err.value(py).call_method1("add_note", (note,))?;
                return Err(err);
            }
            let (kind, time, step) = match &error {
                CoreError::NonFinite { time, step, .. } => ("nonfinite", *time, *step),
                CoreError::Callback { time, .. } => ("callback", *time, 0),
                CoreError::NoConvergence { time, .. } => ("convergence", *time, 0),
                _ => return Err(core_err(error)),
            };
            let d = partial.into_dict(py)?;
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

/// The Python result of a run that reports statistics: the history dict (see [`finish`])
/// with `stats` set by `fill`; a Python exception raised by the load function or by a Python
/// element is re-raised.
pub(crate) fn finish_run<'py, H: IntoDict, S>(
    py: Python<'py>,
    result: Result<(H, S), Box<Failure<H>>>,
    forcing: Option<PyForcing>,
    python: &[std::sync::Arc<crate::elements::PyElement>],
    fill: impl FnOnce(&S, &Bound<'py, PyDict>) -> PyResult<()>,
) -> PyResult<Bound<'py, PyDict>> {
    let (result, stats) = match result {
        Ok((h, s)) => (Ok(h), Some(s)),
        Err(e) => (Err(e), None),
    };
    let py_error = forcing.and_then(|f| f.error).or_else(|| {
        python
            .iter()
            .find_map(|e| e.error.lock().unwrap_or_else(|p| p.into_inner()).take())
    });
    let d = finish(py, result, py_error)?;
    let st = PyDict::new(py);
    if let Some(s) = &stats {
        fill(s, &st)?;
    }
    d.set_item("stats", st)?;
    Ok(d)
}
