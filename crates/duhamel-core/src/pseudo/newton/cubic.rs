//! The closed-form step of one mode with polynomial forces through the Newton machinery:
//! two evaluations of the residual (values and analytic slopes) give the cubic it is.

use super::super::closed::hermite;
use super::super::force::PseudoForce;
use super::super::scheme::{StepInput, Unknown};
use super::modal::{Modal, Nodes};
use super::setting::Setting;
use crate::cubic::nearest_root;
use crate::error::CoreError;

impl Modal {
    /// `dQ_i/du` at node `i` for one mode (the unknown's direction).
    fn node_slope(&self, set: &Setting, i: usize) -> f64 {
        let [dqq, dqv, dvq, dvv] = set.rule.nodes[i].d;
        let j = &self.jacs[i];
        match set.unknown {
            Unknown::V1 => j.kq[0] * dqv + j.cq[0] * dvv,
            _ => j.kq[0] * dqq + j.cq[0] * dvq,
        }
    }

    /// The closed-form cubic for one mode; `false` when it has no real root.
    ///
    /// With polynomial forces of degree <= 3 and a state affine in the unknown `u`, the
    /// residual and every node's pseudo-force are cubics in `u`: values and analytic slopes
    /// at two points determine them exactly (Hermite), so two evaluations give the cubic,
    /// its root nearest the predictor, and the node values there.
    pub(super) fn closed(
        &mut self,
        set: &Setting,
        pf: &mut PseudoForce,
        inp: &StepInput,
    ) -> Result<bool, CoreError> {
        let u_pred = self.unknown_value(set, 0);
        let u_start = if set.unknown == Unknown::V1 {
            inp.v0[0]
        } else {
            inp.q0[0]
        };
        let h = (u_pred - u_start)
            .abs()
            .max(1e-6 * u_pred.abs().max(u_start.abs()))
            .max(1e-100);
        let nodes = set.rule.nodes.len();
        // (value, slope) of the residual and of each node's Q at delta = 0 and delta = 1.
        let mut r = [[0.0; 2]; 2];
        let mut qv = [[[0.0; 2]; 2]; 4];
        for (k, delta) in [0.0, 1.0].into_iter().enumerate() {
            self.set_unknown(set, 0, u_pred + h * delta);
            self.nodes(set, pf, inp, true, Nodes::Varying)?;
            self.residual(set, inp);
            self.jacobian(set);
            r[k] = [self.res[0], self.mat[0] * h];
            for (i, slot) in qv.iter_mut().enumerate().take(nodes) {
                if !set.constant[i] {
                    slot[k] = [self.values[i][0], self.node_slope(set, i) * h];
                }
            }
        }
        let [c0, c1, c2, c3] = hermite(r[0], r[1]);
        let Some(delta) = nearest_root([c0, c1, c2, c3], 0.0).filter(|d| d.is_finite()) else {
            self.set_unknown(set, 0, u_pred);
            return Ok(false);
        };
        self.set_unknown(set, 0, u_pred + h * delta);
        for (i, data) in qv.iter().enumerate().take(nodes) {
            if !set.constant[i] {
                let [a0, a1, a2, a3] = hermite(data[0], data[1]);
                self.values[i][0] = ((a3 * delta + a2) * delta + a1) * delta + a0;
            }
        }
        Ok(true)
    }
}
