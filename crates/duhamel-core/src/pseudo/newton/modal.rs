//! Newton's method on all the modal coordinates (the dense reference, and the route where
//! the pseudo-force is not the elements' alone: an estimated mass law).

use super::super::force::PseudoForce;
use super::super::scheme::{StepInput, Unknown};
use super::damping::backtrack;
use super::{Nodes, StepSolver};
use crate::dense::solve_in_place;
use crate::error::CoreError;

impl StepSolver<'_> {
    /// Residual of the active unknowns; returns its max norm.
    pub(super) fn residual(&mut self, inp: &StepInput) -> f64 {
        let n = self.n;
        let mut norm = 0.0_f64;
        for m in 0..n {
            let rows: &[(usize, usize)] = match self.unknown {
                Unknown::Q1 => &[(0, 0)],
                Unknown::V1 => &[(1, 0)],
                Unknown::Both => &[(0, 0), (1, 1)],
            };
            for &(row, block) in rows {
                let z = if row == 0 { self.q1[m] } else { self.v1[m] };
                let r = z - self.explicit(inp, row, m);
                self.res[block * n + m] = r;
                // NaN must not vanish in the max (f64::max drops it).
                if r.is_nan() || r.abs() > norm {
                    norm = r.abs();
                }
            }
        }
        norm
    }

    /// Newton matrix `I - sum_i W_i dQ_i/dz` on the active unknowns.
    pub(super) fn jacobian(&mut self) {
        let n = self.n;
        let dt = self.dt;
        let m = self.res.len();
        self.mat.fill(0.0);
        for i in 0..m {
            self.mat[i * m + i] = 1.0;
        }
        for (node, ((wx, wv), jac)) in self
            .rule
            .nodes
            .iter()
            .zip(self.rule.wx.iter().zip(&self.rule.wv).zip(&self.jacs))
        {
            let [dqq, dqv, dvq, dvv] = node.d;
            // dQ/dq1 and dQ/dv1 at this node, entry (r, c)
            let d_dq1 = |r: usize, c: usize| jac.kq[r * n + c] * dqq + jac.cq[r * n + c] * dvq;
            let d_dv1 = |r: usize, c: usize| {
                jac.kq[r * n + c] * dqv
                    + jac.cq[r * n + c] * dvv
                    + if r == c { jac.da / dt } else { 0.0 }
            };
            for r in 0..n {
                match self.unknown {
                    Unknown::Q1 => {
                        for c in 0..n {
                            self.mat[r * m + c] -= wx[r] * d_dq1(r, c);
                        }
                    }
                    Unknown::V1 => {
                        for c in 0..n {
                            self.mat[r * m + c] -= wv[r] * d_dv1(r, c);
                        }
                    }
                    Unknown::Both => {
                        for c in 0..n {
                            let (a, b) = (d_dq1(r, c), d_dv1(r, c));
                            self.mat[r * m + c] -= wx[r] * a;
                            self.mat[r * m + n + c] -= wx[r] * b;
                            self.mat[(n + r) * m + c] -= wv[r] * a;
                            self.mat[(n + r) * m + n + c] -= wv[r] * b;
                        }
                    }
                }
            }
        }
    }

    /// The active unknowns as one vector.
    fn get_z(&self, out: &mut Vec<f64>) {
        out.clear();
        match self.unknown {
            Unknown::Q1 => out.extend_from_slice(&self.q1),
            Unknown::V1 => out.extend_from_slice(&self.v1),
            Unknown::Both => {
                out.extend_from_slice(&self.q1);
                out.extend_from_slice(&self.v1);
            }
        }
    }

    /// Sets the active unknowns to `z + lambda d`.
    fn set_z(&mut self, z: &[f64], d: &[f64], lambda: f64) {
        let n = self.n;
        for (k, (zk, dk)) in z.iter().zip(d).enumerate() {
            let u = zk + lambda * dk;
            match (self.unknown, k / n) {
                (Unknown::Both, 1) => self.v1[k - n] = u,
                (Unknown::Both, _) | (Unknown::Q1, _) => self.q1[k] = u,
                (Unknown::V1, _) => self.v1[k] = u,
            }
        }
    }

    /// Newton's method with the analytic tangents, damped by backtracking when a full step
    /// increases the residual (a stick-slip friction law, for instance, can make plain
    /// Newton cycle).
    pub(super) fn newton(
        &mut self,
        pf: &mut PseudoForce,
        inp: &StepInput,
    ) -> Result<usize, CoreError> {
        let m = self.res.len();
        let scale0 = inp
            .q0
            .iter()
            .chain(inp.v0)
            .chain(inp.q_lin)
            .chain(inp.v_lin)
            .fold(0.0_f64, |a, b| a.max(b.abs()));
        let mut norm = f64::INFINITY;
        let (mut z0, mut delta) = (
            std::mem::take(&mut self.z0),
            std::mem::take(&mut self.delta),
        );
        delta.resize(m, 0.0);
        let result = self.newton_iterations(pf, inp, &mut z0, &mut delta, scale0, &mut norm);
        (self.z0, self.delta) = (z0, delta);
        result
    }

    fn newton_iterations(
        &mut self,
        pf: &mut PseudoForce,
        inp: &StepInput,
        z0: &mut Vec<f64>,
        delta: &mut [f64],
        scale0: f64,
        norm: &mut f64,
    ) -> Result<usize, CoreError> {
        let m = self.res.len();
        let mut last: Option<f64> = None;
        for iter in 1..=self.max_iter {
            self.nodes(pf, inp, true, Nodes::Varying)?;
            *norm = self.residual(inp);
            if let Some(prev) = last {
                *norm = backtrack(prev, *norm, scale0, |lambda| {
                    self.set_z(z0, delta, lambda);
                    self.nodes(pf, inp, true, Nodes::Varying)?;
                    Ok(self.residual(inp))
                })?;
            }
            self.jacobian();
            for (d, r) in delta.iter_mut().zip(&self.res) {
                *d = -r;
            }
            if !solve_in_place(m, &self.mat, delta) {
                break;
            }
            self.get_z(z0);
            self.set_z(z0, delta, 1.0);
            let size = delta.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
            let zmax = z0
                .iter()
                .zip(delta.iter())
                .fold(0.0_f64, |a, (z, d)| a.max((z + d).abs()));
            // An affine residual with its exact Jacobian is solved by this one step.
            if self.linear || size <= self.tol * zmax.max(scale0) || size == 0.0 {
                return Ok(iter);
            }
            last = Some(*norm);
        }
        Err(CoreError::NoConvergence {
            time: inp.t + self.dt,
            step: 0,
            residual: *norm,
            iterations: self.max_iter,
            last_good_time: Some(inp.t),
        })
    }
}
