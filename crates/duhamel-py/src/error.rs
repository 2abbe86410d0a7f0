//! The one place where core errors become Python exceptions, keeping their fields.

use duhamel_core::CoreError;
use pyo3::exceptions::{PyKeyboardInterrupt, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// Bad input: `ValueError` with the core's message (which names the parameter); a run
/// failure reaching here (it should travel as a [`RunError`]) is a `RuntimeError`.
pub(crate) fn core_err(e: CoreError) -> PyErr {
    match e {
        CoreError::InvalidInput { .. } | CoreError::LengthMismatch { .. } => {
            PyValueError::new_err(e.to_string())
        }
        CoreError::Interrupted { .. } => PyKeyboardInterrupt::new_err(e.to_string()),
        _ => PyRuntimeError::new_err(e.to_string()),
    }
}

/// Why a run stopped before its end, with the fields of the core error. Travels with the
/// partial history in a `RunResult`; `duhamel` turns it into `SolverError` or
/// `KeyboardInterrupt`.
#[pyclass(frozen, module = "duhamel._core")]
pub(crate) struct RunError {
    /// "nonfinite", "convergence", "domain", "stiffness", "callback" or
    /// "interrupted".
    #[pyo3(get)]
    kind: &'static str,
    /// The core's message.
    #[pyo3(get)]
    message: String,
    /// When the run failed (the failed step's end; for a callback, the time it was called
    /// at; for an interruption, the time reached).
    #[pyo3(get)]
    time: f64,
    /// The step that could not be completed (steps count from 1).
    #[pyo3(get)]
    step: usize,
    /// The last time whose state is good, if the kind has one.
    #[pyo3(get)]
    last_good_time: Option<f64>,
    /// Newton: the last residual and the iterations taken.
    #[pyo3(get)]
    residual: Option<f64>,
    #[pyo3(get)]
    iterations: Option<usize>,
    /// The Python exception raised by a callback (load, element, progress), or the
    /// `KeyboardInterrupt` of an interruption.
    #[pyo3(get)]
    cause: Option<Py<PyAny>>,
    /// The core's error, to render it again with other fields.
    core: CoreError,
}

impl RunError {
    /// The run failure `error`, or the input error as a Python exception.
    pub(crate) fn new(py: Python<'_>, error: CoreError, cause: Option<PyErr>) -> PyResult<Self> {
        let message = error.to_string();
        let cause = cause.map(|e| e.into_value(py).into_any());
        let core = error.clone();
        let (kind, time, step, last_good, residual, iterations) = match error {
            CoreError::NonFinite {
                time,
                step,
                last_good_time,
            } => ("nonfinite", time, step, last_good_time, None, None),
            CoreError::NoConvergence {
                time,
                step,
                residual,
                iterations,
                last_good_time,
            } => (
                "convergence",
                time,
                step,
                last_good_time,
                Some(residual),
                Some(iterations),
            ),
            CoreError::Callback { time, step, .. } => ("callback", time, step, None, None, None),
            CoreError::OutOfDomain {
                time,
                step,
                last_good_time,
                ..
            } => ("domain", time, step, last_good_time, None, None),
            CoreError::TooStiff {
                time,
                step,
                last_good_time,
                ..
            } => ("stiffness", time, step, last_good_time, None, None),
            CoreError::Growth {
                time,
                step,
                last_good_time,
                ..
            } => ("growth", time, step, last_good_time, None, None),
            CoreError::Interrupted { time, step } => {
                ("interrupted", time, step, Some(time), None, None)
            }
            input => return Err(core_err(input)),
        };
        Ok(RunError {
            kind,
            message,
            time,
            step,
            last_good_time: last_good,
            residual,
            iterations,
            cause,
            core,
        })
    }
}

#[pymethods]
impl RunError {
    /// The same failure with the history kept only up to `last_good_time` (when the
    /// physical outputs of the last kept states overflowed; None when nothing is kept), its
    /// message rendered anew.
    #[pyo3(signature = (last_good_time))]
    fn kept_until(&self, py: Python<'_>, last_good_time: Option<f64>) -> PyResult<Self> {
        let mut core = self.core.clone();
        match &mut core {
            CoreError::NonFinite {
                last_good_time: t, ..
            }
            | CoreError::NoConvergence {
                last_good_time: t, ..
            }
            | CoreError::OutOfDomain {
                last_good_time: t, ..
            }
            | CoreError::TooStiff {
                last_good_time: t, ..
            }
            | CoreError::Growth {
                last_good_time: t, ..
            } => *t = last_good_time,
            _ => {}
        }
        let cause = self
            .cause
            .as_ref()
            .map(|c| PyErr::from_value(c.bind(py).clone()));
        RunError::new(py, core, cause)
    }

    fn __repr__(&self) -> String {
        format!(
            "RunError(kind={:?}, step={}, time={}, message={:?})",
            self.kind, self.step, self.time, self.message
        )
    }
}
