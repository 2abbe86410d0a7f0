//! What a run returns to Python: its history as numpy arrays (moved, not copied), its
//! statistics and, for a run that stopped early, why.

use duhamel_core::direct::DirectHistory;
use duhamel_core::{Coordinates, CoreError, Failure, History, Stats};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::error::RunError;

pub(crate) type Array1 = Py<PyArray1<f64>>;
pub(crate) type Array2 = Py<PyArray2<f64>>;

/// The result of a run (complete, or partial with `error` set). Arrays are time-major,
/// `(n_saved, width)`; those a route does not produce are None.
#[pyclass(frozen, module = "duhamel._core")]
pub(crate) struct RunResult {
    /// Saved times.
    #[pyo3(get)]
    t: Array1,
    /// Modal coordinates and velocities (uncoupled and pseudo-force routes).
    #[pyo3(get)]
    q: Option<Array2>,
    #[pyo3(get)]
    v: Option<Array2>,
    /// First-order coordinates `[Re eta | Im eta]` (coupled route).
    #[pyo3(get)]
    eta: Option<Array2>,
    /// Outputs mapped during the run (coupled route).
    #[pyo3(get)]
    outputs: Option<Array2>,
    /// Each load's time function at the saved instants.
    #[pyo3(get)]
    load_values: Option<Array2>,
    /// Modal forcing of Python load functions at the saved instants.
    #[pyo3(get)]
    forcing: Option<Array2>,
    /// Modal pseudo-force at the saved states (routes with a corrector).
    #[pyo3(get)]
    pseudo: Option<Array2>,
    /// Physical displacements, velocities, accelerations (direct integrators).
    #[pyo3(get)]
    x: Option<Array2>,
    #[pyo3(get)]
    a: Option<Array2>,
    /// The elements' local displacements, velocities and restoring forces (modal routes
    /// that evaluate elements), `n_saved x sum of local dofs`.
    #[pyo3(get)]
    element_x: Option<Array2>,
    #[pyo3(get)]
    element_v: Option<Array2>,
    #[pyo3(get)]
    element_force: Option<Array2>,
    /// The number of local dofs of each element (columns of the element arrays).
    #[pyo3(get)]
    element_widths: Option<Vec<usize>>,
    /// The hysteretic elements' committed variables at the end (what a continued run
    /// starts from).
    #[pyo3(get)]
    element_state: Option<Vec<f64>>,
    /// The growth guard's accumulated bounds at the end (what a continued run starts from),
    /// None when the run was not guarded.
    #[pyo3(get)]
    guard_state: Option<Vec<f64>>,
    /// The energy integrals at the saved instants, when asked for: `[damping, input,
    /// absolute - relative input, ground velocities, element work]`.
    #[pyo3(get)]
    energy: Option<Array2>,
    /// Newton iterations, closed-form steps and factorisations over the run.
    #[pyo3(get)]
    newton_iterations: usize,
    #[pyo3(get)]
    closed_form_steps: usize,
    #[pyo3(get)]
    factorizations: usize,
    /// Steps retried in halves, and the deepest subdivision (semi-analytic route).
    #[pyo3(get)]
    subdivided_steps: usize,
    #[pyo3(get)]
    subdivision_depth: usize,
    /// Seconds spent in the engine's loop (with the GIL released), as measured by the
    /// binding: the run's cost without extraction and conversion.
    #[pyo3(get)]
    pub(crate) loop_time: f64,
    /// None, or why the run stopped early (the arrays then hold what was kept).
    #[pyo3(get)]
    error: Option<Py<RunError>>,
}

#[pymethods]
impl RunResult {
    fn __repr__(&self) -> String {
        format!(
            "RunResult(error={})",
            if self.error.is_some() { "set" } else { "None" }
        )
    }
}

/// What the error estimate reads of a run ([`crate::accuracy::Estimator`]).
pub(crate) struct Estimated<'a> {
    pub(crate) t: &'a Array1,
    pub(crate) q: Option<&'a Array2>,
    pub(crate) pseudo: Option<&'a Array2>,
    pub(crate) element_x: Option<&'a Array2>,
    pub(crate) element_force: bool,
    pub(crate) element_widths: Option<&'a [usize]>,
}

impl RunResult {
    /// The arrays the error estimate reads.
    pub(crate) fn estimated(&self) -> Estimated<'_> {
        Estimated {
            t: &self.t,
            q: self.q.as_ref(),
            pseudo: self.pseudo.as_ref(),
            element_x: self.element_x.as_ref(),
            element_force: self.element_force.is_some(),
            element_widths: self.element_widths.as_deref(),
        }
    }
}

fn array2(py: Python<'_>, v: Vec<f64>, rows: usize, cols: usize) -> PyResult<Array2> {
    Ok(PyArray1::from_vec(py, v).reshape([rows, cols])?.unbind())
}

impl RunResult {
    fn empty(py: Python<'_>, t: Vec<f64>) -> Self {
        RunResult {
            t: PyArray1::from_vec(py, t).unbind(),
            q: None,
            v: None,
            eta: None,
            outputs: None,
            load_values: None,
            forcing: None,
            pseudo: None,
            x: None,
            a: None,
            element_x: None,
            element_v: None,
            element_force: None,
            element_widths: None,
            element_state: None,
            guard_state: None,
            energy: None,
            newton_iterations: 0,
            closed_form_steps: 0,
            factorizations: 0,
            subdivided_steps: 0,
            subdivision_depth: 0,
            loop_time: 0.0,
            error: None,
        }
    }

    fn modal(py: Python<'_>, h: History) -> PyResult<Self> {
        let rows = h.t.len();
        let n = h.n_modes;
        let mut r = RunResult::empty(py, h.t);
        match h.coordinates {
            Coordinates::Modal { q, v } => {
                r.q = Some(array2(py, q, rows, n)?);
                r.v = Some(array2(py, v, rows, n)?);
            }
            Coordinates::FirstOrder { eta, width } => {
                r.eta = Some(array2(py, eta, rows, width)?);
            }
        }
        r.load_values = Some(array2(py, h.load_values, rows, h.n_loads)?);
        let as_modal = |v: Vec<f64>| array2(py, v, rows, n);
        r.forcing = h.forcing.map(as_modal).transpose()?;
        r.pseudo = h.pseudo.map(as_modal).transpose()?;
        r.outputs = h
            .outputs
            .map(|o| array2(py, o, rows, h.n_outputs))
            .transpose()?;
        if let Some(e) = h.elements {
            let w = e.width;
            r.element_x = Some(array2(py, e.x, rows, w)?);
            r.element_v = Some(array2(py, e.v, rows, w)?);
            r.element_force = Some(array2(py, e.r, rows, w)?);
            r.element_widths = Some(e.widths);
        }
        r.element_state = h.element_state;
        r.guard_state = h.guard_state;
        if let Some(e) = h.energy {
            r.energy = Some(array2(py, e.values, rows, e.n_cols)?);
        }
        Ok(r)
    }

    fn direct(py: Python<'_>, h: DirectHistory) -> PyResult<Self> {
        let rows = h.t.len();
        let cols = h.n_out;
        let mut r = RunResult::empty(py, h.t);
        let shaped = |v: Vec<f64>| array2(py, v, rows, cols);
        r.x = Some(shaped(h.x)?);
        r.v = Some(shaped(h.v)?);
        r.a = Some(shaped(h.a)?);
        if let Some(e) = h.energy {
            r.energy = Some(array2(py, e.values, rows, e.n_cols)?);
        }
        Ok(r)
    }
}

/// A history type the core returns, and how it becomes a [`RunResult`].
pub(crate) trait IntoResult: Sized {
    fn into_result(self, py: Python<'_>) -> PyResult<RunResult>;
}

impl IntoResult for History {
    fn into_result(self, py: Python<'_>) -> PyResult<RunResult> {
        RunResult::modal(py, self)
    }
}

impl IntoResult for DirectHistory {
    fn into_result(self, py: Python<'_>) -> PyResult<RunResult> {
        RunResult::direct(py, self)
    }
}

/// Run statistics, whatever their core type.
pub(crate) trait IntoStats {
    /// `(newton_iterations, closed_form_steps, factorizations)`.
    fn counts(&self) -> (usize, usize, usize);

    /// `(subdivided_steps, subdivision_depth)`.
    fn subdivisions(&self) -> (usize, usize) {
        (0, 0)
    }
}

impl IntoStats for Stats {
    fn counts(&self) -> (usize, usize, usize) {
        (
            self.newton_iterations,
            self.closed_form_steps,
            self.factorizations,
        )
    }

    fn subdivisions(&self) -> (usize, usize) {
        (self.subdivided_steps, self.subdivision_depth)
    }
}

impl IntoStats for () {
    fn counts(&self) -> (usize, usize, usize) {
        (0, 0, 0)
    }
}

/// The Python exceptions a run may have met: a load or element function's (`callback`) and
/// the control's (`control`: Ctrl-C, or a progress function's exception).
#[derive(Default)]
pub(crate) struct Causes {
    pub(crate) callback: Option<PyErr>,
    pub(crate) control: Option<PyErr>,
}

/// The result of a run: the history (partial on failure, with `error` set and the Python
/// exception behind a callback failure or an interruption as its cause). Input errors raise.
pub(crate) fn finish<H: IntoResult, S: IntoStats>(
    py: Python<'_>,
    result: Result<(H, S), Box<Failure<H>>>,
    causes: Causes,
) -> PyResult<RunResult> {
    match result {
        Ok((h, stats)) => {
            let mut r = h.into_result(py)?;
            (r.newton_iterations, r.closed_form_steps, r.factorizations) = stats.counts();
            (r.subdivided_steps, r.subdivision_depth) = stats.subdivisions();
            Ok(r)
        }
        Err(failure) => {
            let Failure {
                error,
                partial,
                stats,
            } = *failure;
            let cause = match &error {
                CoreError::Callback { .. } => causes.callback,
                CoreError::Interrupted { .. } => causes.control,
                _ => None,
            };
            let error = RunError::new(py, error, cause)?;
            let mut r = partial.into_result(py)?;
            (r.newton_iterations, r.closed_form_steps, r.factorizations) = stats.counts();
            (r.subdivided_steps, r.subdivision_depth) = stats.subdivisions();
            r.error = Some(Py::new(py, error)?);
            Ok(r)
        }
    }
}
