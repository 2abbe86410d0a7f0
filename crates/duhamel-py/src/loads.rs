//! Loads: time functions as typed values, the loads of a problem, and Python load functions.

use duhamel_core::loads::{Axis, Coupling, ModalForcing, ModalLoad, TimeFunction as CoreFunction};
use duhamel_core::CoreError;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::vec_of;
use crate::error::core_err;
use crate::guard::guarded;
use crate::speed::speed_of;
use crate::values::{from_json, to_json};

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
        checked(CoreFunction::Unbalance {
            law: speed_of(law)?,
            phase,
            axis: axis_of(axis)?,
        })
    }

    /// One component (`axis` "x" or "y") of a misaligned flexible coupling's reaction force
    /// (N) at the angle of `law`: shaft `radius`, `parallel = (delta_x, delta_y,
    /// radial_stiffness)`, `angular = (angle, bending_stiffness)`.
    #[staticmethod]
    fn misalignment(
        law: &Bound<'_, PyAny>,
        radius: f64,
        parallel: (f64, f64, f64),
        angular: (f64, f64),
        axis: &str,
    ) -> PyResult<Self> {
        let coupling = Coupling {
            radius,
            delta: [parallel.0, parallel.1],
            radial_stiffness: parallel.2,
            angle: angular.0,
            bending_stiffness: angular.1,
        };
        checked(CoreFunction::Misalignment {
            coupling,
            law: speed_of(law)?,
            axis: axis_of(axis)?,
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

    /// The function as JSON text (what a store keeps of a load's time function).
    fn _to_value(&self) -> PyResult<String> {
        to_json(&self.0)
    }

    /// The function of `_to_value`'s text, checked as when made.
    #[staticmethod]
    fn _from_value(text: &str) -> PyResult<Self> {
        checked(from_json(text, "a load's time function")?)
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

fn axis_of(axis: &str) -> PyResult<Axis> {
    match axis {
        "x" => Ok(Axis::X),
        "y" => Ok(Axis::Y),
        other => Err(PyValueError::new_err(format!(
            "`axis` must be 'x' or 'y', got {other:?}"
        ))),
    }
}

fn checked(f: CoreFunction) -> PyResult<TimeFunction> {
    guarded(|| f.validate().map_err(core_err))?;
    Ok(TimeFunction(f))
}

/// A built-in load of a model: `pattern * s(t)` (modal pattern for the modal routes,
/// physical for the direct integrators), checked when made.
#[pyclass(frozen, name = "Load", module = "duhamel._core")]
pub(crate) struct Load(pub(crate) ModalLoad);

#[pymethods]
impl Load {
    #[new]
    fn new(pattern: &Bound<'_, PyAny>, time: &TimeFunction) -> PyResult<Self> {
        let pattern = vec_of(pattern, "load pattern")?;
        if let Some(i) = pattern.iter().position(|x| !x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "a load's pattern must be finite, got {} at entry {i}",
                pattern[i]
            )));
        }
        Ok(Load(ModalLoad {
            pattern,
            time: time.0.clone(),
        }))
    }

    /// The load's pattern.
    #[getter]
    fn pattern<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.0.pattern)
    }

    /// The load's time function.
    #[getter]
    fn time(&self) -> TimeFunction {
        TimeFunction(self.0.time.clone())
    }
}

/// The core's loads of a sequence of `_core.Load`s.
pub(crate) fn owned_loads(loads: &[PyRef<'_, Load>]) -> Vec<ModalLoad> {
    loads.iter().map(|l| l.0.clone()).collect()
}

/// Mode shapes `phi` (`n_dof x n_modes`, row-major), transposed: what [`PyForcing`]
/// projects a physical load vector with.
pub(crate) fn transposed(phi: &[f64], n_dof: usize, n_modes: usize) -> Vec<f64> {
    let mut phi_t = vec![0.0; phi.len()];
    for d in 0..n_dof {
        for m in 0..n_modes {
            phi_t[m * n_dof + d] = phi[d * n_modes + m];
        }
    }
    phi_t
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
    /// The forcing of `func` projected with the transposed mode shapes `phi_t`
    /// (`n_modes x n_dof`, see [`transposed`]).
    pub(crate) fn projected(func: &Bound<'_, PyAny>, phi_t: &[f64], n_dof: usize) -> Option<Self> {
        (!func.is_none()).then(|| PyForcing {
            func: func.clone().unbind(),
            phi_t: Some(phi_t.to_vec()),
            n_dof,
            error: None,
        })
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
