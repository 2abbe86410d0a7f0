//! Binding of the pseudo-force route (the uncoupled background with the corrector).

use duhamel_core::pseudo::{
    self, NonlinearProblem, Options, Quadrature, ScaledCoupling, Scheme, Solver,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{attr, flat_of, optional_flat};
use crate::driver::run;
use crate::elements;
use crate::guard::guarded;
use crate::history::RunResult;
use crate::loads::PyForcing;
use crate::mass::mass_of;
use crate::problem::ModalInput;
use crate::speed::speed_of;

/// The integrator settings of a `duhamel.Semianalytic` (`scheme`, `quadrature`, `tol`,
/// `max_iter`, `solver` attributes).
fn options_of(obj: &Bound<'_, PyAny>) -> PyResult<Options> {
    let choice = |name: &str| attr::<String>(obj, name);
    let scheme = match choice("scheme")?.as_str() {
        "a" => Scheme::A,
        "b" => Scheme::B,
        "c" => Scheme::C,
        other => {
            return Err(PyValueError::new_err(format!(
                "`scheme` must be 'a', 'b' or 'c', got {other:?}"
            )))
        }
    };
    let quadrature = match choice("quadrature")?.as_str() {
        "trapezoid" => Quadrature::Trapezoid,
        "parabolic" => Quadrature::Parabolic,
        "exact" => Quadrature::Exact,
        other => {
            return Err(PyValueError::new_err(format!(
                "`quadrature` must be 'trapezoid', 'parabolic' or 'exact', got {other:?}"
            )))
        }
    };
    let solver = match choice("solver")?.as_str() {
        "auto" => Solver::Auto,
        "newton" => Solver::Newton,
        "modal-newton" => Solver::ModalNewton,
        other => {
            return Err(PyValueError::new_err(format!(
                "`solver` must be 'auto', 'newton' or 'modal-newton', got {other:?}"
            )))
        }
    };
    Ok(Options {
        scheme,
        quadrature,
        tol: attr(obj, "tol")?,
        max_iter: attr(obj, "max_iter")?,
        solver,
        // An integrator object from before the option: the default depth.
        subdivisions: if obj.hasattr("subdivisions")? {
            attr(obj, "subdivisions")?
        } else {
            4
        },
    })
}

/// The optional `element_state` attribute (the elements' committed variables a continued
/// run starts from): None when absent or None.
pub(crate) fn element_state_of(obj: &Bound<'_, PyAny>) -> PyResult<Option<Vec<f64>>> {
    if !obj.hasattr("element_state")? {
        return Ok(None);
    }
    optional_flat(&obj.getattr("element_state")?, "element_state")
}

/// Owned modal couplings scaled by a speed law: `(K, C, law)`.
type Scaled = (
    Option<Vec<f64>>,
    Option<Vec<f64>>,
    duhamel_core::speed::SpeedLaw,
);

/// Integrates a modal problem whose pseudo-force (elements, couplings, mass law) is solved
/// every step; see `duhamel.solve`.
///
/// `nonlinear` has `phi` (`n_dof x m`), `elements` (`_core.Element`s), `options` (with
/// `scheme`, `quadrature`, `tol`, `max_iter`, `solver`), `coupling_k`, `coupling_c` (modal,
/// or None), `scaled` (objects with `k`, `c`, `law`: couplings scaled by a
/// `_core.SpeedLaw`) and `mass` (None, or as `duhamel._core.MassLaw` with form, scaling and
/// treatment).
#[pyfunction]
pub(crate) fn solve_pseudo(
    py: Python<'_>,
    problem: &Bound<'_, PyAny>,
    nonlinear: &Bound<'_, PyAny>,
    forcing: &Bound<'_, PyAny>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    guarded(|| {
        let input = ModalInput::extract(problem)?;
        let mut base = input.problem();
        // One mode-coupled step at a time: a single thread.
        base.threads = Some(1);
        let phi = flat_of(&nonlinear.getattr("phi")?, "phi")?;
        let n_dof = phi.len().checked_div(base.n_modes()).unwrap_or(0);
        let built = elements::build(py, &nonlinear.getattr("elements")?)?;
        let refs = built.refs();
        let coupling_k = optional_flat(&nonlinear.getattr("coupling_k")?, "coupling_k")?;
        let coupling_c = optional_flat(&nonlinear.getattr("coupling_c")?, "coupling_c")?;
        let mass = mass_of(&nonlinear.getattr("mass")?)?;
        let options = options_of(&nonlinear.getattr("options")?)?;
        let element_state = element_state_of(nonlinear)?;
        let mut owned: Vec<Scaled> = Vec::new();
        for item in nonlinear.getattr("scaled")?.try_iter()? {
            let item = item?;
            owned.push((
                optional_flat(&item.getattr("k")?, "scaled coupling K")?,
                optional_flat(&item.getattr("c")?, "scaled coupling C")?,
                speed_of(&item.getattr("law")?)?,
            ));
        }
        let scaled: Vec<ScaledCoupling> = owned
            .iter()
            .map(|(k, c, law)| ScaledCoupling {
                k: k.as_deref(),
                c: c.as_deref(),
                law: *law,
            })
            .collect();
        let problem_nl = NonlinearProblem {
            base,
            phi: &phi,
            n_dof,
            elements: &refs,
            coupling_k: coupling_k.as_deref(),
            coupling_c: coupling_c.as_deref(),
            scaled: &scaled,
            mass: mass.as_ref(),
            options,
            element_state: element_state.as_deref(),
        };
        let forcing =
            PyForcing::modal(forcing, &problem.getattr("phi")?, problem_nl.base.n_modes())?;
        run(py, forcing, Some(&built), progress, |f, control| {
            pseudo::integrate(&problem_nl, f, control)
        })
    })
}
