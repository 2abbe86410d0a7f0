//! Time-varying mass laws (`duhamel.mass`), as typed values.

use duhamel_core::mass::{MassForm, MassLaw as CoreLaw, MassTreatment, TimeVaryingMass};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{attr, vec_of};

/// A mass law `mu(t)` (checked against the run's span when the run starts).
#[pyclass(frozen, name = "MassLaw", module = "duhamel._core")]
#[derive(Clone)]
pub(crate) struct MassLaw(pub(crate) CoreLaw);

#[pymethods]
impl MassLaw {
    /// `mu = scale exp(rate t)`.
    #[staticmethod]
    fn exponential(rate: f64, scale: f64) -> Self {
        MassLaw(CoreLaw::Exponential { rate, scale })
    }

    /// `mu = 1 + amplitude sin(frequency t)`.
    #[staticmethod]
    fn harmonic(amplitude: f64, frequency: f64) -> Self {
        MassLaw(CoreLaw::Harmonic {
            amplitude,
            frequency,
        })
    }

    /// Piecewise-linear `mu` through `(t, mu)`.
    #[staticmethod]
    fn table(t: &Bound<'_, PyAny>, mu: &Bound<'_, PyAny>) -> PyResult<Self> {
        Ok(MassLaw(CoreLaw::Table {
            t: vec_of(t, "t")?,
            mu: vec_of(mu, "mu")?,
        }))
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

/// The mass of a run: an object with `law` (a `_core.MassLaw`), `form` ("acceleration" or
/// "momentum"), `scale_stiffness` (bool) and `treatment` ("eliminate" or "estimate"; the
/// direct integrators ignore it).
pub(crate) fn mass_of(obj: &Bound<'_, PyAny>) -> PyResult<Option<TimeVaryingMass>> {
    if obj.is_none() {
        return Ok(None);
    }
    let law = obj.getattr("law")?.cast::<MassLaw>()?.get().0.clone();
    let form = match attr::<String>(obj, "form")?.as_str() {
        "acceleration" => MassForm::Acceleration,
        "momentum" => MassForm::Momentum,
        other => {
            return Err(PyValueError::new_err(format!(
                "`form` must be 'acceleration' or 'momentum', got {other:?}"
            )))
        }
    };
    let treatment = match attr::<String>(obj, "treatment")?.as_str() {
        "eliminate" => MassTreatment::Eliminate,
        "estimate" => MassTreatment::Estimate,
        other => {
            return Err(PyValueError::new_err(format!(
                "`mass_treatment` must be 'eliminate' or 'estimate', got {other:?}"
            )))
        }
    };
    Ok(Some(TimeVaryingMass {
        law,
        form,
        scale_stiffness: attr(obj, "scale_stiffness")?,
        treatment,
    }))
}
