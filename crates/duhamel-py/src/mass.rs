//! Time-varying mass laws (`duhamel.mass`), as typed values.

use duhamel_core::mass::{MassForm, MassLaw as CoreLaw, MassTreatment, TimeVaryingMass};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::vec_of;
use crate::values::{from_json, to_json};

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

    /// The law as JSON text (what a store keeps of a mass law).
    fn _to_value(&self) -> PyResult<String> {
        to_json(&self.0)
    }

    /// The law of `_to_value`'s text.
    #[staticmethod]
    fn _from_value(text: &str) -> PyResult<Self> {
        Ok(MassLaw(from_json(text, "a mass law")?))
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

/// The mass of a run: the law `mu(t)`, the `form` of the inertia term ("acceleration":
/// `mu M x''`, or "momentum": `(mu M x')'`), whether the stiffness scales with the mass, and
/// the semi-analytic `treatment` ("eliminate" or "estimate"; the direct integrators ignore
/// it). Checked when made.
#[pyclass(frozen, name = "Mass", module = "duhamel._core")]
pub(crate) struct Mass(pub(crate) TimeVaryingMass);

#[pymethods]
impl Mass {
    #[new]
    fn new(law: &MassLaw, form: &str, scale_stiffness: bool, treatment: &str) -> PyResult<Self> {
        let form = match form {
            "acceleration" => MassForm::Acceleration,
            "momentum" => MassForm::Momentum,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`form` must be 'acceleration' or 'momentum', got {other:?}"
                )))
            }
        };
        let treatment = match treatment {
            "eliminate" => MassTreatment::Eliminate,
            "estimate" => MassTreatment::Estimate,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`mass_treatment` must be 'eliminate' or 'estimate', got {other:?}"
                )))
            }
        };
        Ok(Mass(TimeVaryingMass {
            law: law.0.clone(),
            form,
            scale_stiffness,
            treatment,
        }))
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}
