//! What a method's step is: the direct integrators' one interface.

use super::model::Model;
use crate::error::CoreError;
use crate::loads::ModalForcing;

/// One step of a method.
pub(crate) trait Stepper {
    /// Advances `[x, v, a]` from `t` to `t + dt`; returns the Newton corrections taken.
    fn step(
        &mut self,
        model: &mut Model,
        forcing: Option<&mut (dyn ModalForcing + '_)>,
        t: f64,
        state: [&mut [f64]; 3],
    ) -> Result<usize, CoreError>;

    /// Factorisations of the iteration matrix so far.
    fn factorizations(&self) -> usize;

    /// Whether the saved acceleration is recomputed from the equation of motion (the state's
    /// `a` is then only a predictor).
    fn equation_acceleration(&self) -> bool;
}
