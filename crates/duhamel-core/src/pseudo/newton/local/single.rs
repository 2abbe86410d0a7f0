//! Newton's method in the element space when the elements act on one dof (`n_d = 1`: a
//! storey with one isolator, a chain with one device): [`LocalNewton::newton`] with its
//! residual, Jacobian and `1 x 1` elimination written on scalars, operation for operation
//! (the same numbers, bit for bit), without the per-iteration loops and copies over `n_d`.

use super::super::super::local::ElementSpace;
use super::super::super::scheme::StepInput;
use super::super::damping::{backtrack, below_rounding};
use super::{LocalNewton, Setting};
use crate::error::CoreError;

impl LocalNewton {
    /// `F(y)` at the current `y` for `n_d = 1` (the varying nodes evaluated); its max norm.
    fn residual_one(
        &mut self,
        space: &mut ElementSpace,
        set: &Setting,
        inp: &StepInput,
        tangent: bool,
    ) -> Result<f64, CoreError> {
        let y = self.y[0];
        let mut res = y;
        res -= self.y0[0];
        for i in 0..self.map.len() {
            let m = self.map[i];
            if m.constant {
                continue;
            }
            self.u[0] = self.u0[i][0] + m.alpha * y;
            self.ud[0] = self.ud0[i][0] + m.beta * y;
            let t = inp.t + m.s * set.dt;
            if space.single() {
                let (r, k, c) = space.eval_one(self.u[0], self.ud[0], t, tangent)?;
                self.r[i][0] = r;
                if tangent {
                    (self.kt[i][0], self.ct[i][0]) = (k, c);
                }
            } else {
                let tan = tangent.then_some((&mut self.kt[i][..], &mut self.ct[i][..]));
                space.eval(&self.u, &self.ud, t, &mut self.r[i], tan)?;
            }
            // `dot` of one term: its four zero partial sums, then the term
            let tail: f64 = std::iter::once(self.g[i][0] * self.r[i][0]).sum();
            res += (0.0 + 0.0) + (0.0 + 0.0) + tail;
        }
        self.res[0] = res;
        Ok(if res.is_nan() || res.abs() > 0.0 {
            res.abs()
        } else {
            0.0
        })
    }

    /// `J = 1 + sum_i g_i (alpha_i k_i + beta_i c_i)` over the varying nodes, `n_d = 1`.
    fn jacobian_one(&self) -> f64 {
        let mut mat = 1.0;
        for (i, m) in self.map.iter().enumerate() {
            if m.constant || self.pattern[0].is_empty() {
                continue;
            }
            let g = self.g[i][0];
            if g == 0.0 {
                continue;
            }
            mat += g * (m.alpha * self.kt[i][0] + m.beta * self.ct[i][0]);
        }
        mat
    }

    /// [`LocalNewton::newton`] for `n_d = 1`.
    pub(super) fn newton_one(
        &mut self,
        space: &mut ElementSpace,
        set: &Setting,
        inp: &StepInput,
        scale0: f64,
    ) -> Result<usize, CoreError> {
        let mut last: Option<f64> = None;
        let mut last_size: Option<f64> = None;
        let mut norm = f64::INFINITY;
        for iter in 1..=set.max_iter {
            norm = self.residual_one(space, set, inp, true)?;
            let mut cut = false;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    cut = true;
                    self.y[0] = self.y_prev[0] + lambda * self.delta[0];
                    self.residual_one(space, set, inp, true)
                })?;
            }
            let mat = self.jacobian_one();
            // the elimination of the 1 x 1 system: its pivot test, its back substitution
            let pivot = mat.abs();
            if !(pivot.is_finite() && pivot > 0.0) {
                break;
            }
            let none: f64 = std::iter::empty::<f64>().sum();
            let delta = (-self.res[0] - none) / mat;
            self.delta[0] = delta;
            if !delta.is_finite() {
                break;
            }
            if below_rounding(delta.abs(), self.y[0].abs().max(scale0)) {
                // the state just evaluated is the solution to rounding: its forces and
                // tangents are the end's, no update and no evaluation again
                self.accept(space);
                return Ok(iter);
            }
            self.y_prev[0] = self.y[0];
            self.y[0] += delta;
            let size = 0.0_f64.max(delta.abs());
            let ymax = 0.0_f64.max(self.y[0].abs());
            let scale = ymax.max(scale0);
            if set.settled(last_size, size, scale, cut) {
                let at_end = self.ends_at_end();
                self.residual_one(space, set, inp, at_end)?;
                if at_end {
                    self.accept(space);
                }
                return Ok(iter);
            }
            last = Some(norm);
            last_size = Some(size);
        }
        Err(set.no_convergence(inp, norm))
    }
}
