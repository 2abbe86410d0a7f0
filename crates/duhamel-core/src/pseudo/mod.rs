//! Nonlinear semi-analytic stepping (the paper's sections 2-4): every modal oscillator of
//! the linear background is stepped with its exact matrices, and everything else — element
//! forces, linear couplings (non-classical damping, cross-coupled and gyroscopic terms),
//! time-varying mass — enters as a modal pseudo-force approximated over the step.

//!
//! The corrector of a route ([`crate::driver`]): on the uncoupled background it is the
//! implicit step equation of [`newton`] (with the closed form of [`closed`] for one mode),
//! run by [`route`]; on the first-order background of a coupled system it is
//! [`first_order`].

mod closed;
pub mod first_order;
pub mod force;
mod newton;
mod route;
mod scalar;
mod scheme;

pub use newton::Solver;
pub use route::integrate;
pub use scheme::{Quadrature, Scheme};

pub use crate::history::Stats;

use crate::elements::Element;
use crate::error::CoreError;
use crate::mass::TimeVaryingMass;
use crate::problem::ModalProblem;
use crate::speed::SpeedLaw;

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
}

/// A modal coupling whose pseudo-force is `-s(t) (K q + C v)`, `s` a speed law:
/// `LinearCoupling(K, C, scale=...)`.
#[derive(Debug, Clone, Copy)]
pub struct ScaledCoupling<'a> {
    /// Modal stiffness coupling `Phi^T K Phi` (`n_modes x n_modes`, row-major), if any.
    pub k: Option<&'a [f64]>,
    /// Modal damping coupling `Phi^T C Phi`, if any.
    pub c: Option<&'a [f64]>,
    /// The time scale.
    pub law: SpeedLaw,
}

/// Checks the problem; errors name the Python-side parameter.
fn validate(problem: &NonlinearProblem) -> Result<(), CoreError> {
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
    if let Some(mass) = problem.mass {
        mass.law.validate(problem.base.time(problem.base.n_steps))?;
    }
    for s in problem.scaled {
        s.law.validate()?;
    }
    Ok(())
}
