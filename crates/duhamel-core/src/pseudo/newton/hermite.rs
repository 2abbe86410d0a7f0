//! The step of one mode along the Hermite scheme, on scalars: a one-dof oscillator with
//! elements (no mass law, no couplings), both halves of the end state unknown.
//!
//! The node states of the Hermite scheme depend on `q1` and `v1`, so the step equation
//! `z = z_lin + sum_i W_i Q_i(z)` is a `2 x 2` system. Newton's method with the elements'
//! analytic tangents, damped by [`backtrack`] as the other iterations; the start node
//! (`s = 0`, the start state itself) is evaluated once per step. The generic
//! [`super::modal::Modal`] iteration solves the same equation on vectors (`2 n` unknowns);
//! this one leaves out its per-node vectors and dense elimination.

use super::super::force::PseudoForce;
use super::super::local::ElementSpace;
use super::super::scheme::StepInput;
use super::damping::backtrack;
use super::one::force;
use super::setting::Setting;
use crate::error::CoreError;

/// The most nodes a quadrature has (the exact cubic rule's four).
const NODES: usize = 4;

/// The one-mode Hermite step's rule (fixed for the run) and its node values.
pub(super) struct Hermite {
    nodes: usize,
    s: [f64; NODES],
    d: [[f64; 4]; NODES],
    wx: [f64; NODES],
    wv: [f64; NODES],
    constant: [bool; NODES],
    wx_sum: f64,
    wv_sum: f64,
    /// Per node: `Q` and its tangents `dQ/dq`, `dQ/dv` (zero at the constant nodes).
    values: [f64; NODES],
    kq: [f64; NODES],
    cq: [f64; NODES],
    q1: f64,
    v1: f64,
    /// Whether the last varying node is the end state (its tangents are then the ones the
    /// stiffness watch reads).
    at_end: bool,
}

impl Hermite {
    /// The step of `set` (one mode, at most [`NODES`] nodes).
    pub fn new(set: &Setting) -> Self {
        let rule = set.rule;
        let nodes = rule.nodes.len();
        let mut one = Hermite {
            nodes,
            s: [0.0; NODES],
            d: [[0.0; 4]; NODES],
            wx: [0.0; NODES],
            wv: [0.0; NODES],
            constant: [true; NODES],
            wx_sum: rule.wx.iter().map(|w| w[0]).sum(),
            wv_sum: rule.wv.iter().map(|w| w[0]).sum(),
            values: [0.0; NODES],
            kq: [0.0; NODES],
            cq: [0.0; NODES],
            q1: 0.0,
            v1: 0.0,
            at_end: false,
        };
        for (i, node) in rule.nodes.iter().enumerate() {
            one.s[i] = node.s;
            one.d[i] = node.d;
            one.wx[i] = rule.wx[i][0];
            one.wv[i] = rule.wv[i][0];
            one.constant[i] = set.constant[i];
        }
        let end = (0..nodes).rev().find(|&i| !set.constant[i]);
        one.at_end = end.is_some_and(|i| rule.nodes[i].s == 1.0);
        one
    }

    /// Whether it applies: one mode along the Hermite scheme, a pseudo-force of elements
    /// only.
    pub fn applies(set: &Setting, pf: &PseudoForce) -> bool {
        set.n == 1
            && set.scheme == super::super::scheme::Scheme::H
            && !set.acceleration
            && set.rule.nodes.len() <= NODES
            && !pf.has_mass()
            && !pf.has_couplings()
    }

    /// Evaluates the constant or the varying nodes at the current end state.
    #[inline(always)]
    fn eval_nodes(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
        tangent: bool,
        constant: bool,
    ) -> Result<(), CoreError> {
        let (dt, q0, v0) = (set.dt, inp.q0[0], inp.v0[0]);
        for i in 0..self.nodes {
            if self.constant[i] != constant {
                continue;
            }
            let s = self.s[i];
            let (q, v) = set.scheme.state(s, dt, q0, v0, self.q1, self.v1);
            let [value, kq, cq] = force(space, (q, v, inp.t + s * dt), tangent)?;
            self.values[i] = value;
            if tangent {
                (self.kq[i], self.cq[i]) = (kq, cq);
            }
        }
        Ok(())
    }

    /// The residuals `z - z_lin - sum_i W_i Q_i` and their max norm (NaN kept).
    #[inline(always)]
    fn residual(&self, inp: &StepInput) -> ([f64; 2], f64) {
        let (mut rq, mut rv) = (self.q1 - inp.q_lin[0], self.v1 - inp.v_lin[0]);
        for i in 0..self.nodes {
            rq -= self.wx[i] * self.values[i];
            rv -= self.wv[i] * self.values[i];
        }
        let norm = if rq.is_nan() || rv.is_nan() {
            f64::NAN
        } else {
            rq.abs().max(rv.abs())
        };
        ([rq, rv], norm)
    }

    /// Solves the step into `(q_out, v_out)`; the start state's pseudo-force into `start`.
    /// Returns the iterations.
    pub fn solve(
        &mut self,
        set: &Setting,
        pf: &mut PseudoForce,
        inp: &StepInput,
        (q_out, v_out): (&mut [f64], &mut [f64]),
        start: &mut f64,
    ) -> Result<usize, CoreError> {
        let space = pf.space_mut();
        let (q0, v0) = (inp.q0[0], inp.v0[0]);
        (self.q1, self.v1) = (q0, v0);
        self.eval_nodes(set, space, inp, false, true)?;
        *start = if self.constant[0] {
            self.values[0]
        } else {
            force(space, (q0, v0, inp.t), false)?[0]
        };
        self.q1 = inp.q_lin[0] + self.wx_sum * *start;
        self.v1 = inp.v_lin[0] + self.wv_sum * *start;
        let iterations = self.newton(set, space, inp)?;
        // the node values, tangents and trial variables at the converged state
        self.eval_nodes(set, space, inp, self.at_end, false)?;
        if self.at_end {
            space.mark_end();
        }
        (q_out[0], v_out[0]) = (self.q1, self.v1);
        Ok(iterations)
    }

    /// Newton's method on `(q1, v1)`, damped as the modal one.
    fn newton(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
    ) -> Result<usize, CoreError> {
        let scale0 = [inp.q0[0], inp.v0[0], inp.q_lin[0], inp.v_lin[0]]
            .iter()
            .fold(0.0_f64, |a, b| a.max(b.abs()));
        let (mut z0, mut delta) = ([0.0; 2], [0.0; 2]);
        let mut norm = f64::INFINITY;
        let mut last: Option<f64> = None;
        for iter in 1..=set.max_iter {
            self.eval_nodes(set, space, inp, true, false)?;
            let (mut res, n) = self.residual(inp);
            norm = n;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    (self.q1, self.v1) = (z0[0] + lambda * delta[0], z0[1] + lambda * delta[1]);
                    self.eval_nodes(set, space, inp, true, false)?;
                    let (r, n) = self.residual(inp);
                    res = r;
                    Ok(n)
                })?;
            }
            // Newton's matrix I - sum_i W_i dQ_i/dz, z = (q1, v1)
            let mut m = [[1.0, 0.0], [0.0, 1.0]];
            for i in 0..self.nodes {
                if self.constant[i] {
                    continue;
                }
                let [dqq, dqv, dvq, dvv] = self.d[i];
                let (a, b) = (
                    self.kq[i] * dqq + self.cq[i] * dvq,
                    self.kq[i] * dqv + self.cq[i] * dvv,
                );
                m[0][0] -= self.wx[i] * a;
                m[0][1] -= self.wx[i] * b;
                m[1][0] -= self.wv[i] * a;
                m[1][1] -= self.wv[i] * b;
            }
            let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
            if !(det.is_finite() && det != 0.0) {
                break;
            }
            delta = [
                -(m[1][1] * res[0] - m[0][1] * res[1]) / det,
                -(m[0][0] * res[1] - m[1][0] * res[0]) / det,
            ];
            if !(delta[0].is_finite() && delta[1].is_finite()) {
                break;
            }
            z0 = [self.q1, self.v1];
            (self.q1, self.v1) = (z0[0] + delta[0], z0[1] + delta[1]);
            let size = delta[0].abs().max(delta[1].abs());
            let zmax = self.q1.abs().max(self.v1.abs());
            if set.linear || size <= set.tol * zmax.max(scale0) || size == 0.0 {
                return Ok(iter);
            }
            last = Some(norm);
        }
        Err(set.no_convergence(inp, norm))
    }
}
