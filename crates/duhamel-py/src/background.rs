//! Binding of the background propagators' routes: uncoupled oscillators, first-order modes.

use duhamel_core::background::first_order::{self, FirstOrderModes};
use duhamel_core::background::uncoupled;
use duhamel_core::output::Outputs;
use duhamel_core::pseudo::first_order::Nonlinear;
use pyo3::prelude::*;

use crate::arrays::{attr, flat_of};
use crate::driver::run;
use crate::elements;
use crate::guard::guarded;
use crate::history::RunResult;
use crate::loads::PyForcing;
use crate::problem::ModalInput;

/// Integrates uncoupled modal oscillators exactly; see `duhamel.solve`.
///
/// `problem` has the attributes of `duhamel._solve.plan.ModalSpec` (`phi` is used to project
/// `forcing`, a Python function of time returning the physical load vector, or None);
/// `progress` is None or a function `(step, n_steps, t)` called between blocks.
#[pyfunction]
pub(crate) fn solve_uncoupled(
    py: Python<'_>,
    problem: &Bound<'_, PyAny>,
    forcing: &Bound<'_, PyAny>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    guarded(|| {
        let input = ModalInput::extract(problem)?;
        let p = input.problem();
        let forcing = PyForcing::modal(forcing, &problem.getattr("phi")?, p.n_modes())?;
        run(py, forcing, None, progress, |f, control| {
            uncoupled::integrate(&p, f, control).map(|h| (h, ()))
        })
    })
}

/// Owned first-order modes: `lambda_re`, `lambda_im`, `gain_re`, `gain_im` (`r x m`),
/// `eta0_re`, `eta0_im` attributes of a Python object.
struct ModesInput {
    parts: [Vec<f64>; 6],
}

impl ModesInput {
    fn extract(obj: &Bound<'_, PyAny>) -> PyResult<Self> {
        let names = [
            "lambda_re",
            "lambda_im",
            "gain_re",
            "gain_im",
            "eta0_re",
            "eta0_im",
        ];
        let mut parts: [Vec<f64>; 6] = Default::default();
        for (part, name) in parts.iter_mut().zip(names) {
            *part = flat_of(&obj.getattr(name)?, name)?;
        }
        Ok(ModesInput { parts })
    }

    fn modes(&self) -> FirstOrderModes<'_> {
        let [lr, li, gr, gi, er, ei] = &self.parts;
        FirstOrderModes {
            lambda_re: lr,
            lambda_im: li,
            gain_re: gr,
            gain_im: gi,
            eta0_re: er,
            eta0_im: ei,
        }
    }
}

/// Integrates a linear system with modal couplings exactly in its first-order modes; see
/// `duhamel.solve`.
///
/// `modes` has `lambda_re`, `lambda_im`, `gain_re`, `gain_im`, `eta0_re`, `eta0_im`;
/// `outputs` is None or has `map` (`2 r x n_cols`), `loads` (`n_loads x n_cols`) and
/// `n_cols`, mapped during the run into `RunResult.outputs`; `nonlinear` is None or has
/// `phi` (`n_dof x m`), `elements` (`_core.Element`s), `back` (`2 r x 2 m`), `tol` and
/// `max_iter`: the elements then enter as a pseudo-force (scheme b, trapezoid).
#[pyfunction]
pub(crate) fn solve_first_order(
    py: Python<'_>,
    problem: &Bound<'_, PyAny>,
    modes: &Bound<'_, PyAny>,
    outputs: &Bound<'_, PyAny>,
    nonlinear: &Bound<'_, PyAny>,
    forcing: &Bound<'_, PyAny>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    guarded(|| {
        let input = ModalInput::extract(problem)?;
        let p = input.problem();
        let modes = ModesInput::extract(modes)?;
        let maps = if outputs.is_none() {
            None
        } else {
            Some((
                flat_of(&outputs.getattr("map")?, "map")?,
                flat_of(&outputs.getattr("loads")?, "loads")?,
                attr::<usize>(outputs, "n_cols")?,
            ))
        };
        let outputs = maps.as_ref().map(|(map, loads, n_cols)| Outputs {
            map,
            loads,
            n_cols: *n_cols,
        });
        let (nl_arrays, built) = if nonlinear.is_none() {
            (None, elements::Built::default())
        } else {
            (
                Some((
                    flat_of(&nonlinear.getattr("phi")?, "phi")?,
                    flat_of(&nonlinear.getattr("back")?, "back")?,
                    attr::<f64>(nonlinear, "tol")?,
                    attr::<usize>(nonlinear, "max_iter")?,
                    crate::pseudo::element_state_of(nonlinear)?,
                )),
                elements::build(py, &nonlinear.getattr("elements")?)?,
            )
        };
        let refs = built.refs();
        let nonlinear = nl_arrays
            .as_ref()
            .map(|(phi, back, tol, max_iter, state)| Nonlinear {
                phi,
                n_dof: phi.len().checked_div(p.n_modes()).unwrap_or(0),
                elements: &refs,
                back,
                tol: *tol,
                max_iter: *max_iter,
                element_state: state.as_deref(),
            });
        let forcing = PyForcing::modal(forcing, &problem.getattr("phi")?, p.n_modes())?;
        run(py, forcing, Some(&built), progress, |f, control| {
            first_order::integrate(
                &p,
                &modes.modes(),
                outputs.as_ref(),
                nonlinear.as_ref(),
                f,
                control,
            )
        })
    })
}
