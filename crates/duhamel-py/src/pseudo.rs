//! Binding of the pseudo-force route (the uncoupled background with the corrector): the
//! integrator's options and the route's couplings, elements and mass law as typed values.

use duhamel_core::direct::assembly::Matrix as CoreMatrix;
use duhamel_core::pseudo::{
    self, NonlinearProblem, Options as CoreOptions, Quadrature, ScaledCoupling as CoreScaled,
    Scheme, Solver,
};
use duhamel_core::ModalProblem;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::direct::{Matrix, ScaledCoupling};
use crate::driver::run as drive;
use crate::element_build;
use crate::element_type::Element as ElementSpec;
use crate::history::RunResult;
use crate::loads::PyForcing;
use crate::mass::Mass;

/// The growth guard's limit (None: no guard, infinite in the core), checked: above 1.
pub(crate) fn growth_limit_of(limit: Option<f64>) -> PyResult<f64> {
    match limit {
        None => Ok(f64::INFINITY),
        Some(x) if x.is_finite() && x > 1.0 => Ok(x),
        Some(x) => Err(PyValueError::new_err(format!(
            "`growth_limit` must be a finite number above 1 (or None: no guard), got {x}"
        ))),
    }
}

/// The settings of a `duhamel.Semianalytic` step equation, checked when made: `scheme`
/// ("a", "b", "c"), `quadrature` ("trapezoid", "parabolic", "exact"), Newton `tol` and
/// `max_iter`, `solver` ("auto", "newton", "modal-newton"), the levels of automatic step
/// `subdivisions` and the growth guard's `growth_limit` (None: off).
#[pyclass(frozen, name = "Options", module = "duhamel._core")]
#[derive(Clone, Copy)]
pub(crate) struct Options(pub(crate) CoreOptions);

#[pymethods]
impl Options {
    #[new]
    #[pyo3(signature = (scheme, quadrature, tol, max_iter, solver, subdivisions, growth_limit=None))]
    fn new(
        scheme: &str,
        quadrature: &str,
        tol: f64,
        max_iter: usize,
        solver: &str,
        subdivisions: usize,
        growth_limit: Option<f64>,
    ) -> PyResult<Self> {
        let growth_limit = growth_limit_of(growth_limit)?;
        let scheme = match scheme {
            "a" => Scheme::A,
            "b" => Scheme::B,
            "c" => Scheme::C,
            "hermite" => Scheme::H,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`scheme` must be 'a', 'b', 'c' or 'hermite', got {other:?}"
                )))
            }
        };
        let quadrature = match quadrature {
            "trapezoid" => Quadrature::Trapezoid,
            "parabolic" => Quadrature::Parabolic,
            "exact" => Quadrature::Exact,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`quadrature` must be 'trapezoid', 'parabolic' or 'exact', got {other:?}"
                )))
            }
        };
        let solver = match solver {
            "auto" => Solver::Auto,
            "newton" => Solver::Newton,
            "modal-newton" => Solver::ModalNewton,
            other => {
                return Err(PyValueError::new_err(format!(
                    "`solver` must be 'auto', 'newton' or 'modal-newton', got {other:?}"
                )))
            }
        };
        Ok(Options(CoreOptions {
            scheme,
            quadrature,
            tol,
            max_iter,
            solver,
            subdivisions,
            growth_limit,
        }))
    }

    fn __repr__(&self) -> String {
        format!("{:?}", self.0)
    }
}

/// The pseudo-force route: the force `elements`, the integrator's `options`, constant modal
/// couplings `coupling_k`, `coupling_c` (dense `_core.Matrix`, or None), couplings `scaled`
/// by a speed law, and the `mass` law (None: constant mass).
#[pyclass(frozen, name = "PseudoForceRoute", module = "duhamel._core")]
pub(crate) struct PseudoForceRoute {
    elements: Vec<Py<ElementSpec>>,
    options: CoreOptions,
    coupling: [Option<Py<Matrix>>; 2],
    scaled: Vec<Py<ScaledCoupling>>,
    mass: Option<Py<Mass>>,
}

#[pymethods]
impl PseudoForceRoute {
    #[new]
    #[pyo3(signature = (elements, options, coupling_k=None, coupling_c=None, scaled=Vec::new(), mass=None))]
    fn new(
        elements: Vec<Py<ElementSpec>>,
        options: &Options,
        coupling_k: Option<Py<Matrix>>,
        coupling_c: Option<Py<Matrix>>,
        scaled: Vec<Py<ScaledCoupling>>,
        mass: Option<Py<Mass>>,
    ) -> Self {
        PseudoForceRoute {
            elements,
            options: options.0,
            coupling: [coupling_k, coupling_c],
            scaled,
            mass,
        }
    }
}

/// The row-major values of a dense modal matrix (a `_core.Matrix`).
fn dense<'a>(m: Option<&'a Py<Matrix>>, name: &str) -> PyResult<Option<&'a [f64]>> {
    match m.map(|m| &m.get().0) {
        None => Ok(None),
        Some(CoreMatrix::Dense { data, .. }) => Ok(Some(data)),
        Some(_) => Err(PyValueError::new_err(format!(
            "`{name}`: a modal coupling must be a dense matrix"
        ))),
    }
}

/// One run on the pseudo-force route.
pub(crate) struct PseudoRun<'a> {
    /// Mode shapes, `n_dof x n_modes` row-major.
    pub(crate) phi: &'a [f64],
    pub(crate) n_dof: usize,
    pub(crate) route: &'a PseudoForceRoute,
    pub(crate) problem: ModalProblem<'a>,
    pub(crate) element_state: Option<&'a [f64]>,
    pub(crate) guard_state: Option<&'a [f64]>,
    pub(crate) energy: Option<duhamel_core::energy::EnergySpec<'a>>,
}

/// Integrates a modal problem whose pseudo-force (elements, couplings, mass law) is solved
/// every step.
pub(crate) fn run(
    py: Python<'_>,
    job: PseudoRun<'_>,
    forcing: Option<PyForcing>,
    progress: &Bound<'_, PyAny>,
) -> PyResult<RunResult> {
    let route = job.route;
    let mut base = job.problem;
    // One mode-coupled step at a time: a single thread.
    base.threads = Some(1);
    let built = element_build::build_all(py, &route.elements)?;
    let refs = built.refs();
    let scaled = route
        .scaled
        .iter()
        .map(|s| {
            let s = s.get();
            Ok(CoreScaled {
                k: dense(s.k.as_ref(), "scaled coupling K")?,
                c: dense(s.c.as_ref(), "scaled coupling C")?,
                law: s.law,
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let problem = NonlinearProblem {
        base,
        phi: job.phi,
        n_dof: job.n_dof,
        elements: &refs,
        coupling_k: dense(route.coupling[0].as_ref(), "coupling_k")?,
        coupling_c: dense(route.coupling[1].as_ref(), "coupling_c")?,
        scaled: &scaled,
        mass: route.mass.as_ref().map(|m| &m.get().0),
        options: route.options,
        element_state: job.element_state,
        guard_state: job.guard_state,
        energy: job.energy,
    };
    drive(py, forcing, Some(&built), progress, |f, control| {
        pseudo::integrate(&problem, f, control)
    })
}
