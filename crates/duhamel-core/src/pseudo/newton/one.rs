//! The modal Newton of one mode on scalars: a one-dof device, a storey with one isolator.
//!
//! The same iteration as [`super::modal::Modal::solve`] for `n = 1` (no mass law, no
//! couplings: the pseudo-force is the elements' alone), operation for operation, so its
//! results are the modal Newton's bit for bit: the predictor from the start state's force,
//! Newton's steps damped by [`backtrack`], the node values at the converged state, the
//! explicit half. What it leaves out is the generic machinery around one number: the
//! `Vec` per node and per tangent, the modal projection and congruence loops over `n`, the
//! elimination of a `1 x 1` system. Nothing is allocated per step; the elements are called
//! through their [`Evaluation`](crate::elements::Evaluation) (built-in ones directly).

use super::super::force::PseudoForce;
use super::super::local::ElementSpace;
use super::super::scheme::{StepInput, Unknown};
use super::damping::{backtrack, scalar_correction};
use super::setting::Setting;
use crate::error::CoreError;

/// The most nodes a quadrature has (the exact cubic rule's four).
const NODES: usize = 4;

/// The pseudo-force `Q = -phi^T r` of one mode at `(q, v, t)`, with its tangents
/// `dQ/dq`, `dQ/dv` when `tangent`: [`PseudoForce::eval`]'s arithmetic for `n = 1` without
/// mass law or couplings (the sums in its order, from its zero).
#[inline(always)]
pub(super) fn force(
    space: &mut ElementSpace,
    (q, v, t): (f64, f64, f64),
    tangent: bool,
) -> Result<[f64; 3], CoreError> {
    if space.single() {
        // one element on the one dof (a one-dof device): the loops below on its scalars
        let (phi, e) = space.single_member();
        e.x[0] = std::iter::once(phi * q).sum();
        e.v[0] = std::iter::once(phi * v).sum();
        e.evaluate(t, tangent)?;
        let rho = 0.0 + phi * e.r[0];
        let (mut kq, mut cq) = (0.0, 0.0);
        if tangent {
            for (tab, out) in [(e.kx[0], &mut kq), (e.cv[0], &mut cq)] {
                if tab != 0.0 {
                    *out += phi * tab * phi;
                }
            }
        }
        return Ok([-rho, -kq, -cq]);
    }
    let (phi, members) = space.members_mut();
    let (mut rho, mut kq, mut cq) = (0.0, 0.0, 0.0);
    for (e, at) in members {
        for (j, &a) in at.iter().enumerate() {
            // a one-term dot product, as `dot` and the iterator sums round it
            e.x[j] = std::iter::once(phi[a] * q).sum();
            e.v[j] = std::iter::once(phi[a] * v).sum();
        }
        e.evaluate(t, tangent)?;
        for (j, &a) in at.iter().enumerate() {
            rho += phi[a] * e.r[j];
        }
        if tangent {
            let nl = at.len();
            for (m, out) in [(&e.kx, &mut kq), (&e.cv, &mut cq)] {
                for a in 0..nl {
                    for b in 0..nl {
                        let tab = m[a * nl + b];
                        if tab != 0.0 {
                            *out += phi[at[a]] * tab * phi[at[b]];
                        }
                    }
                }
            }
        }
    }
    Ok([-rho, -kq, -cq])
}

/// The one-mode step's rule (fixed for the run) and its node values.
pub(super) struct OneMode {
    nodes: usize,
    s: [f64; NODES],
    d: [[f64; 4]; NODES],
    wx: [f64; NODES],
    wv: [f64; NODES],
    constant: [bool; NODES],
    /// The weights summed over the nodes (the predictor's).
    wx_sum: f64,
    wv_sum: f64,
    /// The last node whose state varies, when it is the end state (its final evaluation
    /// then computes the tangents the stiffness watch reuses).
    at_end: bool,
    /// Per node: `Q` and its tangents `dQ/dq`, `dQ/dv` (zero at the constant nodes).
    values: [f64; NODES],
    kq: [f64; NODES],
    cq: [f64; NODES],
    /// The end state.
    q1: f64,
    v1: f64,
    /// Whether the elements' force at a committed state is the one that committed it
    /// ([`ElementSpace::restarts_exactly`]), whether they are hysteretic and whether one
    /// reads the velocity (asked at the first step).
    restarts: Option<(bool, bool, bool)>,
    /// Whether an element reads the velocity (the third of `restarts`).
    velocity: bool,
    /// The last node whose state varies (the end node when `at_end`), and the `q` it was
    /// last evaluated at (the scheme's end state: `q0 + (q1 - q0)` is not always `q1`).
    end_node: usize,
    end_q: f64,
    /// The last step's end node: its `q` (bits), the space's
    /// [`ElementSpace::generation`] then, and its `Q`, which is the next start's when the
    /// next step starts at that `q` after (at most) the route's one commit.
    end: Option<(u64, u64, f64)>,
}

impl OneMode {
    /// The step of `set` (one mode, at most [`NODES`] nodes, unknown `q1` or `v1`).
    pub fn new(set: &Setting) -> Self {
        let rule = set.rule;
        let nodes = rule.nodes.len();
        let mut one = OneMode {
            nodes,
            s: [0.0; NODES],
            d: [[0.0; 4]; NODES],
            wx: [0.0; NODES],
            wv: [0.0; NODES],
            constant: [true; NODES],
            wx_sum: rule.wx.iter().map(|w| w[0]).sum(),
            wv_sum: rule.wv.iter().map(|w| w[0]).sum(),
            at_end: false,
            values: [0.0; NODES],
            kq: [0.0; NODES],
            cq: [0.0; NODES],
            q1: 0.0,
            v1: 0.0,
            restarts: None,
            velocity: true,
            end_node: 0,
            end_q: 0.0,
            end: None,
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
        one.end_node = end.unwrap_or(0);
        one
    }

    /// Whether it applies: one mode, a pseudo-force of elements only, a known unknown.
    pub fn applies(set: &Setting, pf: &PseudoForce) -> bool {
        set.n == 1
            && set.unknown != Unknown::Both
            && set.rule.nodes.len() <= NODES
            && !pf.has_mass()
            && !pf.has_couplings()
    }

    /// Evaluates the selected nodes (`constant` or varying) from node `from` on at the
    /// current end state.
    #[inline(always)]
    fn eval_nodes(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
        tangent: bool,
        constant: bool,
        from: usize,
    ) -> Result<(), CoreError> {
        let (dt, q0, v0) = (set.dt, inp.q0[0], inp.v0[0]);
        for i in from..self.nodes {
            if self.constant[i] != constant {
                continue;
            }
            let s = self.s[i];
            // without an element reading the velocity, the node's is not formed (a division
            // per evaluation): the elements' forces at it are those at any velocity, and
            // the pseudo-force sums them from zero (a signed zero of a force changes nothing)
            let (q, v) = if self.velocity {
                set.scheme.state(s, dt, q0, v0, self.q1, self.v1)
            } else {
                (set.scheme.state(s, dt, q0, v0, self.q1, self.v1).0, 0.0)
            };
            if i == self.end_node {
                self.end_q = q;
            }
            let [value, kq, cq] = force(space, (q, v, inp.t + s * dt), tangent)?;
            self.values[i] = value;
            if tangent {
                (self.kq[i], self.cq[i]) = (kq, cq);
            }
        }
        Ok(())
    }

    /// `base + sum_i w_i Q_i` (row 0: `q`, 1: `v`).
    #[inline(always)]
    fn explicit(&self, base: f64, row: usize) -> f64 {
        let w = if row == 0 { &self.wx } else { &self.wv };
        base + (0..self.nodes).map(|i| w[i] * self.values[i]).sum::<f64>()
    }

    /// The unknown half.
    #[inline(always)]
    fn unknown(&self, set: &Setting) -> f64 {
        if set.unknown == Unknown::V1 {
            self.v1
        } else {
            self.q1
        }
    }

    #[inline(always)]
    fn set_unknown(&mut self, set: &Setting, u: f64) {
        if set.unknown == Unknown::V1 {
            self.v1 = u;
        } else {
            self.q1 = u;
        }
    }

    /// The residual of the unknown and its absolute value (NaN kept).
    #[inline(always)]
    fn residual(&self, set: &Setting, inp: &StepInput) -> (f64, f64) {
        let r = if set.unknown == Unknown::V1 {
            self.v1 - self.explicit(inp.v_lin[0], 1)
        } else {
            self.q1 - self.explicit(inp.q_lin[0], 0)
        };
        let norm = if r.is_nan() || r.abs() > 0.0 {
            r.abs()
        } else {
            0.0
        };
        (r, norm)
    }

    /// Newton's matrix `1 - sum_i W_i dQ_i/du`.
    #[inline(always)]
    fn jacobian(&self, set: &Setting) -> f64 {
        let dt = set.dt;
        let mut mat = 1.0;
        for i in 0..self.nodes {
            let [dqq, dqv, dvq, dvv] = self.d[i];
            let (kq, cq, da) = (self.kq[i], self.cq[i], 0.0);
            if set.unknown == Unknown::V1 {
                mat -= self.wv[i] * (kq * dqv + cq * dvv + da / dt);
            } else {
                mat -= self.wx[i] * (kq * dqq + cq * dvq);
            }
        }
        mat
    }

    /// Solves the step into `(q_out, v_out)`; the start state's pseudo-force into `start`
    /// (returned: whether the first node is the start state). Returns the iterations.
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
        let (restarts, stateful, velocity) = *self.restarts.get_or_insert_with(|| {
            let velocity = space.uses_velocity();
            (space.restarts_exactly(), space.stateful(), velocity)
        });
        self.velocity = velocity;
        // The start state's Q is the last end's when the step starts where the last one
        // ended (bit for bit) and, for hysteretic elements, exactly one commit (the route's,
        // at that end) came in between; elements that restart exactly only (a `Bilinear`,
        // springs, gaps: time- and velocity-free), the start a node of the rule.
        let known = self.end.take().filter(|&(bits, generation, _)| {
            let commits = space.generation().wrapping_sub(generation);
            restarts
                && self.constant[0]
                && self.s[0] == 0.0
                && bits == q0.to_bits()
                && commits == u64::from(stateful)
        });
        let from = match known {
            Some((_, _, value)) => {
                self.values[0] = value;
                1
            }
            None => 0,
        };
        self.eval_nodes(set, space, inp, false, true, from)?;
        *start = if self.constant[0] {
            self.values[0]
        } else {
            force(space, (q0, v0, inp.t), false)?[0]
        };
        self.q1 = inp.q_lin[0] + self.wx_sum * *start;
        self.v1 = inp.v_lin[0] + self.wv_sum * *start;
        let (iterations, moved) = self.newton(set, space, inp)?;
        // Newton's last evaluation was at the state before its last update: when that
        // update left the unknown as it was (bit for bit: a predictor that was the answer,
        // as in every elastic step of a hysteretic device), the node values, tangents and
        // the elements' trial variables are those of the end state already.
        if moved {
            self.eval_nodes(set, space, inp, self.at_end, false, 0)?;
        }
        if self.at_end {
            space.mark_end();
            if restarts {
                let value = self.values[self.end_node];
                self.end = Some((self.end_q.to_bits(), space.generation(), value));
            }
        }
        match set.unknown {
            Unknown::V1 => self.q1 = self.explicit(inp.q_lin[0], 0),
            _ => self.v1 = self.explicit(inp.v_lin[0], 1),
        }
        (q_out[0], v_out[0]) = (self.q1, self.v1);
        Ok(iterations)
    }

    /// Newton's method on the unknown, damped as the modal one: the iterations, and whether
    /// the last update moved the unknown from the state last evaluated.
    fn newton(
        &mut self,
        set: &Setting,
        space: &mut ElementSpace,
        inp: &StepInput,
    ) -> Result<(usize, bool), CoreError> {
        let scale0 = [inp.q0[0], inp.v0[0], inp.q_lin[0], inp.v_lin[0]]
            .iter()
            .fold(0.0_f64, |a, b| a.max(b.abs()));
        let (mut z0, mut delta) = (0.0, 0.0);
        let mut norm = f64::INFINITY;
        let mut last: Option<f64> = None;
        for iter in 1..=set.max_iter {
            self.eval_nodes(set, space, inp, true, false, 0)?;
            let (mut res, n) = self.residual(set, inp);
            norm = n;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    self.set_unknown(set, z0 + lambda * delta);
                    self.eval_nodes(set, space, inp, true, false, 0)?;
                    let (r, n) = self.residual(set, inp);
                    res = r;
                    Ok(n)
                })?;
            }
            let mat = self.jacobian(set);
            let Some(correction) = scalar_correction(res, mat) else {
                break;
            };
            delta = correction;
            z0 = self.unknown(set);
            let z = z0 + 1.0 * delta;
            self.set_unknown(set, z);
            let size = 0.0_f64.max(delta.abs());
            let zmax = 0.0_f64.max((z0 + delta).abs());
            if set.linear || size <= set.tol * zmax.max(scale0) || size == 0.0 {
                return Ok((iter, z.to_bits() != z0.to_bits()));
            }
            last = Some(norm);
        }
        Err(set.no_convergence(inp, norm))
    }
}
