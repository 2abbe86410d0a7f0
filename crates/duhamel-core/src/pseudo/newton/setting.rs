//! What every strategy of the step solver knows about the step.

use super::super::scheme::{Rule, Scheme, StepInput, Unknown};
use crate::error::CoreError;

/// The step's rule and scheme, its unknown half and Newton's settings, fixed for a run.
pub(super) struct Setting<'r> {
    /// The number of modes.
    pub n: usize,
    /// The quadrature rule (nodes and weights).
    pub rule: &'r Rule,
    /// The state approximation inside the step.
    pub scheme: Scheme,
    /// The step.
    pub dt: f64,
    /// The half of the end state the pseudo-force depends on.
    pub unknown: Unknown,
    /// Per node: whether its state does not depend on the unknowns (evaluated once per step).
    pub constant: Vec<bool>,
    /// Relative tolerance of the Newton updates.
    pub tol: f64,
    /// Newton iterations before giving up.
    pub max_iter: usize,
    /// The step equation is linear (affine pseudo-force): one Newton step is exact.
    pub linear: bool,
    /// Every force is a polynomial of degree <= 3 with analytic tangents: Newton's
    /// convergence near the solution is quadratic, so the next correction can be predicted
    /// ([`super::damping::next_below_rounding`]).
    pub smooth: bool,
    /// The pseudo-force reads the step's acceleration estimate `(v1 - v0)/dt` (an estimated
    /// mass law).
    pub acceleration: bool,
}

impl Setting<'_> {
    /// The error of a step from `inp` whose Newton iterations did not converge, its last
    /// residual `residual` (every strategy's).
    pub fn no_convergence(&self, inp: &StepInput<'_>, residual: f64) -> CoreError {
        CoreError::NoConvergence {
            time: inp.t + self.dt,
            step: 0,
            residual,
            iterations: self.max_iter,
            last_good_time: Some(inp.t),
        }
    }

    /// Whether an element-space Newton correction of `size` (largest magnitude) settles the
    /// step at `scale`: an affine force, the tolerance, a zero correction, or (smooth forces,
    /// no cut-back) the next correction foreseen below rounding from the last one
    /// (`last_size`).
    pub fn settled(&self, last_size: Option<f64>, size: f64, scale: f64, cut: bool) -> bool {
        let exact =
            self.smooth && !cut && super::damping::next_below_rounding(last_size, size, scale);
        self.linear || size <= self.tol * scale || size == 0.0 || exact
    }
}
