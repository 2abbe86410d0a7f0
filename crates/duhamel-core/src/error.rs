//! The one error type of the engine; variants carry structured fields.

use thiserror::Error;

/// Every failure the engine reports. Input errors name the parameter; run failures name the
/// step and time at which the run stopped.
///
/// Steps are numbered from 1: step `n` advances the state from `t0 + (n - 1) dt` to
/// `t0 + n dt`. A run failure's `step` is the step that could not be completed; the run's
/// partial history holds the saved states before it. Code deep inside a step (an element, a
/// Newton iteration) does not know its step index and leaves `step` at 0: the time-stepping
/// driver fills it in ([`CoreError::located`]) before the error leaves the engine.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CoreError {
    /// A parameter has a value outside its domain.
    #[error("`{name}` {problem}")]
    InvalidInput { name: &'static str, problem: String },
    /// Two arrays that must agree in length do not.
    #[error("`{name}` has length {got}, expected {expected}")]
    LengthMismatch {
        name: &'static str,
        got: usize,
        expected: usize,
    },
    /// The state stopped being finite: the simulation diverged.
    #[error("the state became non-finite at t = {time} (step {step}): the response diverges (negative damping, an unstable load, a step beyond the integrator's stability limit or an overflow); {}", kept(last_good_time))]
    NonFinite {
        time: f64,
        step: usize,
        /// The last saved time kept, None when nothing is.
        last_good_time: Option<f64>,
    },
    /// The implicit step equation did not converge.
    #[error("the step equation did not converge at t = {time} (step {step}): residual {residual:.3e} after {iterations} Newton iterations (reduce `dt`, raise `max_iter` (or `subdivisions`, semi-analytic) or loosen `tol`); {}", kept(last_good_time))]
    NoConvergence {
        time: f64,
        step: usize,
        residual: f64,
        iterations: usize,
        /// The last saved time kept, None when nothing is.
        last_good_time: Option<f64>,
    },
    /// A user-supplied load or element function failed or returned bad values.
    #[error("callback failed at t = {time} (step {step}): {message}")]
    Callback {
        time: f64,
        step: usize,
        message: String,
    },
    /// An element was evaluated at a state outside the states it is defined for (a journal
    /// at or beyond its bearing's wall). A step where a Newton iterate strays there is
    /// retried in halves; this is the error when that does not help.
    #[error("{message} at t = {time} (step {step}); {}", kept(last_good_time))]
    OutOfDomain {
        message: String,
        time: f64,
        step: usize,
        /// The last saved time kept, None when nothing is.
        last_good_time: Option<f64>,
    },
    /// An element's tangent stiffness puts the pseudo-force step beyond its stability limit
    /// and subdivision cannot bring the step within it (the message names the element, the
    /// limit and what to change).
    #[error("{message} at t = {time} (step {step}); {}", kept(last_good_time))]
    TooStiff {
        message: String,
        time: f64,
        step: usize,
        /// The last saved time kept, None when nothing is.
        last_good_time: Option<f64>,
    },
    /// The response's energy grew far beyond what the initial state and the loads supplied
    /// while staying finite (an unstable step; see [`crate::pseudo::GrowthGuard`]).
    #[error("{message} at t = {time} (step {step}); {}", kept(last_good_time))]
    Growth {
        message: String,
        time: f64,
        step: usize,
        /// The last saved time kept, None when nothing is.
        last_good_time: Option<f64>,
    },
    /// The caller asked the run to stop (Ctrl-C): the history up to `time` is kept.
    #[error(
        "interrupted at t = {time} (before step {step}); the history up to t = {time} is kept"
    )]
    Interrupted { time: f64, step: usize },
}

/// What a failed run keeps, for its message.
fn kept(last_good_time: &Option<f64>) -> String {
    match last_good_time {
        Some(t) => format!("the history up to t = {t} is kept"),
        None => "nothing is kept (the initial state's response is not finite)".to_string(),
    }
}

impl CoreError {
    /// The step a run failure stopped at (None for input errors).
    pub fn step(&self) -> Option<usize> {
        match self {
            CoreError::NonFinite { step, .. }
            | CoreError::NoConvergence { step, .. }
            | CoreError::Callback { step, .. }
            | CoreError::OutOfDomain { step, .. }
            | CoreError::TooStiff { step, .. }
            | CoreError::Growth { step, .. }
            | CoreError::Interrupted { step, .. } => Some(*step),
            _ => None,
        }
    }

    /// The failure of step `step`, with the step's times from `time(n)` (the time of grid
    /// point `n`). A step equation whose residual is no longer finite is a diverging response
    /// (an overflowing state), not a convergence problem: it becomes [`CoreError::NonFinite`].
    pub fn located(self, step: usize, time: impl Fn(usize) -> f64) -> CoreError {
        let (end, start) = (time(step), time(step.saturating_sub(1)));
        // Step 0 is the initial state itself: a failure there keeps nothing.
        let kept_time = (step > 0).then_some(start);
        match self {
            CoreError::NonFinite { .. } => CoreError::NonFinite {
                time: end,
                step,
                last_good_time: kept_time,
            },
            CoreError::NoConvergence { residual, .. } if !residual.is_finite() => {
                CoreError::NonFinite {
                    time: end,
                    step,
                    last_good_time: kept_time,
                }
            }
            CoreError::NoConvergence {
                residual,
                iterations,
                ..
            } => CoreError::NoConvergence {
                time: end,
                step,
                residual,
                iterations,
                last_good_time: kept_time,
            },
            CoreError::Callback { time, message, .. } => CoreError::Callback {
                time,
                step,
                message,
            },
            CoreError::OutOfDomain { message, .. } => CoreError::OutOfDomain {
                message,
                time: end,
                step,
                last_good_time: kept_time,
            },
            CoreError::TooStiff { message, .. } => CoreError::TooStiff {
                message,
                time: end,
                step,
                last_good_time: kept_time,
            },
            CoreError::Growth { message, .. } => CoreError::Growth {
                message,
                time: end,
                step,
                last_good_time: kept_time,
            },
            CoreError::Interrupted { .. } => CoreError::Interrupted { time: start, step },
            input => input,
        }
    }
}
