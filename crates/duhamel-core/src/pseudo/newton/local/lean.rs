//! The element-space step of one element on one dof without affine terms (no mass law, no
//! couplings: `A = I`, `P = Phi_D`): a storey chain with one device, a frame with one
//! isolator. [`LocalNewton::step`] written on scalars for that case, operation for
//! operation: `y0 = phi . z_lin`, the constant nodes' forces, Newton on the one element
//! coordinate with the influences `g_i = w_i . phi^2` fixed for the run, then one pass over
//! the modes for the end state (`z = z_lin - sum_i w_i phi r_i`, the other half and the
//! start's pseudo-force together). What it leaves out is the general step's bookkeeping: a
//! `Vec` per node for every scalar, a copy of `z_lin` and of the other half, one pass over
//! the modes per node.

use super::super::super::force::PseudoForce;
use super::super::super::local::ElementSpace;
use super::super::super::scheme::StepInput;
use super::super::damping::{backtrack, below_rounding, scalar_correction};
use super::{End, LocalNewton, NodeMap, Setting};
use crate::error::CoreError;

/// The most nodes a quadrature has (the exact cubic rule's four).
const NODES: usize = 4;

/// The per-node scalars of one step.
struct Nodes {
    len: usize,
    /// The nodes' maps and influences `g_i` (copied from the step's `Vec`s once per step:
    /// the iterations read them from here without the indirections).
    map: [NodeMap; NODES],
    g: [f64; NODES],
    /// `U_i`, `V_i`: the node's element state at `y = 0`.
    u0: [f64; NODES],
    ud0: [f64; NODES],
    /// The node's force and tangents.
    r: [f64; NODES],
    kt: [f64; NODES],
    ct: [f64; NODES],
}

impl LocalNewton {
    /// Whether [`LocalNewton::step_lean`] applies: one element on one dof, nothing affine
    /// besides it, at most [`NODES`] nodes.
    pub(super) fn lean_applies(&self, space: &ElementSpace) -> bool {
        !self.affine && self.nd == 1 && space.single() && self.map.len() <= NODES
    }

    /// `F(y)` at `y` (the varying nodes evaluated) and its absolute value (NaN kept), as
    /// [`LocalNewton::residual_one`] forms it.
    #[inline(always)]
    fn lean_residual(
        &self,
        nodes: &mut Nodes,
        space: &mut ElementSpace,
        (set, inp): (&Setting, &StepInput),
        (y, y0): (f64, f64),
        tangent: bool,
    ) -> Result<(f64, f64), CoreError> {
        let mut res = y;
        res -= y0;
        for i in 0..nodes.len {
            let m = nodes.map[i];
            if m.constant {
                continue;
            }
            let u = nodes.u0[i] + m.alpha * y;
            let ud = nodes.ud0[i] + m.beta * y;
            let t = inp.t + m.s * set.dt;
            let (r, k, c) = space.eval_one(u, ud, t, tangent)?;
            nodes.r[i] = r;
            if tangent {
                (nodes.kt[i], nodes.ct[i]) = (k, c);
            }
            // `dot` of one term: its zero partial sums, then the term
            res += 0.0 + nodes.g[i] * r;
        }
        let norm = if res.is_nan() || res.abs() > 0.0 {
            res.abs()
        } else {
            0.0
        };
        Ok((res, norm))
    }

    /// [`LocalNewton::step`] where [`LocalNewton::lean_applies`].
    pub(super) fn step_lean(
        &mut self,
        pf: &mut PseudoForce,
        set: &Setting,
        inp: &StepInput,
        (z_lin, w_lin): (&[f64], &[f64]),
        end: End,
    ) -> Result<usize, CoreError> {
        let End { z, w, start } = end;
        let n = self.n;
        self.start_ready = false;
        if !self.ready {
            self.kept.valid = false;
            self.assemble(pf, set);
            self.prepare(pf.space())?;
        }
        let space = pf.space_mut();
        space.drop_start();
        let (pq, pv, mut y0) = crate::dense::dot3(space.phi(), [inp.q0, inp.v0, z_lin]);
        (self.pq[0], self.pv[0], self.y0[0]) = (pq, pv, y0);
        let len = self.map.len();
        let mut nodes = Nodes {
            len,
            map: std::array::from_fn(|i| self.map[i.min(len - 1)]),
            g: std::array::from_fn(|i| if i < len { self.g[i][0] } else { 0.0 }),
            u0: [0.0; NODES],
            ud0: [0.0; NODES],
            r: [0.0; NODES],
            kt: [0.0; NODES],
            ct: [0.0; NODES],
        };
        for (i, m) in self.map.iter().enumerate() {
            nodes.u0[i] = m.cq.0 * pq + m.cq.1 * pv;
            nodes.ud0[i] = m.cv.0 * pq + m.cv.1 * pv;
        }
        // the constant nodes' forces, evaluated once
        for i in 0..nodes.len {
            let m = nodes.map[i];
            if m.constant {
                let t = inp.t + m.s * set.dt;
                let start = m.s == 0.0 && nodes.u0[i].to_bits() == pq.to_bits();
                let (r, _, _) = space.eval_one(nodes.u0[i], nodes.ud0[i], t, false)?;
                nodes.r[i] = r;
                // the start state itself (its displacement bit for bit): kept for its record
                if start {
                    let differs = nodes.ud0[i].to_bits() != pv.to_bits();
                    space.keep_start((inp.q0, inp.v0), t, (&[pq], &self.pv), differs);
                }
                y0 -= 0.0 + nodes.g[i] * r;
            }
        }
        // the initial guess: the start state's force held over the step
        let first = self.map[0];
        let r_start = if !(first.constant && first.s == 0.0) {
            let (r, _, _) = space.eval_one(pq, pv, inp.t, false)?;
            space.keep_start((inp.q0, inp.v0), inp.t, (&self.pq, &self.pv), false);
            r
        } else {
            nodes.r[0]
        };
        self.r_start[0] = r_start;
        self.start_ready = true;
        let mut y = y0;
        for i in 0..nodes.len {
            if !nodes.map[i].constant {
                y -= 0.0 + nodes.g[i] * r_start;
            }
        }
        let mut scale0 = 0.0_f64.max(y0.abs());
        for i in 0..nodes.len {
            scale0 = scale0.max(nodes.u0[i].abs());
        }
        let scale0 = scale0.max(space.resolution() / set.tol);
        let iterations = self.lean_newton(&mut nodes, space, (set, inp), (&mut y, y0), scale0)?;
        // the end state in one pass over the modes: per node `t_i = phi r_i`,
        // `z -= s_i w_i t_i`, `Q_i = -s_i t_i`, `w += w'_i Q_i` (the general finish's order)
        let (_, wo) = Self::weights(set);
        let phi = &space.phi()[..n];
        let count = nodes.len;
        let out = (z, w, start);
        let (lin, (r, s)) = ((z_lin, w_lin), (&nodes.r, &self.s[..]));
        match count {
            1 => finish::<1>(phi, lin, (&self.w_hat, wo), (r, s), out),
            2 => finish::<2>(phi, lin, (&self.w_hat, wo), (r, s), out),
            3 => finish::<3>(phi, lin, (&self.w_hat, wo), (r, s), out),
            _ => finish::<4>(phi, lin, (&self.w_hat, wo), (r, s), out),
        }
        for i in 0..count {
            self.r[i][0] = nodes.r[i];
        }
        Ok(iterations)
    }

    /// [`LocalNewton::newton_one`] on the step's scalars.
    fn lean_newton(
        &self,
        nodes: &mut Nodes,
        space: &mut ElementSpace,
        (set, inp): (&Setting, &StepInput),
        (y, y0): (&mut f64, f64),
        scale0: f64,
    ) -> Result<usize, CoreError> {
        let at_end = self.ends_at_end();
        let mut last: Option<f64> = None;
        let mut last_size: Option<f64> = None;
        let mut norm = f64::INFINITY;
        let (mut y_prev, mut delta) = (*y, 0.0);
        for iter in 1..=set.max_iter {
            let (mut res, n) = self.lean_residual(nodes, space, (set, inp), (*y, y0), true)?;
            norm = n;
            let mut cut = false;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    cut = true;
                    *y = y_prev + lambda * delta;
                    let (r, n) = self.lean_residual(nodes, space, (set, inp), (*y, y0), true)?;
                    res = r;
                    Ok(n)
                })?;
            }
            // J = 1 + sum_i g_i (alpha_i k_i + beta_i c_i) over the varying nodes
            let mut mat = 1.0;
            for i in 0..nodes.len {
                let (m, g) = (nodes.map[i], nodes.g[i]);
                if m.constant || g == 0.0 {
                    continue;
                }
                mat += g * (m.alpha * nodes.kt[i] + m.beta * nodes.ct[i]);
            }
            let Some(correction) = scalar_correction(res, mat) else {
                break;
            };
            delta = correction;
            if below_rounding(delta.abs(), y.abs().max(scale0)) {
                if at_end {
                    space.mark_end();
                    if self.end_is_unknown {
                        space.mark_end_trial();
                    }
                }
                return Ok(iter);
            }
            y_prev = *y;
            *y += delta;
            let size = 0.0_f64.max(delta.abs());
            let scale = 0.0_f64.max(y.abs()).max(scale0);
            if set.settled(last_size, size, scale, cut) {
                self.lean_residual(nodes, space, (set, inp), (*y, y0), at_end)?;
                if at_end {
                    space.mark_end();
                    if self.end_is_unknown {
                        space.mark_end_trial();
                    }
                }
                return Ok(iter);
            }
            last = Some(norm);
            last_size = Some(size);
        }
        Err(set.no_convergence(inp, norm))
    }
}

/// The lean step's end state from the `N` nodes' forces `r` (see
/// [`LocalNewton::step_lean`]), the same operations in the same order as the general
/// finish: `z = z_lin - sum_i s_i W_i phi r_i`, `w = w_lin + sum_i W'_i Q_i` with
/// `Q_i = -s_i phi r_i`, and `Q_0` into `start`.
#[inline(always)]
fn finish<const N: usize>(
    phi: &[f64],
    (z_lin, w_lin): (&[f64], &[f64]),
    (w_hat, w_other): (&[Vec<f64>], &[Vec<f64>]),
    (r, s): (&[f64; NODES], &[f64]),
    (z, w, start): (&mut [f64], &mut [f64], Option<&mut [f64]>),
) {
    let n = phi.len();
    let (z, w) = (&mut z[..n], &mut w[..n]);
    // node by node over all the modes (each mode's sums in node order, as one pass per
    // mode takes them: the same numbers), each pass a vector loop: the end state written
    // in vectors, not mode by mode in scalars, which the next step's vector loads of it
    // (the linear step, the guard) stalled on (store forwarding)
    z.copy_from_slice(&z_lin[..n]);
    w.copy_from_slice(&w_lin[..n]);
    for i in 0..N {
        let (wh, wo, neg) = (&w_hat[i][..n], &w_other[i][..n], -s[i]);
        // `project` of one dof: `0 + r phi`, or 0 for a zero force
        let ri = r[i];
        if ri != 0.0 {
            for m in 0..n {
                let ti = 0.0 + ri * phi[m];
                z[m] -= wh[m] * ti;
                w[m] += wo[m] * (ti * neg);
            }
        } else {
            for m in 0..n {
                z[m] -= wh[m] * 0.0;
                w[m] += wo[m] * (0.0 * neg);
            }
        }
    }
    if let Some(start) = start {
        let (r0, neg) = (r[0], -s[0]);
        for (o, &p) in start[..n].iter_mut().zip(phi) {
            *o = if r0 != 0.0 { 0.0 + r0 * p } else { 0.0 } * neg;
        }
    }
}
