//! The uniaxial material law: force, tangent and internal variables (see `mod.rs`).

use crate::error::CoreError;

/// A uniaxial force-deformation law with internal variables.
pub trait Material: Send + Sync + std::fmt::Debug {
    /// The number of internal variables (0 for an elastic law).
    fn state_len(&self) -> usize;

    /// The virgin internal variables (no deformation, no history).
    fn initial_state(&self, state: &mut [f64]);

    /// The force and consistent tangent `(F, dF/du)` at deformation `u` (rate `rate`)
    /// reached from the `committed` variables, writing the variables a commit at `u` keeps
    /// into `trial` (same length as `committed`). An error names what failed (a deformation
    /// outside the law's domain); non-finite results are caught by the element.
    fn response(
        &self,
        u: f64,
        rate: f64,
        committed: &[f64],
        trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError>;

    /// The tangent at the virgin state (OpenSees' `getInitialTangent`): the stiffness of the
    /// element's linear background, of `System.modal(elements="initial")`, and the bound
    /// the substep rules start from.
    fn initial_tangent(&self) -> f64;

    /// Whether the force depends on the rate (a viscous material).
    fn uses_rate(&self) -> bool {
        false
    }

    /// A bound on `|dF/du|` over every state the law can reach, when there is one (the
    /// largest stiffness of its branches); None when it has none (the default).
    fn tangent_bound(&self) -> Option<f64> {
        None
    }

    /// Whether the force at a committed deformation, evaluated again from the committed
    /// variables, is bit for bit the force of the evaluation that committed them (a zero
    /// increment changes nothing): the integrators then reuse that force as the next step's
    /// start ([`Element::restarts_exactly`](crate::elements::element::Element)). False by
    /// default; a law that says true is checked along its histories (`restart_tests.rs`).
    fn restarts_exactly(&self) -> bool {
        false
    }

    /// Whether the law only stores or dissipates the work done on it (true of every
    /// rate-independent hysteretic law whose stored energy is bounded below).
    fn passive(&self) -> bool {
        true
    }

    /// The recoverable (stored) energy at the state `(u, F)` with the committed variables
    /// `state`: the energy released by unloading to zero force along the unloading branch.
    /// Default: unloading along the initial tangent, `F^2 / (2 k0)`.
    fn stored_energy(&self, _state: &[f64], _u: f64, force: f64) -> f64 {
        let k0 = self.initial_tangent();
        if k0 > 0.0 {
            0.5 * force * force / k0
        } else {
            0.0
        }
    }
}

impl<M: Material + ?Sized> Material for Box<M> {
    fn state_len(&self) -> usize {
        (**self).state_len()
    }
    fn initial_state(&self, state: &mut [f64]) {
        (**self).initial_state(state)
    }
    fn response(
        &self,
        u: f64,
        rate: f64,
        committed: &[f64],
        trial: &mut [f64],
    ) -> Result<(f64, f64), CoreError> {
        (**self).response(u, rate, committed, trial)
    }
    fn initial_tangent(&self) -> f64 {
        (**self).initial_tangent()
    }
    fn uses_rate(&self) -> bool {
        (**self).uses_rate()
    }
    fn tangent_bound(&self) -> Option<f64> {
        (**self).tangent_bound()
    }
    fn restarts_exactly(&self) -> bool {
        (**self).restarts_exactly()
    }
    fn passive(&self) -> bool {
        (**self).passive()
    }
    fn stored_energy(&self, state: &[f64], u: f64, force: f64) -> f64 {
        (**self).stored_energy(state, u, force)
    }
}
