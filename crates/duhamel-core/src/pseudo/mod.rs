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
mod energy_hook;
pub mod first_order;
pub mod force;
mod growth;
mod local;
mod newton;
mod problem;
mod route;
mod rows;
mod scalar;
mod scheme;
mod stiff_rule;
mod subdivide;

pub use growth::GrowthGuard;
pub use problem::{NonlinearProblem, Options, Solver};
pub use route::integrate;
pub use scheme::{Quadrature, Scheme};

pub use crate::history::Stats;
pub use crate::speed::ScaledCoupling;
