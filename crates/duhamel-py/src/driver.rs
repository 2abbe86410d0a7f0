//! The caller's side of a run: Ctrl-C and progress between blocks.

use duhamel_core::Control;
use pyo3::prelude::*;

/// Checks for pending signals (Ctrl-C) between blocks, with the GIL taken briefly, and calls
/// a Python progress function `(step, n_steps, t)` if there is one.
pub(crate) struct PyControl {
    progress: Option<Py<PyAny>>,
    /// The exception that stopped the run: a `KeyboardInterrupt` (or whatever the signal
    /// handler raised), or the progress function's own exception.
    pub(crate) error: Option<PyErr>,
}

impl PyControl {
    pub(crate) fn new(progress: &Bound<'_, PyAny>) -> Self {
        PyControl {
            progress: (!progress.is_none()).then(|| progress.clone().unbind()),
            error: None,
        }
    }
}

impl Control for PyControl {
    fn interrupted(&mut self) -> bool {
        if self.error.is_some() {
            return true;
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
