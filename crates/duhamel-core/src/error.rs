//! The one error type of the engine; variants carry structured fields.

use thiserror::Error;

/// Every failure the engine reports. Input errors name the parameter.
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
    #[error("the state became non-finite at t = {time} (step {step}): the response diverges (negative damping, an unstable load, a step beyond the integrator's stability limit or an overflow); the history up to t = {last_good_time} is kept")]
    NonFinite {
        time: f64,
        step: usize,
        last_good_time: f64,
    },
    /// The implicit step equation did not converge.
    #[error("the step equation did not converge at t = {time}: residual {residual:.3e} after {iterations} Newton iterations (reduce `dt`, raise `max_iter` or loosen `tol`); the history up to t = {last_good_time} is kept")]
    NoConvergence {
        time: f64,
        residual: f64,
        iterations: usize,
        last_good_time: f64,
    },
    /// A user-supplied load or element function failed or returned bad values.
    #[error("callback failed at t = {time}: {message}")]
    Callback { time: f64, message: String },
}
