//! A prepared modal model (`duhamel.Prepared`): what does not change between runs of one
//! model — the background modes, the mode shapes, the route and its corrector, the default
//! loads — extracted once into Rust values; [`ModalModel::run`] is the one entry point of
//! every modal run.

use duhamel_core::loads::ModalLoad;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::arrays::{matrix_of, vec_of};
use crate::background::{self, FirstOrderRoute, Outputs};
use crate::guard::guarded;
use crate::history::RunResult;
use crate::loads::{owned_loads, transposed, Load, PyForcing};
use crate::problem::RunSpec;
use crate::pseudo::{self, PseudoForceRoute};

/// The route of a model: the background, and the corrector on it.
pub(crate) enum Route {
    /// Uncoupled oscillators, no corrector: exact.
    Uncoupled,
    /// First-order modes of a coupled background (elements as a pseudo-force, if any).
    FirstOrder(Py<FirstOrderRoute>),
    /// Uncoupled oscillators with the pseudo-force corrector.
    PseudoForce(Py<PseudoForceRoute>),
}

/// The route argument of [`ModalModel::new`]: None (uncoupled) or one of the route classes.
#[derive(FromPyObject)]
enum RouteArg {
    FirstOrder(Py<FirstOrderRoute>),
    PseudoForce(Py<PseudoForceRoute>),
}

/// A modal model, checked once: modal stiffness `k` (`omega^2`) and damping `c` per unit
/// modal mass, mass-normalised mode shapes `phi` (`n_dof x n_modes`), the built-in `loads`
/// (`_core.Load`s with modal patterns) and the `route` (None: uncoupled oscillators;
/// `FirstOrderRoute` or `PseudoForceRoute`).
#[pyclass(frozen, name = "ModalModel", module = "duhamel._core")]
pub(crate) struct ModalModel {
    k: Vec<f64>,
    c: Vec<f64>,
    /// `n_dof x n_modes`, row-major.
    phi: Vec<f64>,
    /// `n_modes x n_dof`: what a Python load function's vector is projected with.
    phi_t: Vec<f64>,
    n_dof: usize,
    loads: Vec<ModalLoad>,
    route: Route,
}

#[pymethods]
impl ModalModel {
    #[new]
    #[pyo3(signature = (k, c, phi, loads, route=None))]
    fn new(
        k: &Bound<'_, PyAny>,
        c: &Bound<'_, PyAny>,
        phi: &Bound<'_, PyAny>,
        loads: Vec<PyRef<'_, Load>>,
        route: Option<RouteArg>,
    ) -> PyResult<Self> {
        let k = vec_of(k, "k")?;
        let c = vec_of(c, "c")?;
        let m = k.len();
        if c.len() != m {
            return Err(PyValueError::new_err(format!(
                "`c` has length {}, expected {m} (one modal damping per mode)",
                c.len()
            )));
        }
        let (phi, n_dof, _) = matrix_of(phi, "phi", None, Some(m))?;
        let route = match route {
            None => Route::Uncoupled,
            Some(RouteArg::FirstOrder(r)) => Route::FirstOrder(r),
            Some(RouteArg::PseudoForce(r)) => Route::PseudoForce(r),
        };
        Ok(ModalModel {
            phi_t: transposed(&phi, n_dof, m),
            k,
            c,
            phi,
            n_dof,
            loads: owned_loads(&loads),
            route,
        })
    }

    /// Number of modes.
    #[getter]
    fn n_modes(&self) -> usize {
        self.k.len()
    }

    /// Number of physical degrees of freedom.
    #[getter]
    fn n_dof(&self) -> usize {
        self.n_dof
    }

    /// The route's name: "uncoupled", "first-order" or "pseudo-force".
    #[getter]
    fn route(&self) -> &'static str {
        match self.route {
            Route::Uncoupled => "uncoupled",
            Route::FirstOrder(_) => "first-order",
            Route::PseudoForce(_) => "pseudo-force",
        }
    }

    /// Runs the model from `run`'s state over its grid; `loads` (a list of `_core.Load`)
    /// replaces the model's own for this run; `outputs` (first-order route) maps the
    /// coordinates to physical outputs during the run; `forcing` is None or a Python function
    /// of time returning the physical load vector; `progress` None or a function
    /// `(step, n_steps, t)` called between blocks.
    #[pyo3(signature = (run, loads=None, outputs=None, forcing=None, progress=None))]
    fn run(
        &self,
        py: Python<'_>,
        run: &RunSpec,
        loads: Option<Vec<PyRef<'_, Load>>>,
        outputs: Option<PyRef<'_, Outputs>>,
        forcing: Option<&Bound<'_, PyAny>>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<RunResult> {
        guarded(|| {
            let replaced = loads.map(|l| owned_loads(&l));
            let loads = replaced.as_deref().unwrap_or(&self.loads);
            let none = py.None().into_bound(py);
            let forcing = PyForcing::projected(forcing.unwrap_or(&none), &self.phi_t, self.n_dof);
            let progress = progress.unwrap_or(&none);
            let problem = run.problem(&self.k, &self.c, loads);
            if run.energy.is_some() && matches!(self.route, Route::Uncoupled) {
                return Err(PyValueError::new_err(
                    "`energy`: the energy integrals are accumulated during the run on the \
                     pseudo-force and first-order routes (an uncoupled model is stepped by \
                     the pseudo-force route for it)",
                ));
            }
            match &self.route {
                Route::Uncoupled => background::uncoupled(py, &problem, forcing, progress),
                Route::FirstOrder(route) => background::first_order(
                    py,
                    background::FirstOrderRun {
                        phi: &self.phi,
                        n_dof: self.n_dof,
                        route: route.get(),
                        problem: &problem,
                        run,
                        outputs: outputs.as_deref(),
                    },
                    forcing,
                    progress,
                ),
                Route::PseudoForce(route) => pseudo::run(
                    py,
                    pseudo::PseudoRun {
                        phi: &self.phi,
                        n_dof: self.n_dof,
                        route: route.get(),
                        problem,
                        element_state: run.element_state.as_deref(),
                        guard_state: run.guard_state.as_deref(),
                        energy: run.energy.as_ref().map(|e| e.core()),
                    },
                    forcing,
                    progress,
                ),
            }
        })
    }

    fn __repr__(&self) -> String {
        format!(
            "ModalModel(n_dof={}, n_modes={}, loads={}, route={:?})",
            self.n_dof,
            self.k.len(),
            self.loads.len(),
            self.route()
        )
    }
}
