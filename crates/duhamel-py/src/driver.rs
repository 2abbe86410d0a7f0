//! The caller's side of a run: Ctrl-C and progress between blocks.

use duhamel_core::loads::ModalForcing;
use duhamel_core::{Control, Failure};
use pyo3::prelude::*;

use crate::callable::Built;
use crate::guard::guarded;
use crate::history::{finish, Causes, IntoResult, IntoStats, RunResult};
use crate::loads::PyForcing;

/// Checks for pending signals (Ctrl-C) between blocks, with the GIL taken briefly, and calls
/// a Python progress function `(step, n_steps, t)` if there is one.
pub(crate) struct PyControl {
    progress: Option<Py<PyAny>>,
    /// Whether the run is on Python's main thread, the only one that handles signals: a run
    /// in a worker thread (an ensemble's) has no signal to check, and does not take the GIL
    /// between blocks for nothing (it would wait for the other threads' Python).
    main_thread: bool,
    /// The exception that stopped the run: a `KeyboardInterrupt` (or whatever the signal
    /// handler raised), or the progress function's own exception.
    pub(crate) error: Option<PyErr>,
}

impl PyControl {
    pub(crate) fn new(progress: &Bound<'_, PyAny>) -> PyResult<Self> {
        let threading = progress.py().import("threading")?;
        let main = threading.call_method0("main_thread")?.getattr("ident")?;
        let current = threading.call_method0("get_ident")?;
        Ok(PyControl {
            progress: (!progress.is_none()).then(|| progress.clone().unbind()),
            main_thread: main.eq(current)?,
            error: None,
        })
    }
}

impl Control for PyControl {
    fn interrupted(&mut self) -> bool {
        if self.error.is_some() {
            return true;
        }
        if !self.main_thread {
            return false; // no signal is ever handled outside the main thread
        }
        Python::attach(|py| match py.check_signals() {
            Ok(()) => false,
            Err(e) => {
                self.error = Some(e);
                true
            }
        })
    }

    fn progress(&mut self, step: usize, n_steps: usize, t: f64) {
        let Some(f) = &self.progress else { return };
        if self.error.is_some() {
            return;
        }
        Python::attach(|py| {
            if let Err(e) = f.call1(py, (step, n_steps, t)) {
                // Stops the run at the next check, as an interruption with this cause.
                self.error = Some(e);
            }
        });
    }
}

/// Runs `integrate` with the GIL released, the Python load function `forcing` and a
/// [`PyControl`] for `progress`; the result of the run, with the Python exception behind a
/// failure (the load function's, a Python element's of `built`, or the control's). A panic
/// in the engine raises `InternalError` ([`guarded`]).
pub(crate) fn run<H, S>(
    py: Python<'_>,
    mut forcing: Option<PyForcing>,
    built: Option<&Built>,
    progress: &Bound<'_, PyAny>,
    integrate: impl for<'f> FnOnce(
            Option<&'f mut dyn ModalForcing>,
            &'f mut PyControl,
        ) -> Result<(H, S), Box<Failure<H>>>
        + Send,
) -> PyResult<RunResult>
where
    H: IntoResult + Send,
    S: IntoStats + Send,
{
    guarded(|| {
        let mut control = PyControl::new(progress)?;
        let started = std::time::Instant::now();
        let result = py.detach(|| {
            let f = forcing.as_mut().map(|f| f as &mut dyn ModalForcing);
            integrate(f, &mut control)
        });
        let loop_time = started.elapsed().as_secs_f64();
        let causes = Causes {
            callback: forcing
                .and_then(|f| f.error)
                .or_else(|| built.and_then(Built::take_error)),
            control: control.error,
        };
        let mut result = finish(py, result, causes)?;
        result.loop_time = loop_time;
        Ok(result)
    })
}
