//! The single-mode view of the pseudo-force: what the closed-form cubic step needs.

use super::PseudoForce;
use crate::elements::ModalCubic;
use crate::mass::{MassForm, MassTreatment};

impl PseudoForce<'_> {
    /// For one mode with polynomial forces only (and no estimated mass): the coefficients of
    /// `rho(q, v) = sum a[i][j] q^i v^j`, elements and couplings together. None as well when
    /// a coupling's scale varies in time (the coefficients would change from node to node:
    /// such a step is solved by the generic closed form or by Newton).
    pub fn scalar_model(&self) -> Option<ModalCubic> {
        if self.n != 1
            || self
                .mass
                .is_some_and(|m| m.treatment == MassTreatment::Estimate)
            || self.scaled.iter().any(|s| s.law.constant_value().is_none())
        {
            return None;
        }
        let mut a = [[0.0; 4]; 4];
        for (element, phi_e) in self.space.element_rows() {
            let e = element.modal_cubic(&phi_e)?;
            for (ai, ei) in a.iter_mut().zip(&e) {
                for (x, y) in ai.iter_mut().zip(ei) {
                    *x += y;
                }
            }
        }
        a[1][0] += self.coupling_k.map_or(0.0, |m| m[0]);
        a[0][1] += self.coupling_c.map_or(0.0, |m| m[0]);
        for s in self.scaled {
            let w = s.law.constant_value()?;
            a[1][0] += w * s.k.map_or(0.0, |m| m[0]);
            a[0][1] += w * s.c.map_or(0.0, |m| m[0]);
        }
        Some(a)
    }

    /// For one mode: `Q = alpha rho + beta q + gamma v + delta` at time `t` with the modal
    /// external load `p` (see the module documentation); returns `[alpha, beta, gamma, delta]`.
    pub fn scalar_terms(&self, t: f64, p: f64, left: bool) -> [f64; 4] {
        let Some(mass) = self.mass else {
            return [-1.0, 0.0, 0.0, 0.0];
        };
        let (mu, dmu) = mass.law.eval_side(t, left);
        let g = 1.0 / mu - 1.0;
        let beta = if mass.scale_stiffness {
            0.0
        } else {
            -g * self.k[0]
        };
        let mom = if mass.form == MassForm::Momentum {
            dmu / mu
        } else {
            0.0
        };
        [-1.0 / mu, beta, -g * self.c[0] - mom, g * p]
    }
}
