//! Speed laws (`duhamel.speed`), as a typed value.

use duhamel_core::speed::SpeedLaw as CoreLaw;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::arrays::vec_of;
use crate::error::core_err;
use crate::guard::guarded;
use crate::values::{from_json, to_json};

/// A checked speed law `omega(t)`.
#[pyclass(frozen, name = "SpeedLaw", module = "duhamel._core")]
#[derive(Clone)]
pub(crate) struct SpeedLaw(pub(crate) CoreLaw);

#[pymethods]
impl SpeedLaw {
    /// `omega(t) = omega`.
    #[staticmethod]
    fn constant(omega: f64) -> PyResult<Self> {
        checked(CoreLaw::Constant(omega))
    }

    /// `omega` linear from `omega0` at 0 to `omega1` at `t1`, then held.
    #[staticmethod]
    fn run_up(omega0: f64, omega1: f64, t1: f64) -> PyResult<Self> {
        checked(CoreLaw::LinearRunUp { omega0, omega1, t1 })
    }

    /// `(omega, omega', theta)` at the times `t` (`omega'` right-continuous).
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let law = &self.0;
        let t = vec_of(t, "t")?;
        let (omega, domega, theta) = guarded(|| {
            let omega: Vec<f64> = t.iter().map(|&x| law.omega(x)).collect();
            let domega: Vec<f64> = t.iter().map(|&x| law.domega(x)).collect();
            let theta: Vec<f64> = t.iter().map(|&x| law.theta(x)).collect();
            Ok((omega, domega, theta))
        })?;
        PyTuple::new(
            py,
            [
                PyArray1::from_vec(py, omega),
                PyArray1::from_vec(py, domega),
                PyArray1::from_vec(py, theta),
            ],
        )
    }

    /// The law as JSON text (a number, or `{"omega0", "omega1", "t1"}`).
    fn _to_value(&self) -> PyResult<String> {
        to_json(&self.0)
    }

    /// The law of `_to_value`'s text, checked as when made.
    #[staticmethod]
    fn _from_value(text: &str) -> PyResult<Self> {
        checked(from_json(text, "a speed law")?)
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

fn checked(law: CoreLaw) -> PyResult<SpeedLaw> {
    guarded(|| law.validate().map_err(core_err))?;
    Ok(SpeedLaw(law))
}

/// The speed law of a Python `_core.SpeedLaw` object.
pub(crate) fn speed_of(obj: &Bound<'_, PyAny>) -> PyResult<CoreLaw> {
    Ok(obj.cast::<SpeedLaw>()?.get().0)
}
