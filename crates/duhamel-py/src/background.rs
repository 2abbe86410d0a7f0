//! Binding of the background propagators' routes: uncoupled oscillators, first-order modes
//! (with the elements' corrector on them), and the outputs mapped during a run.

use duhamel_core::background::first_order::{self, FirstOrderModes};
use duhamel_core::background::uncoupled;
use duhamel_core::output::Outputs as CoreOutputs;
use duhamel_core::pseudo::first_order::Nonlinear;
use duhamel_core::ModalProblem;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{matrix_of, vec_of};
use crate::driver::run;
use crate::element_build;
use crate::element_type::Element as ElementSpec;
use crate::history::RunResult;
use crate::loads::PyForcing;
use crate::problem::RunSpec;

/// Runs uncoupled modal oscillators exactly.
pub(crate) fn uncoupled(
    py: Python<'_>,
    problem: &ModalProblem<'_>,
    forcing: Option<PyForcing>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    run(py, forcing, None, progress, |f, control| {
        uncoupled::integrate(problem, f, control).map(|h| (h, ()))
    })
}

/// The elements' corrector on the first-order background: the elements (`_core.Element`s),
/// `back` (`[Re eta | Im eta] @ back = [q | q']`, `2 r x 2 m`), and the Newton tolerance and
/// iteration limit of the step equation (scheme b, trapezoid), and the growth guard's
/// `growth_limit` (None: off).
#[pyclass(frozen, name = "Corrector", module = "duhamel._core")]
pub(crate) struct Corrector {
    elements: Vec<Py<ElementSpec>>,
    back: Vec<f64>,
    tol: f64,
    max_iter: usize,
    growth_limit: f64,
}

#[pymethods]
impl Corrector {
    #[new]
    #[pyo3(signature = (elements, back, tol, max_iter, growth_limit=None))]
    fn new(
        elements: Vec<Py<ElementSpec>>,
        back: &Bound<'_, PyAny>,
        tol: f64,
        max_iter: usize,
        growth_limit: Option<f64>,
    ) -> PyResult<Self> {
        Ok(Corrector {
            elements,
            back: matrix_of(back, "back", None, None)?.0,
            tol,
            max_iter,
            growth_limit: crate::pseudo::growth_limit_of(growth_limit)?,
        })
    }
}

/// The first-order route: eigenvalues `lambda` and gains (`r x m`, row `k` of `V^-1 B`) of
/// the coupled background, as real and imaginary parts, and the elements' `corrector` (None:
/// linear).
#[pyclass(frozen, name = "FirstOrderRoute", module = "duhamel._core")]
pub(crate) struct FirstOrderRoute {
    lambda: [Vec<f64>; 2],
    gain: [Vec<f64>; 2],
    corrector: Option<Py<Corrector>>,
}

#[pymethods]
impl FirstOrderRoute {
    #[new]
    #[pyo3(signature = (lambda_re, lambda_im, gain_re, gain_im, corrector=None))]
    fn new(
        lambda_re: &Bound<'_, PyAny>,
        lambda_im: &Bound<'_, PyAny>,
        gain_re: &Bound<'_, PyAny>,
        gain_im: &Bound<'_, PyAny>,
        corrector: Option<Py<Corrector>>,
    ) -> PyResult<Self> {
        let lambda = [
            vec_of(lambda_re, "lambda_re")?,
            vec_of(lambda_im, "lambda_im")?,
        ];
        let r = lambda[0].len();
        let (gain_re, _, m) = matrix_of(gain_re, "gain_re", Some(r), None)?;
        let (gain_im, ..) = matrix_of(gain_im, "gain_im", Some(r), Some(m))?;
        if let Some(c) = &corrector {
            if c.get().back.len() != 4 * r * m {
                return Err(PyValueError::new_err(format!(
                    "the corrector's `back` must have shape ({}, {}) for {r} first-order \
                     coordinates and {m} modes",
                    2 * r,
                    2 * m
                )));
            }
        }
        Ok(FirstOrderRoute {
            lambda,
            gain: [gain_re, gain_im],
            corrector,
        })
    }
}

/// Outputs mapped during a first-order run: `map` (`2 r x n_cols`: per unit of each
/// coordinate) and `loads` (`n_loads x n_cols`: per unit value of each load's time function).
#[pyclass(frozen, name = "Outputs", module = "duhamel._core")]
pub(crate) struct Outputs {
    map: Vec<f64>,
    loads: Vec<f64>,
    n_cols: usize,
}

#[pymethods]
impl Outputs {
    #[new]
    fn new(map: &Bound<'_, PyAny>, loads: &Bound<'_, PyAny>, n_cols: usize) -> PyResult<Self> {
        Ok(Outputs {
            map: matrix_of(map, "map", None, Some(n_cols))?.0,
            loads: matrix_of(loads, "loads", None, Some(n_cols))?.0,
            n_cols,
        })
    }
}

/// One run on the first-order route: the mode shapes, the route, the run's problem and state, and
/// the outputs to map.
pub(crate) struct FirstOrderRun<'a> {
    /// Mode shapes, `n_dof x n_modes` row-major.
    pub(crate) phi: &'a [f64],
    pub(crate) n_dof: usize,
    pub(crate) route: &'a FirstOrderRoute,
    pub(crate) problem: &'a ModalProblem<'a>,
    pub(crate) run: &'a RunSpec,
    pub(crate) outputs: Option<&'a Outputs>,
}

/// Integrates a linear system with modal couplings exactly in its first-order modes, the
/// elements (if any) as a pseudo-force.
pub(crate) fn first_order(
    py: Python<'_>,
    job: FirstOrderRun<'_>,
    forcing: Option<PyForcing>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    let route = job.route;
    let r = route.lambda[0].len();
    let eta0 =
        job.run.eta0.as_deref().ok_or_else(|| {
            PyValueError::new_err("a first-order run needs its initial state `eta0`")
        })?;
    if eta0.len() != 2 * r {
        return Err(PyValueError::new_err(format!(
            "`eta0` must have {} entries (real and imaginary parts of {r} coordinates), got {}",
            2 * r,
            eta0.len()
        )));
    }
    let modes = FirstOrderModes {
        lambda_re: &route.lambda[0],
        lambda_im: &route.lambda[1],
        gain_re: &route.gain[0],
        gain_im: &route.gain[1],
        eta0_re: &eta0[..r],
        eta0_im: &eta0[r..],
    };
    let outputs = job.outputs.map(|o| CoreOutputs {
        map: &o.map,
        loads: &o.loads,
        n_cols: o.n_cols,
    });
    let corrector = route.corrector.as_ref().map(Py::get);
    let built = match corrector {
        Some(c) => element_build::build_all(py, &c.elements)?,
        None => crate::callable::Built::default(),
    };
    let refs = built.refs();
    let nonlinear = corrector.map(|c| Nonlinear {
        phi: job.phi,
        n_dof: job.n_dof,
        elements: &refs,
        back: &c.back,
        tol: c.tol,
        max_iter: c.max_iter,
        element_state: job.run.element_state.as_deref(),
        guard_state: job.run.guard_state.as_deref(),
        growth_limit: c.growth_limit,
    });
    let problem = job.problem;
    let energy = job.run.energy.as_ref().map(|e| (e.core(), e.back()));
    run(py, forcing, Some(&built), progress, |f, control| {
        let with = (outputs.as_ref(), nonlinear.as_ref(), energy);
        first_order::integrate_with(problem, &modes, with, f, control)
    })
}
