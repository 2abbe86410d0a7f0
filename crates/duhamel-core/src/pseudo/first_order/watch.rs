//! The checks after a corrected step of the coupled route: the elements' tangent stiffness
//! against the route's limit ([`COUPLED_LIMIT`]: accuracy, well within stability), and the
//! growth guard.

use super::{Corrector, Work};
use crate::error::CoreError;
use crate::pseudo::stiff_rule::COUPLED_LIMIT;

impl Corrector<'_> {
    /// Whether the growth guard watches the run (it then needs the modal loads).
    pub(crate) fn guarded(&self) -> bool {
        self.guard.is_some()
    }

    /// The checks of a corrected step's end at `t`: the elements' tangent stiffness against
    /// the step's stability limit, and the growth guard.
    pub(super) fn watch_end(
        &mut self,
        t: f64,
        (re, im): (&[f64], &[f64]),
        loads: Option<(&[f64], &[f64], &[f64])>,
        w: &mut Work,
    ) -> Result<(), CoreError> {
        if !self.watch && self.guard.is_none() {
            return Ok(());
        }
        self.map(re, im, 1, &mut w.v);
        if self.watch {
            let (lambda, worst) = self.pf.tangent_stiffness(&self.q, &w.v, t)?;
            let h = self.dt * lambda.sqrt();
            let background = self.pf.bg();
            if let Some(nodes) = self.nodes.as_mut() {
                nodes.start = (lambda, background);
            }
            if h > COUPLED_LIMIT {
                let dofs = self.pf.space().element_dofs(worst);
                return Err(CoreError::TooStiff {
                    message: format!(
                        "element {worst} (on dofs {dofs:?}) is too stiff for the step of the \
                         coupled (first-order) route: with its tangent the modes it loads \
                         vibrate at omega_c^2 = {lambda:.4e} (rad/s)^2, omega_c dt = {h:.4}, and \
                         this route, which does not subdivide, is held below omega_c dt = \
                         {COUPLED_LIMIT} (less accurate than Newmark beyond; the pseudo-force \
                         step is unstable beyond 2 sqrt(3) = 3.46): reduce `dt` below {:.4e}",
                        COUPLED_LIMIT / lambda.sqrt()
                    ),
                    time: 0.0,
                    step: 0,
                    last_good_time: None,
                });
            }
        }
        if let (Some(guard), Some(load)) = (self.guard.as_mut(), loads) {
            guard.step(self.dt, (&self.q, &w.v), load)?;
        }
        Ok(())
    }
}
