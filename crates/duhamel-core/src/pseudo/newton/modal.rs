//! Newton's method on all the modal coordinates (the dense reference, and the route where
//! the pseudo-force is not the elements' alone: an estimated mass law), and the buffers the
//! single-mode closed forms share with it.

use super::super::force::{At, Jacobian, PseudoForce};
use super::super::scheme::{StepInput, Unknown};
use super::damping::backtrack;
use super::setting::Setting;
use crate::dense::solve_overwriting;
use crate::dense_kept::KeptLu;
use crate::error::CoreError;

/// Which nodes to evaluate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Nodes {
    /// Those whose state does not depend on the unknowns (once per step).
    Constant,
    /// Those whose state does.
    Varying,
}

/// The pseudo-force at the start state of the last step, when the step evaluated it (an
/// evaluation saved for the saved history).
pub(super) struct Start {
    /// Whether `values` belongs to the last step's start state.
    pub known: bool,
    /// The pseudo-force there (`n`).
    pub values: Vec<f64>,
}

/// The modal step's state and buffers: the end state being solved for, the node states,
/// loads and pseudo-force values, their tangents and Newton's system.
pub(super) struct Modal {
    /// The end state.
    pub(super) q1: Vec<f64>,
    pub(super) v1: Vec<f64>,
    /// The state, load and acceleration estimate at a node.
    pub(super) qn: Vec<f64>,
    pub(super) vn: Vec<f64>,
    pub(super) pn: Vec<f64>,
    pub(super) acc: Vec<f64>,
    /// The pseudo-force at each node, and its tangents.
    pub(super) values: Vec<Vec<f64>>,
    pub(super) jacs: Vec<Jacobian>,
    /// Newton's residual and matrix on the active unknowns.
    pub(super) res: Vec<f64>,
    pub(super) mat: Vec<f64>,
    /// Newton's buffers, kept between steps.
    pub(super) z0: Vec<f64>,
    pub(super) delta: Vec<f64>,
    /// Whether Newton's matrix is the same at every step (a linear pseudo-force with
    /// constant couplings and no mass law): then factorised once and kept.
    pub(super) constant_matrix: bool,
    kept: Option<KeptLu>,
}

impl Modal {
    /// Buffers for `n` modes and `nodes` nodes: Newton's system of `m` unknowns, the
    /// tangents `dense x dense`.
    pub fn new(n: usize, nodes: usize, m: usize, dense: usize) -> Self {
        Modal {
            q1: vec![0.0; n],
            v1: vec![0.0; n],
            qn: vec![0.0; n],
            vn: vec![0.0; n],
            pn: vec![0.0; n],
            acc: vec![0.0; n],
            values: vec![vec![0.0; n]; nodes],
            jacs: (0..nodes).map(|_| Jacobian::new(dense)).collect(),
            res: vec![0.0; m],
            mat: vec![0.0; m * m],
            z0: Vec::with_capacity(m),
            delta: vec![0.0; m],
            constant_matrix: false,
            kept: None,
        }
    }

    /// Solves the step on the modal coordinates into `(q1, v1)`, by the closed-form cubic
    /// first when `closed`; keeps the start state's pseudo-force in `start` when it comes
    /// for free. Returns the Newton iterations (0 for the closed form).
    pub fn solve(
        &mut self,
        set: &Setting,
        closed: bool,
        pf: &mut PseudoForce,
        inp: &StepInput,
        start: &mut Start,
    ) -> Result<usize, CoreError> {
        let n = set.n;
        // Predictor: the linear step plus the pseudo-force of the start state held constant.
        // A constant first node is the start state itself (s = 0, and the force does not
        // depend on the only thing that differs, the velocity of schemes a and b).
        self.q1.copy_from_slice(inp.q0);
        self.v1.copy_from_slice(inp.v0);
        self.nodes(set, pf, inp, false, Nodes::Constant)?;
        start.known = set.constant[0];
        if set.constant[0] {
            start.values.copy_from_slice(&self.values[0]);
        } else {
            self.acc.fill(0.0);
            pf.set_left_limit(false);
            let at = At {
                q: inp.q0,
                v: inp.v0,
                t: inp.t,
                p: inp.pb[0],
                a: Some(&self.acc),
            };
            pf.eval(at, &mut start.values, None)?;
        }
        for m in 0..n {
            let wx: f64 = set.rule.wx.iter().map(|w| w[m]).sum();
            let wv: f64 = set.rule.wv.iter().map(|w| w[m]).sum();
            self.q1[m] = inp.q_lin[m] + wx * start.values[m];
            self.v1[m] = inp.v_lin[m] + wv * start.values[m];
        }
        let iterations = if closed && self.closed(set, pf, inp)? {
            0
        } else {
            let it = self.newton(set, pf, inp)?;
            // Node values at the converged state (Newton's last ones precede its update);
            // for one mode with the end state as the last node, with the tangents the
            // stiffness watch then reuses (wider, the modal tangents cost n^2 per node).
            let end = (0..set.rule.nodes.len()).rev().find(|&i| !set.constant[i]);
            let at_end = set.n == 1 && end.is_some_and(|i| set.rule.nodes[i].s == 1.0);
            self.nodes(set, pf, inp, at_end, Nodes::Varying)?;
            if at_end {
                pf.space_mut().mark_end();
            }
            it
        };
        // The other half of the end state, explicitly, from the node values.
        for m in 0..n {
            match set.unknown {
                Unknown::Q1 => self.v1[m] = self.explicit(set, inp, 1, m),
                Unknown::V1 => self.q1[m] = self.explicit(set, inp, 0, m),
                Unknown::Both => {}
            }
        }
        Ok(iterations)
    }

    /// Evaluates the pseudo-force at the selected nodes for the current `(q1, v1)`.
    pub(super) fn nodes(
        &mut self,
        set: &Setting,
        pf: &mut PseudoForce,
        inp: &StepInput,
        tangent: bool,
        which: Nodes,
    ) -> Result<(), CoreError> {
        let dt = set.dt;
        for (i, node) in set.rule.nodes.iter().enumerate() {
            if set.constant[i] != (which == Nodes::Constant) {
                continue;
            }
            let s = node.s;
            for m in 0..set.n {
                (self.qn[m], self.vn[m]) = set
                    .scheme
                    .state(s, dt, inp.q0[m], inp.v0[m], self.q1[m], self.v1[m]);
                self.pn[m] = inp.pb[0][m] + inp.pb[1][m] * s + 4.0 * inp.pb[2][m] * s * (1.0 - s);
                self.acc[m] = (self.v1[m] - inp.v0[m]) / dt;
            }
            let jac = if tangent {
                Some(&mut self.jacs[i])
            } else {
                None
            };
            let a = set.acceleration.then_some(&self.acc[..]);
            let at = At {
                q: &self.qn,
                v: &self.vn,
                t: inp.t + s * dt,
                p: &self.pn,
                a,
            };
            pf.eval(at, &mut self.values[i], jac)?;
        }
        Ok(())
    }

    /// `row` 0: `q_lin + sum wx Q`; row 1: `v_lin + sum wv Q`, for mode `m`.
    fn explicit(&self, set: &Setting, inp: &StepInput, row: usize, m: usize) -> f64 {
        let (base, w) = if row == 0 {
            (inp.q_lin, &set.rule.wx)
        } else {
            (inp.v_lin, &set.rule.wv)
        };
        base[m]
            + w.iter()
                .zip(&self.values)
                .map(|(wi, qi)| wi[m] * qi[m])
                .sum::<f64>()
    }

    /// Residual of the active unknowns; returns its max norm.
    pub(super) fn residual(&mut self, set: &Setting, inp: &StepInput) -> f64 {
        let n = set.n;
        let mut norm = 0.0_f64;
        for m in 0..n {
            let rows: &[(usize, usize)] = match set.unknown {
                Unknown::Q1 => &[(0, 0)],
                Unknown::V1 => &[(1, 0)],
                Unknown::Both => &[(0, 0), (1, 1)],
            };
            for &(row, block) in rows {
                let z = if row == 0 { self.q1[m] } else { self.v1[m] };
                let r = z - self.explicit(set, inp, row, m);
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
    pub(super) fn jacobian(&mut self, set: &Setting) {
        let n = set.n;
        let dt = set.dt;
        let m = self.res.len();
        self.mat.fill(0.0);
        for i in 0..m {
            self.mat[i * m + i] = 1.0;
        }
        for (node, ((wx, wv), jac)) in set
            .rule
            .nodes
            .iter()
            .zip(set.rule.wx.iter().zip(&set.rule.wv).zip(&self.jacs))
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
                match set.unknown {
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
    fn get_z(&self, set: &Setting, out: &mut Vec<f64>) {
        out.clear();
        match set.unknown {
            Unknown::Q1 => out.extend_from_slice(&self.q1),
            Unknown::V1 => out.extend_from_slice(&self.v1),
            Unknown::Both => {
                out.extend_from_slice(&self.q1);
                out.extend_from_slice(&self.v1);
            }
        }
    }

    /// Sets the active unknowns to `z + lambda d`.
    fn set_z(&mut self, set: &Setting, z: &[f64], d: &[f64], lambda: f64) {
        let n = set.n;
        for (k, (zk, dk)) in z.iter().zip(d).enumerate() {
            let u = zk + lambda * dk;
            match (set.unknown, k / n) {
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
        set: &Setting,
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
        let (mut z0, mut delta) = (
            std::mem::take(&mut self.z0),
            std::mem::take(&mut self.delta),
        );
        delta.resize(m, 0.0);
        let result = self.newton_iterations(set, pf, inp, (&mut z0, &mut delta), scale0);
        (self.z0, self.delta) = (z0, delta);
        result
    }

    fn newton_iterations(
        &mut self,
        set: &Setting,
        pf: &mut PseudoForce,
        inp: &StepInput,
        (z0, delta): (&mut Vec<f64>, &mut [f64]),
        scale0: f64,
    ) -> Result<usize, CoreError> {
        let m = self.res.len();
        let mut norm = f64::INFINITY;
        let mut last: Option<f64> = None;
        // A constant matrix above the small sizes: faer's factors of the first step, kept
        // (the same solution, bit for bit, as factorising it again; no tangents needed).
        let keep = self.constant_matrix && KeptLu::applies(m);
        for iter in 1..=set.max_iter {
            let tangents = !(keep && self.kept.is_some());
            self.nodes(set, pf, inp, tangents, Nodes::Varying)?;
            norm = self.residual(set, inp);
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    self.set_z(set, z0, delta, lambda);
                    self.nodes(set, pf, inp, true, Nodes::Varying)?;
                    Ok(self.residual(set, inp))
                })?;
            }
            for (d, r) in delta.iter_mut().zip(&self.res) {
                *d = -r;
            }
            if keep {
                if self.kept.is_none() {
                    self.jacobian(set);
                    self.kept = Some(KeptLu::factor(m, &self.mat));
                }
                if !self.kept.as_ref().is_some_and(|lu| lu.solve(delta)) {
                    break;
                }
            } else {
                self.jacobian(set);
                if !solve_overwriting(m, &mut self.mat, delta) {
                    break;
                }
            }
            self.get_z(set, z0);
            self.set_z(set, z0, delta, 1.0);
            let size = delta.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
            let zmax = z0
                .iter()
                .zip(delta.iter())
                .fold(0.0_f64, |a, (z, d)| a.max((z + d).abs()));
            // An affine residual with its exact Jacobian is solved by this one step.
            if set.linear || size <= set.tol * zmax.max(scale0) || size == 0.0 {
                return Ok(iter);
            }
            last = Some(norm);
        }
        Err(set.no_convergence(inp, norm))
    }

    pub(super) fn unknown_value(&self, set: &Setting, m: usize) -> f64 {
        if set.unknown == Unknown::V1 {
            self.v1[m]
        } else {
            self.q1[m]
        }
    }

    pub(super) fn set_unknown(&mut self, set: &Setting, m: usize, u: f64) {
        if set.unknown == Unknown::V1 {
            self.v1[m] = u;
        } else {
            self.q1[m] = u;
        }
    }
}
