//! Binding of the nonlinear semi-analytic integrator.

use duhamel_core::elements::Element;
use duhamel_core::linear::{LinearProblem, ModalForcing};
use duhamel_core::mass::{MassForm, MassLaw, MassTreatment, TimeVaryingMass};
use duhamel_core::semianalytic::{
    self, NonlinearProblem, Options, Quadrature, ScaledCoupling, Scheme, Solver,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::elements;
use crate::run::{finish_run, modal_inputs, parse_speed, PyForcing};
use crate::vec_of;

fn parse_options(options: &Bound<'_, PyAny>) -> PyResult<Options> {
    let scheme = match options.get_item(0)?.extract::<String>()?.as_str() {
        "a" => Scheme::A,
        "b" => Scheme::B,
        "c" => Scheme::C,
        other => {
            return Err(PyValueError::new_err(format!(
                "`scheme` must be 'a', 'b' or 'c', got {other:?}"
            )))
        }
    };
    let quadrature = match options.get_item(1)?.extract::<String>()?.as_str() {
        "trapezoid" => Quadrature::Trapezoid,
        "parabolic" => Quadrature::Parabolic,
        "exact" => Quadrature::Exact,
        other => {
            return Err(PyValueError::new_err(format!(
                "`quadrature` must be 'trapezoid', 'parabolic' or 'exact', got {other:?}"
            )))
        }
    };
    let solver = match options.get_item(4)?.extract::<String>()?.as_str() {
        "auto" => Solver::Auto,
        "newton" => Solver::Newton,
        other => {
            return Err(PyValueError::new_err(format!(
                "`solver` must be 'auto' or 'newton', got {other:?}"
            )))
        }
    };
    Ok(Options {
        scheme,
        quadrature,
        tol: options.get_item(2)?.extract()?,
        max_iter: options.get_item(3)?.extract()?,
        solver,
    })
}

pub(crate) fn parse_mass(mass: &Bound<'_, PyAny>) -> PyResult<TimeVaryingMass> {
    let kind: String = mass.get_item(0)?.extract()?;
    let p = mass.get_item(1)?;
    let law = match kind.as_str() {
        "exponential" => MassLaw::Exponential {
            rate: p.get_item(0)?.extract()?,
            scale: p.get_item(1)?.extract()?,
        },
        "harmonic" => MassLaw::Harmonic {
            amplitude: p.get_item(0)?.extract()?,
            frequency: p.get_item(1)?.extract()?,
        },
        "table" => MassLaw::Table {
            t: vec_of(&p.get_item(0)?, "t")?,
            mu: vec_of(&p.get_item(1)?, "mu")?,
        },
        other => return Err(PyValueError::new_err(format!("unknown mass law {other:?}"))),
    };
    let form = match mass.get_item(2)?.extract::<String>()?.as_str() {
        "acceleration" => MassForm::Acceleration,
        "momentum" => MassForm::Momentum,
        other => {
            return Err(PyValueError::new_err(format!(
                "`form` must be 'acceleration' or 'momentum', got {other:?}"
            )))
        }
    };
    // Direct integrators pass no treatment: the mass law enters their equation as it is.
    let treatment = if mass.len()? < 5 {
        "eliminate".to_string()
    } else {
        mass.get_item(4)?.extract::<String>()?
    };
    let treatment = match treatment.as_str() {
        "eliminate" => MassTreatment::Eliminate,
        "estimate" => MassTreatment::Estimate,
        other => {
            return Err(PyValueError::new_err(format!(
                "`mass_treatment` must be 'eliminate' or 'estimate', got {other:?}"
            )))
        }
    };
    Ok(TimeVaryingMass {
        law,
        form,
        scale_stiffness: mass.get_item(3)?.extract()?,
        treatment,
    })
}

pub(crate) fn optional_matrix(
    obj: Option<&Bound<'_, PyAny>>,
    name: &str,
) -> PyResult<Option<Vec<f64>>> {
    obj.map(|m| vec_of(&m.call_method0("ravel")?, name))
        .transpose()
}

/// Integrates a nonlinear modal problem; see `duhamel.solve`.
///
/// `phi` is the `(n_dof, n_modes)` mode-shape matrix, `elements` a list of `(kind, ...)`
/// tuples, `coupling_k`/`coupling_c` modal coupling matrices, `mass` a
/// `(kind, params, form, scale_stiffness, treatment)` tuple, `options`
/// `(scheme, quadrature, tol, max_iter, solver)` and `scaled` a list of
/// `(modal K or None, modal C or None, speed law spec)` couplings scaled by a speed law. Returns the history dict of `solve_linear`
/// with `pseudo` (the modal pseudo-force at the saved states) and `stats`.
#[pyfunction]
#[pyo3(signature = (k, c, q0, v0, loads, dt, n_steps, save_every, phi, elements, options, coupling_k=None, coupling_c=None, mass=None, forcing=None, phi_t=None, scaled=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn solve_nonlinear<'py>(
    py: Python<'py>,
    k: &Bound<'py, PyAny>,
    c: &Bound<'py, PyAny>,
    q0: &Bound<'py, PyAny>,
    v0: &Bound<'py, PyAny>,
    loads: &Bound<'py, PyAny>,
    dt: f64,
    n_steps: usize,
    save_every: usize,
    phi: &Bound<'py, PyAny>,
    elements: &Bound<'py, PyAny>,
    options: &Bound<'py, PyAny>,
    coupling_k: Option<&Bound<'py, PyAny>>,
    coupling_c: Option<&Bound<'py, PyAny>>,
    mass: Option<&Bound<'py, PyAny>>,
    forcing: Option<Py<PyAny>>,
    phi_t: Option<&Bound<'py, PyAny>>,
    scaled: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (k, c, q0, v0, loads) = modal_inputs(k, c, q0, v0, loads)?;
    let phi_v = vec_of(&phi.call_method0("ravel")?, "phi")?;
    let n_dof = if k.is_empty() {
        0
    } else {
        phi_v.len() / k.len()
    };
    let (boxed, python) = elements::parse(elements)?;
    let refs: Vec<&dyn Element> = boxed.iter().map(|b| b.as_ref()).collect();
    let coupling_k = optional_matrix(coupling_k, "coupling_k")?;
    let coupling_c = optional_matrix(coupling_c, "coupling_c")?;
    let mass = mass.map(parse_mass).transpose()?;
    let options = parse_options(options)?;
    let mut scaled_mats = Vec::new();
    if let Some(list) = scaled {
        for item in list.try_iter()? {
            let item = item?;
            let opt = |i: usize, name: &str| -> PyResult<Option<Vec<f64>>> {
                let m = item.get_item(i)?;
                optional_matrix((!m.is_none()).then_some(&m), name)
            };
            scaled_mats.push((
                opt(0, "scaled coupling K")?,
                opt(1, "scaled coupling C")?,
                parse_speed(&item.get_item(2)?)?,
            ));
        }
    }
    let scaled: Vec<ScaledCoupling> = scaled_mats
        .iter()
        .map(|(k, c, law)| ScaledCoupling {
            k: k.as_deref(),
            c: c.as_deref(),
            law: *law,
        })
        .collect();
    let mut py_forcing = PyForcing::new(forcing, phi_t, k.len())?;
    let problem = NonlinearProblem {
        base: LinearProblem {
            k: &k,
            c: &c,
            q0: &q0,
            v0: &v0,
            loads: &loads,
            dt,
            n_steps,
            save_every,
            threads: Some(1),
        },
        phi: &phi_v,
        n_dof,
        elements: &refs,
        coupling_k: coupling_k.as_deref(),
        coupling_c: coupling_c.as_deref(),
        scaled: &scaled,
        mass: mass.as_ref(),
        options,
    };
    let result = py.detach(|| {
        let f = py_forcing.as_mut().map(|f| f as &mut dyn ModalForcing);
        semianalytic::integrate(&problem, f)
    });
    finish_run(py, result, py_forcing, &python, |s, st| {
        st.set_item("newton_iterations", s.newton_iterations)?;
        st.set_item("closed_form_steps", s.closed_form_steps)
    })
}
