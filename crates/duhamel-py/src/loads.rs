//! Loads: time functions as typed values, the loads of a problem, and Python load functions.

use duhamel_core::loads::{Axis, ModalForcing, ModalLoad, TimeFunction as CoreFunction};
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{flat_of, vec_of};
use crate::error::core_err;
use crate::guard::guarded;
use crate::speed::speed_of;

/// A checked scalar function of time, `s(t)`, of a load `pattern * s(t)`.
#[pyclass(frozen, name = "TimeFunction", module = "duhamel._core")]
#[derive(Clone)]
pub(crate) struct TimeFunction(pub(crate) CoreFunction);

#[pymethods]
impl TimeFunction {
    /// Heaviside step at `t0`.
    #[staticmethod]
    fn step(t0: f64) -> PyResult<Self> {
        checked(CoreFunction::Step { t0 })
    }

    /// `sin(omega t + phase)`.
    #[staticmethod]
    fn harmonic(omega: f64, phase: f64) -> PyResult<Self> {
        checked(CoreFunction::Harmonic { omega, phase })
    }

    /// Piecewise-linear through `(t, values)`; 0 outside, or the last value after the end
    /// when `hold`.
    #[staticmethod]
    fn table(t: &Bound<'_, PyAny>, values: &Bound<'_, PyAny>, hold: bool) -> PyResult<Self> {
        checked(CoreFunction::Table {
            t: vec_of(t, "t")?,
            v: vec_of(values, "values")?,
            hold,
        })
    }

    /// One component (`axis` "x" or "y") of an unbalance force per unit `m e` along `law`.
    #[staticmethod]
    fn unbalance(law: &Bound<'_, PyAny>, phase: f64, axis: &str) -> PyResult<Self> {
        let axis = match axis {
            "x" => Axis::X,
            "y" => Axis::Y,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`axis` must be 'x' or 'y', got {other:?}"
                )))
            }
        };
        checked(CoreFunction::Unbalance {
            law: speed_of(law)?,
            phase,
            axis,
        })
    }

    /// The values at the times `t` (right limits at jumps), as the engine evaluates them.
    fn values<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let t = vec_of(t, "t")?;
        let values = guarded(|| Ok(t.iter().map(|&x| self.0.eval(x)).collect()))?;
        Ok(PyArray1::from_vec(py, values))
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

fn checked(f: CoreFunction) -> PyResult<TimeFunction> {
    guarded(|| f.validate().map_err(core_err))?;
    Ok(TimeFunction(f))
}

/// The loads of a problem: a sequence of objects with `pattern` (float64 vector) and `time`
/// (a `_core.TimeFunction`).
pub(crate) fn loads_of(loads: &Bound<'_, PyAny>) -> PyResult<Vec<ModalLoad>> {
    let mut out = Vec::new();
    for item in loads.try_iter()? {
        let item = item?;
        let pattern = vec_of(&item.getattr("pattern")?, "load pattern")?;
        let time = item
            .getattr("time")?
            .cast::<TimeFunction>()?
            .get()
            .0
            .clone();
        out.push(ModalLoad { pattern, time });
    }
    Ok(out)
}

/// Calls a Python function of time and projects its load vector on the modes (or, for the
/// direct integrators, passes the physical load vector on as it is).
pub(crate) struct PyForcing {
    func: Py<PyAny>,
    /// `phi_t[m * n_dof + d]`: mode shapes, transposed; `None` for physical loads.
    phi_t: Option<Vec<f64>>,
    n_dof: usize,
    /// The Python exception that stopped the run.
    pub(crate) error: Option<PyErr>,
}

impl PyForcing {
    /// The forcing of `func` projected on the modes `phi` (`n_dof x n_modes`).
    pub(crate) fn modal(
        func: &Bound<'_, PyAny>,
        phi: &Bound<'_, PyAny>,
        n_modes: usize,
    ) -> PyResult<Option<Self>> {
        if func.is_none() {
            return Ok(None);
        }
        let phi = flat_of(phi, "phi")?;
        let n_dof = phi.len().checked_div(n_modes).unwrap_or(0);
        if n_dof * n_modes != phi.len() {
            return Err(PyValueError::new_err("`phi` must have n_modes columns"));
        }
        let mut phi_t = vec![0.0; phi.len()];
        for d in 0..n_dof {
            for m in 0..n_modes {
                phi_t[m * n_dof + d] = phi[d * n_modes + m];
            }
        }
        Ok(Some(PyForcing {
            func: func.clone().unbind(),
            phi_t: Some(phi_t),
            n_dof,
            error: None,
        }))
    }

    /// The forcing of `func` returning physical loads, used as they are.
    pub(crate) fn physical(func: &Bound<'_, PyAny>, n_dof: usize) -> Option<Self> {
        (!func.is_none()).then(|| PyForcing {
            func: func.clone().unbind(),
            phi_t: None,
            n_dof,
            error: None,
        })
    }

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
                    return Err(CoreError::Callback {
                        time: t,
                        step: 0,
                        message,
                    });
                }
            }
            Ok(())
        })
    }
}
