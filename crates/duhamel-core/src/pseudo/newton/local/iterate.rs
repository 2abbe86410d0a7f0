//! Newton's method on the element-space step equation `F(y) = 0` (see the parent module).

use super::super::super::local::{zero, ElementSpace};
use super::super::super::scheme::StepInput;
use super::super::damping::{backtrack, corrected};
use super::{LocalNewton, Setting};
use crate::dense_rows::add_matvec;
use crate::error::CoreError;

impl LocalNewton {
    /// Evaluates the varying nodes at `y` and returns the residual's max norm.
    pub(super) fn residual(
        &mut self,
        space: &mut ElementSpace,
        set: &Setting,
        inp: &StepInput,
        tangent: bool,
    ) -> Result<f64, CoreError> {
        let nd = self.nd;
        self.res.copy_from_slice(&self.y);
        for (r, y0) in self.res.iter_mut().zip(&self.y0) {
            *r -= y0;
        }
        for i in 0..self.map.len() {
            let (alpha, beta, constant) =
                (self.map[i].alpha, self.map[i].beta, self.map[i].constant);
            if constant {
                continue;
            }
            for a in 0..nd {
                self.u[a] = self.u0[i][a] + alpha * self.y[a];
                self.ud[a] = self.ud0[i][a] + beta * self.y[a];
            }
            let t = inp.t + self.map[i].s * set.dt;
            let tan = tangent.then_some((&mut self.kt[i][..], &mut self.ct[i][..]));
            space.eval(&self.u, &self.ud, t, &mut self.r[i], tan)?;
            add_matvec(&mut self.res, &self.g[i], &self.r[i]);
        }
        // NaN must not vanish in the max (f64::max drops it).
        Ok(self.res.iter().fold(0.0_f64, |acc, &r| {
            if r.is_nan() || r.abs() > acc {
                r.abs()
            } else {
                acc
            }
        }))
    }

    /// `J = I + sum_i G_i (alpha_i K_i + beta_i C_i)` over the varying nodes.
    fn jacobian(&mut self) {
        let nd = self.nd;
        zero(&mut self.mat);
        for a in 0..nd {
            self.mat[a * nd + a] = 1.0;
        }
        for i in 0..self.map.len() {
            let (alpha, beta, constant) =
                (self.map[i].alpha, self.map[i].beta, self.map[i].constant);
            if constant {
                continue;
            }
            let (g, kt, ct) = (&self.g[i], &self.kt[i], &self.ct[i]);
            for a in 0..nd {
                let row = &mut self.mat[a * nd..(a + 1) * nd];
                for (c, cols) in self.pattern.iter().enumerate() {
                    let gac = g[a * nd + c];
                    if gac == 0.0 {
                        continue;
                    }
                    for &b in cols {
                        row[b] += gac * (alpha * kt[c * nd + b] + beta * ct[c * nd + b]);
                    }
                }
            }
        }
    }

    /// Whether the kept elimination is that of the matrix [`LocalNewton::jacobian`] would
    /// form now: the same `G_i` (no rebuild since), and the varying nodes' tangents bit for
    /// bit those it was formed with on every entry the matrix reads.
    fn same_tangents(&self) -> bool {
        if !self.kept.valid {
            return false;
        }
        let nd = self.nd;
        let mut slot = 0;
        for i in 0..self.map.len() {
            if self.map[i].constant {
                continue;
            }
            let (kt, ct, kk, ck) = (
                &self.kt[i],
                &self.ct[i],
                &self.kept_kt[slot],
                &self.kept_ct[slot],
            );
            for (c, cols) in self.pattern.iter().enumerate() {
                for &b in cols {
                    let e = c * nd + b;
                    if kt[e].to_bits() != kk[e].to_bits() || ct[e].to_bits() != ck[e].to_bits() {
                        return false;
                    }
                }
            }
            slot += 1;
        }
        true
    }

    /// Keeps the varying nodes' tangents the matrix is formed with.
    fn keep_tangents(&mut self) {
        let varying = self.map.iter().filter(|m| !m.constant).count();
        self.kept_kt.resize(varying, Vec::new());
        self.kept_ct.resize(varying, Vec::new());
        let mut slot = 0;
        for i in 0..self.map.len() {
            if self.map[i].constant {
                continue;
            }
            self.kept_kt[slot].clone_from(&self.kt[i]);
            self.kept_ct[slot].clone_from(&self.ct[i]);
            slot += 1;
        }
    }

    /// Whether the last node evaluated (the last varying one) is the end state.
    pub(super) fn ends_at_end(&self) -> bool {
        let end = self.map.iter().rev().find(|m| !m.constant);
        end.is_some_and(|m| m.s == 1.0)
    }

    /// The iteration's end: when its last evaluation (with tangents) was at the end node of
    /// the converged state, the stiffness watch reuses those tangents, and the commit those
    /// trial variables where that node's displacements are the unknown `q1` itself
    /// (schemes b and c; along scheme a they are the scheme's approximation, not `q1`).
    pub(super) fn accept(&self, space: &mut ElementSpace) {
        if self.ends_at_end() {
            space.mark_end();
            if self.end_is_unknown {
                space.mark_end_trial();
            }
        }
    }

    /// Newton's method on `F(y) = 0`, damped by the modal one's [`backtrack`].
    pub(super) fn newton(
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
            norm = self.residual(space, set, inp, true)?;
            let mut cut = false;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    cut = true;
                    for ((y, yp), d) in self.y.iter_mut().zip(&self.y_prev).zip(&self.delta) {
                        *y = yp + lambda * d;
                    }
                    self.residual(space, set, inp, true)
                })?;
            }
            for (d, r) in self.delta.iter_mut().zip(&self.res) {
                *d = -r;
            }
            if self.same_tangents() {
                // the matrix bit for bit the last one's: its elimination repeated
                if !self.kept.solve(&mut self.delta) {
                    break;
                }
            } else {
                self.jacobian();
                self.keep_tangents();
                if !self.kept.eliminate(self.nd, &mut self.mat, &mut self.delta) {
                    break;
                }
            }
            let Some((size, scale)) = corrected(&mut self.y, &mut self.y_prev, &self.delta, scale0)
            else {
                // the state just evaluated is the solution to rounding: its forces and
                // tangents are the end's, no update and no evaluation again
                self.accept(space);
                return Ok(iter);
            };
            if set.settled(last_size, size, scale, cut) {
                // The forces at the accepted state, with the tangents the stiffness watch
                // then reuses when the last node evaluated is the end state.
                let at_end = self.ends_at_end();
                self.residual(space, set, inp, at_end)?;
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
