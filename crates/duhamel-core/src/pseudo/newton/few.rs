//! The modal Newton of a few modes on fixed-size arrays: a bidirectional bearing under a
//! rigid mass (two modes, three with its vertical dof), a two-dof device.
//!
//! The same iteration as [`super::modal::Modal::solve`] for `n = N` modes (no mass law, no
//! couplings: the pseudo-force is the elements' alone, `Q = -Phi^T r`), operation for
//! operation, so its results are the modal Newton's bit for bit: the predictor from the
//! start state's force, Newton's steps damped by [`backtrack`], the `N x N` system by the
//! same elimination ([`eliminate_fixed`], `dense::eliminate` unrolled), the node values at the converged state, the
//! explicit half (the last with the tangents the stiffness watch then reuses, as
//! [`super::one`] does). What it leaves out is the generic machinery around `N` numbers: the
//! `Vec` per node and per tangent, the pseudo-force's zeroed buffers and negated copies,
//! the loops over a run-time `n`. Nothing is allocated per step; the elements are called
//! through their [`Evaluation`](crate::elements::Evaluation) (built-in ones directly). It
//! runs where the element space is not smaller than the modes (the modal Newton's case).

use super::super::force::PseudoForce;
use super::super::local::ElementSpace;
use super::super::scheme::{StepInput, Unknown};
use super::damping::backtrack;
use super::setting::Setting;
use crate::dense_fixed::eliminate_fixed;
use crate::error::CoreError;

/// The most nodes a quadrature has (the exact cubic rule's four).
const NODES: usize = 4;

/// A pseudo-force value at a node: `Q` and its tangents `dQ/dq`, `dQ/dv` (row-major).
#[derive(Clone, Copy)]
struct Value<const N: usize> {
    q: [f64; N],
    kq: [[f64; N]; N],
    cq: [[f64; N]; N],
}

impl<const N: usize> Value<N> {
    const ZERO: Self = Value {
        q: [0.0; N],
        kq: [[0.0; N]; N],
        cq: [[0.0; N]; N],
    };
}

/// `rho = Phi^T r` and its tangents `Phi^T (dr/dx) Phi`, `Phi^T (dr/dv) Phi` at the modal
/// state `(q, v, t)` into `out` (negated: `Q = -rho`), with [`PseudoForce::eval`]'s
/// arithmetic for `N` modes without mass law or couplings (the sums in its order, from its
/// zeros; the tangents only when `tangent`, left as they were otherwise).
#[inline(always)]
fn force<const N: usize>(
    space: &mut ElementSpace,
    (q, v, t): (&[f64; N], &[f64; N], f64),
    tangent: bool,
    out: &mut Value<N>,
) -> Result<(), CoreError> {
    let (phi, members) = space.members_mut();
    let row = |a: usize| -> &[f64] { &phi[a * N..(a + 1) * N] };
    let mut rho = [0.0; N];
    let mut kq = [[0.0; N]; N];
    let mut cq = [[0.0; N]; N];
    for (e, at) in members {
        for (j, &a) in at.iter().enumerate() {
            e.x[j] = row(a).iter().zip(q).map(|(p, x)| p * x).sum();
            e.v[j] = row(a).iter().zip(v).map(|(p, x)| p * x).sum();
        }
        e.evaluate(t, tangent)?;
        // the projection `rho += Phi_e^T r`
        for (j, &a) in at.iter().enumerate() {
            for (o, p) in rho.iter_mut().zip(row(a)) {
                *o += p * e.r[j];
            }
        }
        if tangent {
            // the congruences `Phi_e^T T Phi_e`
            let nl = at.len();
            for (t_loc, acc) in [(&e.kx, &mut kq), (&e.cv, &mut cq)] {
                for a in 0..nl {
                    for b in 0..nl {
                        let tab = t_loc[a * nl + b];
                        if tab == 0.0 {
                            continue;
                        }
                        let (ra, rb) = (row(at[a]), row(at[b]));
                        for (i, &pa) in ra.iter().enumerate() {
                            let f = pa * tab;
                            for (o, &pb) in acc[i].iter_mut().zip(rb) {
                                *o += f * pb;
                            }
                        }
                    }
                }
            }
        }
    }
    for (o, r) in out.q.iter_mut().zip(&rho) {
        *o = -r;
    }
    if tangent {
        // by index: the flattened iterators' loop was 7 % of a bidirectional bearing's step
        for i in 0..N {
            for j in 0..N {
                out.kq[i][j] = -kq[i][j];
                out.cq[i][j] = -cq[i][j];
            }
        }
    }
    Ok(())
}

/// The `N`-mode step's rule (fixed for the run) and its node values.
pub(super) struct Few<const N: usize> {
    nodes: usize,
    s: [f64; NODES],
    d: [[f64; 4]; NODES],
    wx: [[f64; N]; NODES],
    wv: [[f64; N]; NODES],
    constant: [bool; NODES],
    /// The last node whose state varies, when it is the end state (its final evaluation
    /// then computes the tangents the stiffness watch reuses; `N^2` numbers per element,
    /// against an evaluation saved).
    at_end: bool,
    /// The weights summed over the nodes, per mode (the predictor's).
    wx_sum: [f64; N],
    wv_sum: [f64; N],
    /// Per node: `Q` and its tangents (zero at the constant nodes, as the modal Newton's).
    values: [Value<N>; NODES],
    /// The end state.
    q1: [f64; N],
    v1: [f64; N],
    /// Newton's residual, matrix (row-major) and step.
    res: [f64; N],
    mat: [[f64; N]; N],
    z0: [f64; N],
    delta: [f64; N],
}

impl<const N: usize> Few<N> {
    /// The step of `set` (`N` modes, at most [`NODES`] nodes, unknown `q1` or `v1`).
    pub fn new(set: &Setting) -> Self {
        let rule = set.rule;
        let nodes = rule.nodes.len();
        let mut few = Few {
            nodes,
            s: [0.0; NODES],
            d: [[0.0; 4]; NODES],
            wx: [[0.0; N]; NODES],
            wv: [[0.0; N]; NODES],
            constant: [true; NODES],
            at_end: false,
            wx_sum: [0.0; N],
            wv_sum: [0.0; N],
            values: [Value::ZERO; NODES],
            q1: [0.0; N],
            v1: [0.0; N],
            res: [0.0; N],
            mat: [[0.0; N]; N],
            z0: [0.0; N],
            delta: [0.0; N],
        };
        for m in 0..N {
            few.wx_sum[m] = rule.wx.iter().map(|w| w[m]).sum();
            few.wv_sum[m] = rule.wv.iter().map(|w| w[m]).sum();
        }
        for (i, node) in rule.nodes.iter().enumerate() {
            few.s[i] = node.s;
            few.d[i] = node.d;
            few.wx[i].copy_from_slice(&rule.wx[i][..N]);
            few.wv[i].copy_from_slice(&rule.wv[i][..N]);
            few.constant[i] = set.constant[i];
        }
        let end = (0..nodes).rev().find(|&i| !set.constant[i]);
        few.at_end = end.is_some_and(|i| rule.nodes[i].s == 1.0);
        few
    }

    /// Whether it applies: `N` modes, a pseudo-force of elements only, a known unknown.
    pub fn applies(set: &Setting, pf: &PseudoForce) -> bool {
        set.n == N
            && set.unknown != Unknown::Both
            && set.rule.nodes.len() <= NODES
            && !pf.has_mass()
            && !pf.has_couplings()
    }

    /// Evaluates the selected nodes (`constant` or varying) at the current end state.
    #[inline(always)]
    fn eval_nodes(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
        tangent: bool,
        constant: bool,
    ) -> Result<(), CoreError> {
        let dt = set.dt;
        let (mut qn, mut vn) = ([0.0; N], [0.0; N]);
        for i in 0..self.nodes {
            if self.constant[i] != constant {
                continue;
            }
            let s = self.s[i];
            for m in 0..N {
                (qn[m], vn[m]) = set
                    .scheme
                    .state(s, dt, inp.q0[m], inp.v0[m], self.q1[m], self.v1[m]);
            }
            force(
                space,
                (&qn, &vn, inp.t + s * dt),
                tangent,
                &mut self.values[i],
            )?;
        }
        Ok(())
    }

    /// `row` 0: `q_lin + sum wx Q`; row 1: `v_lin + sum wv Q`, for mode `m`.
    #[inline(always)]
    fn explicit(&self, inp: &StepInput, row: usize, m: usize) -> f64 {
        let (base, w) = if row == 0 {
            (inp.q_lin, &self.wx)
        } else {
            (inp.v_lin, &self.wv)
        };
        base[m]
            + (0..self.nodes)
                .map(|i| w[i][m] * self.values[i].q[m])
                .sum::<f64>()
    }

    /// The residual of the unknowns into `res`; returns its max norm (NaN kept).
    #[inline(always)]
    fn residual(&mut self, set: &Setting, inp: &StepInput) -> f64 {
        let mut norm = 0.0_f64;
        let row = if set.unknown == Unknown::V1 { 1 } else { 0 };
        for m in 0..N {
            let z = if row == 0 { self.q1[m] } else { self.v1[m] };
            let r = z - self.explicit(inp, row, m);
            self.res[m] = r;
            if r.is_nan() || r.abs() > norm {
                norm = r.abs();
            }
        }
        norm
    }

    /// Newton's matrix `I - sum_i W_i dQ_i/du`.
    #[inline(always)]
    fn jacobian(&mut self, set: &Setting) {
        let dt = set.dt;
        for (i, row) in self.mat.iter_mut().enumerate() {
            *row = [0.0; N];
            row[i] = 1.0;
        }
        for i in 0..self.nodes {
            let [dqq, dqv, dvq, dvv] = self.d[i];
            let Value { kq, cq, .. } = &self.values[i];
            let da = 0.0;
            for r in 0..N {
                for c in 0..N {
                    if set.unknown == Unknown::V1 {
                        let d =
                            kq[r][c] * dqv + cq[r][c] * dvv + if r == c { da / dt } else { 0.0 };
                        self.mat[r][c] -= self.wv[i][r] * d;
                    } else {
                        let d = kq[r][c] * dqq + cq[r][c] * dvq;
                        self.mat[r][c] -= self.wx[i][r] * d;
                    }
                }
            }
        }
    }

    /// Sets the unknowns to `z0 + lambda delta`.
    #[inline(always)]
    fn set_z(&mut self, set: &Setting, lambda: f64) {
        for m in 0..N {
            let u = self.z0[m] + lambda * self.delta[m];
            if set.unknown == Unknown::V1 {
                self.v1[m] = u;
            } else {
                self.q1[m] = u;
            }
        }
    }

    /// Solves the step into `(q_out, v_out)`; the start state's pseudo-force into `start`
    /// (returned: whether the first node is the start state). Returns the iterations.
    pub fn solve(
        &mut self,
        set: &Setting,
        pf: &mut PseudoForce,
        inp: &StepInput,
        (q_out, v_out): (&mut [f64], &mut [f64]),
        start: &mut [f64],
    ) -> Result<usize, CoreError> {
        self.q1.copy_from_slice(&inp.q0[..N]);
        self.v1.copy_from_slice(&inp.v0[..N]);
        self.eval_nodes(set, pf.space_mut(), inp, false, true)?;
        if self.constant[0] {
            start.copy_from_slice(&self.values[0].q);
        } else {
            // the start state from the right, as the modal Newton asks for it (no mass law
            // here to take a side: kept for the same state of `pf`)
            pf.set_left_limit(false);
            let mut at_start = Value::ZERO;
            let (q0, v0) = (self.q1, self.v1);
            force(pf.space_mut(), (&q0, &v0, inp.t), false, &mut at_start)?;
            start.copy_from_slice(&at_start.q);
        }
        let space = pf.space_mut();
        for (m, &s) in start.iter().enumerate() {
            self.q1[m] = inp.q_lin[m] + self.wx_sum[m] * s;
            self.v1[m] = inp.v_lin[m] + self.wv_sum[m] * s;
        }
        let iterations = self.newton(set, space, inp)?;
        self.eval_nodes(set, space, inp, self.at_end, false)?;
        if self.at_end {
            space.mark_end();
        }
        for m in 0..N {
            match set.unknown {
                Unknown::V1 => self.q1[m] = self.explicit(inp, 0, m),
                _ => self.v1[m] = self.explicit(inp, 1, m),
            }
        }
        q_out.copy_from_slice(&self.q1);
        v_out.copy_from_slice(&self.v1);
        Ok(iterations)
    }

    /// Newton's method on the unknowns, damped as the modal one.
    fn newton(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
    ) -> Result<usize, CoreError> {
        let scale0 = inp
            .q0
            .iter()
            .chain(inp.v0)
            .chain(inp.q_lin)
            .chain(inp.v_lin)
            .fold(0.0_f64, |a, b| a.max(b.abs()));
        let mut norm = f64::INFINITY;
        let mut last: Option<f64> = None;
        for iter in 1..=set.max_iter {
            self.eval_nodes(set, space, inp, true, false)?;
            norm = self.residual(set, inp);
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    self.set_z(set, lambda);
                    self.eval_nodes(set, space, inp, true, false)?;
                    Ok(self.residual(set, inp))
                })?;
            }
            self.jacobian(set);
            for (d, r) in self.delta.iter_mut().zip(&self.res) {
                *d = -r;
            }
            if !eliminate_fixed(&mut self.mat, &mut self.delta) {
                break;
            }
            self.z0 = if set.unknown == Unknown::V1 {
                self.v1
            } else {
                self.q1
            };
            self.set_z(set, 1.0);
            let size = self.delta.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
            let zmax = self
                .z0
                .iter()
                .zip(&self.delta)
                .fold(0.0_f64, |a, (z, d)| a.max((z + d).abs()));
            // An affine residual with its exact Jacobian is solved by this one step.
            if set.linear || size <= set.tol * zmax.max(scale0) || size == 0.0 {
                return Ok(iter);
            }
            last = Some(norm);
        }
        Err(set.no_convergence(inp, norm))
    }
}
