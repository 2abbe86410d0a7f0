//! The affine part of the element-space step: `Q_i^0`, `d_i`, `b`, the matrix `A` with
//! `P = Phi_D A^{-1}` and `G_i`, and the end state from the converged element forces.

use super::super::super::force::PseudoForce;
use super::super::super::local::ElementSpace;
use super::super::super::scheme::{StepInput, Unknown};
use super::{LocalNewton, Setting};
use crate::dense::{dot, DenseLu};
use crate::dense_rows::matvec;
use crate::error::CoreError;

impl LocalNewton {
    /// The node values `s_i`, `Q_i^0`, `d_i` (a mass law, couplings) and their share of `b`;
    /// the couplings at the nodes when they must be (re)read.
    pub(super) fn affine_terms(&mut self, pf: &PseudoForce, set: &Setting, inp: &StepInput) {
        let n = self.n;
        let (kk, cc) = pf.modal_kc();
        let (q0, v0) = (inp.q0, inp.v0);
        let coupled = pf.has_couplings();
        let varying = pf.varying_couplings();
        if coupled && !varying {
            if !self.ready {
                self.has_kc = pf.couplings_at(inp.t, &mut self.kc[0], &mut self.cc[0]);
            }
            // The products of the start state the nodes need.
            let any = |f: &dyn Fn(&super::NodeMap) -> f64| self.map.iter().any(|m| f(m) != 0.0);
            let wanted = [
                (self.has_kc.0 && any(&|m| m.cq.0), 0, true, q0),
                (self.has_kc.0 && any(&|m| m.cq.1), 1, true, v0),
                (self.has_kc.1 && any(&|m| m.cv.0), 2, false, q0),
                (self.has_kc.1 && any(&|m| m.cv.1), 3, false, v0),
            ];
            // The start half that the last step's `z` became (q0, or v0 for scheme a): its
            // products are the last step's `K z`, `C z` when it is that `z` bit for bit.
            let v1 = set.unknown == Unknown::V1;
            let reuse =
                !self.last_z.is_empty() && super::same(if v1 { v0 } else { q0 }, &self.last_z);
            for (on, slot, stiff, x) in wanted {
                let m = if stiff { &self.kc[0] } else { &self.cc[0] };
                if on && reuse && (slot % 2 == 1) == v1 {
                    self.prod[slot].copy_from_slice(&self.last_prod[slot / 2]);
                } else if on {
                    matvec(m, x, &mut self.prod[slot]);
                } else {
                    self.prod[slot].fill(0.0);
                }
            }
        }
        let (w, _) = Self::weights(set);
        for (i, node) in self.map.iter().enumerate() {
            let t = inp.t + node.s * set.dt;
            let [mu, g, mom, kappa] = pf.node_mass(t);
            self.s[i] = 1.0 / mu;
            let si = self.s[i];
            let qa = &mut self.q_aff[i];
            let (a, b) = (node.cq, node.cv);
            if pf.has_mass() {
                let d = &mut self.d[i];
                for m in 0..n {
                    let (qi, vi) = (a.0 * q0[m] + a.1 * v0[m], b.0 * q0[m] + b.1 * v0[m]);
                    let s = node.s;
                    let p = inp.pb[0][m] + inp.pb[1][m] * s + 4.0 * inp.pb[2][m] * s * (1.0 - s);
                    let damp = g * cc[m] + mom;
                    let stiff = g * kappa * kk[m];
                    qa[m] = g * p - damp * vi - stiff * qi;
                    d[m] = damp * node.beta + stiff * node.alpha;
                }
            } else {
                qa.fill(0.0);
            }
            if coupled {
                if varying {
                    self.has_kc = pf.couplings_at(t, &mut self.kc[i], &mut self.cc[i]);
                    // the node's start-state part of the couplings, `K_i q_i^0 + C_i v_i^0`
                    let (qi, vi) = (&mut self.t[i], &mut self.work);
                    for m in 0..n {
                        qi[m] = a.0 * q0[m] + a.1 * v0[m];
                        vi[m] = b.0 * q0[m] + b.1 * v0[m];
                    }
                    let (head, cx) = self.prod.split_at_mut(5);
                    let (kx, cx) = (&mut head[4], &mut cx[0]);
                    matvec(&self.kc[i], qi, kx);
                    matvec(&self.cc[i], vi, cx);
                    for m in 0..n {
                        qa[m] -= si * (kx[m] + cx[m]);
                    }
                } else {
                    let p = &self.prod;
                    for m in 0..n {
                        let kx = a.0 * p[0][m] + a.1 * p[1][m];
                        let cx = b.0 * p[2][m] + b.1 * p[3][m];
                        qa[m] -= si * (kx + cx);
                    }
                }
            }
            for ((bm, wm), q) in self.base.iter_mut().zip(&w[i]).zip(qa.iter()) {
                *bm += wm * q;
            }
        }
    }

    /// `A = I + sum_i W_i (diag(d_i) + s_i M_i)`: its diagonal part in `diag`, the
    /// couplings' part in `a`; and `s_i W_i`.
    pub(super) fn assemble(&mut self, pf: &PseudoForce, set: &Setting) {
        let n = self.n;
        let (w, _) = Self::weights(set);
        self.diag.fill(1.0);
        self.a.fill(0.0);
        for (i, node) in self.map.iter().enumerate() {
            let si = self.s[i];
            for (wh, wm) in self.w_hat[i].iter_mut().zip(&w[i]) {
                *wh = si * wm;
            }
            if pf.has_mass() {
                for ((dg, wm), dm) in self.diag.iter_mut().zip(&w[i]).zip(&self.d[i]) {
                    *dg += wm * dm;
                }
            }
            if self.a.is_empty() || (node.alpha == 0.0 && node.beta == 0.0) {
                continue;
            }
            let k = if self.kc.len() > 1 { i } else { 0 };
            let (kc, ccm) = (&self.kc[k], &self.cc[k]);
            for r in 0..n {
                let f = self.w_hat[i][r];
                let row = &mut self.a[r * n..(r + 1) * n];
                let (kr, cr) = (&kc[r * n..(r + 1) * n], &ccm[r * n..(r + 1) * n]);
                for ((x, kv), cv) in row.iter_mut().zip(kr).zip(cr) {
                    *x += f * (node.alpha * kv + node.beta * cv);
                }
            }
        }
    }

    /// `P = Phi_D A^{-1}` and `G_i = P diag(s_i W_i) Phi_D^T` from `A`.
    pub(super) fn prepare(&mut self, space: &ElementSpace) -> Result<(), CoreError> {
        let (n, nd) = (self.n, self.nd);
        let phi = space.phi();
        if !self.a.is_empty() {
            for m in 0..n {
                self.a[m * n + m] += self.diag[m];
            }
            let lu = self.lu.get_or_insert_with(DenseLu::default);
            if !lu.refactor(n, &self.a) {
                return Err(CoreError::NonFinite {
                    time: 0.0,
                    step: 0,
                    last_good_time: None,
                });
            }
        }
        match &self.lu {
            Some(lu) => {
                // P^T = A^-T Phi_D^T, all the element dofs at once
                let (pt, perm) = (&mut self.pt, &mut self.pt_work);
                for (a, row) in phi.chunks_exact(n).enumerate() {
                    for (m, &p) in row.iter().enumerate() {
                        pt[m * nd + a] = p;
                    }
                }
                lu.solve_transpose_many(pt, nd, perm);
                if self.a_constant {
                    // A^{-1} column by column, for every step of the run
                    self.ainv.resize(n * n, 0.0);
                    for j in 0..n {
                        self.work.fill(0.0);
                        self.work[j] = 1.0;
                        lu.solve(&mut self.work, perm);
                        for (i, x) in self.work.iter().enumerate() {
                            self.ainv[i * n + j] = *x;
                        }
                    }
                }
                for (a, prow) in self.pmat.chunks_exact_mut(n).enumerate() {
                    for (m, p) in prow.iter_mut().enumerate() {
                        *p = pt[m * nd + a];
                    }
                }
            }
            None => {
                self.unit = self.diag.iter().all(|&d| d == 1.0);
                self.pmat.copy_from_slice(phi);
                for row in self.pmat.chunks_exact_mut(n) {
                    for (p, d) in row.iter_mut().zip(&self.diag) {
                        *p /= d;
                    }
                }
            }
        }
        for (g, wh) in self.g.iter_mut().zip(&self.w_hat) {
            for (a, pa) in self.pmat.chunks_exact(n).enumerate() {
                // (P diag(w_hat))_a, then its products with the rows of Phi_D
                for ((x, p), w) in self.work.iter_mut().zip(pa).zip(wh) {
                    *x = p * w;
                }
                for (b, rb) in phi.chunks_exact(n).enumerate() {
                    g[a * nd + b] = dot(&self.work, rb);
                }
            }
        }
        self.ready = true;
        Ok(())
    }

    /// The end state from the converged forces `r_i`: `z = A^{-1} (b - sum_i s_i W_i t_i)`,
    /// every `Q_i`, `w = w_lin + sum_i W'_i Q_i`, and `Q_0` into `start`.
    pub(super) fn finish(
        &mut self,
        space: &ElementSpace,
        set: &Setting,
        z: &mut [f64],
        (w_lin, w): (&[f64], &mut [f64]),
        start: Option<&mut [f64]>,
    ) {
        let n = self.n;
        let (_, w_other) = Self::weights(set);
        z.copy_from_slice(&self.base);
        if !self.affine && self.lu.is_none() && self.unit {
            // Nothing but the elements (A = I): each node's `z -= s_i W_i t_i`,
            // `Q_i = -s_i t_i` and `w += W'_i Q_i` in one pass, the same operations in the
            // same order as below.
            w.copy_from_slice(w_lin);
            for (i, wo_i) in w_other.iter().enumerate().take(self.map.len()) {
                let si = self.s[i];
                super::project_node(&self.red, space, (i, &self.r[i]), &mut self.t[i]);
                let zw = z.iter_mut().zip(w.iter_mut());
                let weights = self.w_hat[i].iter().zip(wo_i);
                for ((q, (zm, wm)), (wh, wo)) in self.t[i].iter_mut().zip(zw).zip(weights) {
                    *zm -= wh * *q;
                    *q *= -si;
                    *wm += wo * *q;
                }
            }
            if let Some(start) = start {
                start.copy_from_slice(&self.t[0]);
            }
            return;
        }
        for i in 0..self.map.len() {
            super::project_node(&self.red, space, (i, &self.r[i]), &mut self.t[i]);
            for ((zm, wh), t) in z.iter_mut().zip(&self.w_hat[i]).zip(&self.t[i]) {
                *zm -= wh * t;
            }
        }
        match &self.lu {
            Some(_) if !self.ainv.is_empty() => {
                self.work.copy_from_slice(z);
                matvec(&self.ainv, &self.work, z);
            }
            Some(lu) => {
                lu.solve(z, &mut self.work);
            }
            // x / 1 is x (NaN, infinities and signed zeros too)
            None if self.unit => {}
            None => {
                for (zm, d) in z.iter_mut().zip(&self.diag) {
                    *zm /= d;
                }
            }
        }
        let shared = self.kc.len() == 1 && !self.kc[0].is_empty();
        if shared {
            // a coupling absent is a zero matrix: its product, zeros, without the pass
            let (kz, cz) = self.prod.split_at_mut(5);
            if self.has_kc.0 {
                matvec(&self.kc[0], z, &mut kz[4]);
            } else {
                kz[4].fill(0.0);
            }
            if self.has_kc.1 {
                matvec(&self.cc[0], z, &mut cz[0]);
            } else {
                cz[0].fill(0.0);
            }
            if self.has_kc.0 || self.has_kc.1 {
                self.last_z.clear();
                self.last_z.extend_from_slice(z);
                self.last_prod[0].clone_from(&kz[4]);
                self.last_prod[1].clone_from(&cz[0]);
            }
        }
        w.copy_from_slice(w_lin);
        for (i, node) in self.map.iter().enumerate() {
            let si = self.s[i];
            // Q_i into t_i
            let q = &mut self.t[i];
            for qm in q.iter_mut() {
                *qm *= -si;
            }
            if self.affine {
                for (qm, a) in q.iter_mut().zip(&self.q_aff[i]) {
                    *qm += a;
                }
            }
            if !self.d[i].is_empty() {
                for ((qm, d), zm) in q.iter_mut().zip(&self.d[i]).zip(z.iter()) {
                    *qm -= d * zm;
                }
            }
            if !self.kc[0].is_empty() && (node.alpha != 0.0 || node.beta != 0.0) {
                if !shared {
                    let (kz, cz) = self.prod.split_at_mut(5);
                    matvec(&self.kc[i], z, &mut kz[4]);
                    matvec(&self.cc[i], z, &mut cz[0]);
                }
                let (kz, cz) = (&self.prod[4], &self.prod[5]);
                for m in 0..n {
                    q[m] -= si * (node.alpha * kz[m] + node.beta * cz[m]);
                }
            }
            for ((wm, wo), qm) in w.iter_mut().zip(&w_other[i]).zip(q.iter()) {
                *wm += wo * qm;
            }
        }
        if let Some(start) = start {
            start.copy_from_slice(&self.t[0]);
        }
    }

    /// The pseudo-force at the start state `(q0, v0)` of the last step (with its modal load
    /// `p0` at `t`), as [`PseudoForce::at_state`] gives it, from the start state's element
    /// force kept by the step: `false` (nothing written) where that needs the couplings at a
    /// time the step did not read them.
    pub(in super::super) fn start_value(
        &mut self,
        pf: &PseudoForce,
        (q0, v0, p0): (&[f64], &[f64], &[f64]),
        t: f64,
        out: &mut [f64],
    ) -> bool {
        let n = self.n;
        if !self.start_ready {
            return false;
        }
        let coupled = !self.kc[0].is_empty();
        let k = if self.kc.len() > 1 {
            match self.map.iter().position(|m| m.s == 0.0) {
                Some(i) => i,
                None => return false,
            }
        } else {
            0
        };
        let [mu, g, mom, kappa] = pf.node_mass(t);
        let si = 1.0 / mu;
        pf.space().project(&self.r_start, out);
        if coupled {
            let (head, tail) = self.prod.split_at_mut(5);
            let (kq, cv) = (&mut head[4], &mut tail[0]);
            if self.has_kc.0 {
                matvec(&self.kc[k], q0, kq);
            } else {
                kq.fill(0.0);
            }
            if self.has_kc.1 {
                matvec(&self.cc[k], v0, cv);
            } else {
                cv.fill(0.0);
            }
            for ((o, a), b) in out.iter_mut().zip(kq.iter()).zip(cv.iter()) {
                *o += a + b;
            }
        }
        for o in out.iter_mut() {
            *o *= -si;
        }
        if pf.has_mass() {
            let (kk, cc) = pf.modal_kc();
            for m in 0..n {
                out[m] += g * (p0[m] - cc[m] * v0[m] - kappa * kk[m] * q0[m]) - mom * v0[m];
            }
        }
        true
    }
}
