//! A nonlinear modal problem: the background, the pseudo-forces and the step settings.

use super::scheme::{Quadrature, Scheme};
use crate::elements::Element;
use crate::error::CoreError;
use crate::mass::TimeVaryingMass;
use crate::problem::ModalProblem;
use crate::speed::ScaledCoupling;

/// How the step equation is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Solver {
    /// The closed-form cubic where it applies, Newton otherwise.
    Auto,
    /// Always Newton: in the elements' space where the pseudo-force allows it (elements,
    /// with no mass law or an eliminated one, and fewer element dofs than modes), on the
    /// modal coordinates otherwise.
    Newton,
    /// Always Newton on all the modal coordinates (the dense reference).
    ModalNewton,
}

/// Integrator settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// State approximation inside the step.
    pub scheme: Scheme,
    /// Quadrature of the pseudo-force.
    pub quadrature: Quadrature,
    /// Relative tolerance of the Newton updates.
    pub tol: f64,
    /// Newton iterations before giving up.
    pub max_iter: usize,
    /// Closed form where possible, or always Newton.
    pub solver: Solver,
    /// Levels of automatic step subdivision: a step whose equation does not converge is
    /// retried in halves, down to `dt / 2^subdivisions` (0: the run stops instead).
    pub subdivisions: usize,
    /// The growth guard's limit ([`super::GrowthGuard`]); infinite: no guard.
    pub growth_limit: f64,
}

/// A nonlinear modal problem: the linear background plus the pseudo-forces.
pub struct NonlinearProblem<'a> {
    /// Background modes, loads, initial state, step and output.
    pub base: ModalProblem<'a>,
    /// Mode shapes, `n_dof x n_modes` row-major (mass-normalised).
    pub phi: &'a [f64],
    /// Number of physical degrees of freedom.
    pub n_dof: usize,
    /// Force elements.
    pub elements: &'a [&'a dyn Element],
    /// Modal stiffness coupling `Phi^T K_c Phi` (`n_modes x n_modes`), if any.
    pub coupling_k: Option<&'a [f64]>,
    /// Modal damping coupling `Phi^T C_c Phi`, if any.
    pub coupling_c: Option<&'a [f64]>,
    /// Couplings multiplied by a speed law (the gyroscopic `omega(t) G` of a run-up).
    pub scaled: &'a [ScaledCoupling<'a>],
    /// Time-varying mass, if any.
    pub mass: Option<&'a TimeVaryingMass>,
    /// Integrator settings.
    pub options: Options,
    /// The elements' committed internal variables at the start (a run continued from a
    /// checkpoint: [`crate::History::element_state`] of the run before); None: their
    /// initial values.
    pub element_state: Option<&'a [f64]>,
    /// The growth guard's bounds at the start (a continued run: [`crate::History::guard_state`]
    /// of the run before); None: counted from this run's start.
    pub guard_state: Option<&'a [f64]>,
    /// The energy integrals to accumulate during the run ([`crate::energy`]); None: none.
    pub energy: Option<crate::energy::EnergySpec<'a>>,
}

/// Checks the problem; errors name the Python-side parameter.
pub(super) fn validate(problem: &NonlinearProblem) -> Result<(), CoreError> {
    problem.base.check()?;
    let n = problem.base.k.len();
    if problem.phi.len() != problem.n_dof * n {
        return Err(CoreError::LengthMismatch {
            name: "phi",
            got: problem.phi.len(),
            expected: problem.n_dof * n,
        });
    }
    let o = &problem.options;
    if !(o.tol.is_finite() && o.tol > 0.0) {
        return Err(CoreError::InvalidInput {
            name: "tol",
            problem: format!("must be a positive number, got {}", o.tol),
        });
    }
    if o.max_iter == 0 {
        return Err(CoreError::InvalidInput {
            name: "max_iter",
            problem: "must be at least 1".into(),
        });
    }
    if o.subdivisions > 30 {
        return Err(CoreError::InvalidInput {
            name: "subdivisions",
            problem: format!(
                "must be at most 30 (steps of dt / 2^30), got {}",
                o.subdivisions
            ),
        });
    }
    if let Some(mass) = problem.mass {
        mass.law.validate(problem.base.time(problem.base.n_steps))?;
    }
    for s in problem.scaled {
        s.law.validate()?;
    }
    Ok(())
}
