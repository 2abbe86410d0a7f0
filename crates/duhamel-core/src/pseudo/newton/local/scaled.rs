//! The element-space step's matrix under a scalar mass law `M(t) = mu(t) M0` with constant
//! couplings.
//!
//! Along the eliminated law the couplings at node `i` enter divided by the mass,
//! `s_i = 1/mu(t_i)`, so `A = I + sum_i W_i (diag(d_i) + s_i M_i)` changes every step
//! (parent module). Its coupling part is `sum_i s_i H_i` with `H_i = diag(W_i) M_i`
//! (`M_i = alpha_i K + beta_i C`) fixed for the run: formed once here, each step then costs
//! one pass of `n_nodes` scaled additions instead of reading both couplings per node. The
//! factors `P^T = A^-T Phi_D^T` then give every `G_i` in one pass over the modes with
//! `[f64; n_d]` updates (a few element dofs), instead of `n_d^2` dot products per node.
//!
//! A factorisation per step remains: the nodes' `s_i` differ (the law at the start and the
//! end of the step) and multiply different dense matrices (`H_i`), so `A` is a
//! two-parameter family for the trapezoid rule, not a scalar shift of a fixed matrix; only
//! without couplings is it diagonal (no factorisation at all, as before).

use super::super::super::local::ElementSpace;
use super::{LocalNewton, Setting};
use crate::dense::DenseLu;
use crate::error::CoreError;

impl LocalNewton {
    /// Whether [`LocalNewton::assemble_scaled`] applies: a mass law, couplings, and the
    /// same couplings at every node and step.
    pub(super) fn scaled_applies(&self, mass: bool) -> bool {
        mass && !self.a.is_empty() && self.kc.len() == 1
    }

    /// `A = I + sum_i W_i (diag(d_i) + s_i M_i)` as [`LocalNewton::assemble`] forms it,
    /// from the `H_i` formed on the first call: its diagonal part in `diag`, the couplings'
    /// part in `a`; and `s_i W_i`.
    pub(super) fn assemble_scaled(&mut self, set: &Setting) {
        let n = self.n;
        let (w, _) = Self::weights(set);
        if self.h.is_empty() {
            let (kc, cc) = (&self.kc[0], &self.cc[0]);
            for (i, node) in self.map.iter().enumerate() {
                if node.alpha == 0.0 && node.beta == 0.0 {
                    continue;
                }
                let mut h = vec![0.0; n * n];
                for (r, row) in h.chunks_exact_mut(n).enumerate() {
                    let (kr, cr) = (&kc[r * n..(r + 1) * n], &cc[r * n..(r + 1) * n]);
                    for ((x, kv), cv) in row.iter_mut().zip(kr).zip(cr) {
                        *x = w[i][r] * (node.alpha * kv + node.beta * cv);
                    }
                }
                self.h.push((i, h));
            }
        }
        self.diag.fill(1.0);
        for (((wi, &si), w_hat), d) in w.iter().zip(&self.s).zip(&mut self.w_hat).zip(&self.d) {
            for (wh, wm) in w_hat.iter_mut().zip(wi) {
                *wh = si * wm;
            }
            for ((dg, wm), dm) in self.diag.iter_mut().zip(wi).zip(d) {
                *dg += wm * dm;
            }
        }
        match self.h.as_slice() {
            [(i0, h0), (i1, h1)] => {
                let (s0, s1) = (self.s[*i0], self.s[*i1]);
                for ((x, a), b) in self.a.iter_mut().zip(h0).zip(h1) {
                    *x = s0 * a + s1 * b;
                }
            }
            parts => {
                self.a.fill(0.0);
                for (i, h) in parts {
                    let si = self.s[*i];
                    for (x, a) in self.a.iter_mut().zip(h) {
                        *x += si * a;
                    }
                }
            }
        }
    }
}

impl LocalNewton {
    /// [`LocalNewton::prepare`] after [`LocalNewton::assemble_scaled`]: `P = Phi_D A^{-1}`
    /// and every `G_i`, the element dofs' count fixed at compile time where it is small.
    pub(super) fn prepare_scaled(&mut self, space: &ElementSpace) -> Result<(), CoreError> {
        match self.nd {
            1 => self.prepare_fixed::<1>(space),
            2 => self.prepare_fixed::<2>(space),
            3 => self.prepare_fixed::<3>(space),
            4 => self.prepare_fixed::<4>(space),
            6 => self.prepare_fixed::<6>(space),
            8 => self.prepare_fixed::<8>(space),
            _ => self.prepare(space),
        }
    }

    fn prepare_fixed<const K: usize>(&mut self, space: &ElementSpace) -> Result<(), CoreError> {
        let n = self.n;
        for m in 0..n {
            self.a[m * n + m] += self.diag[m];
        }
        let lu = self.lu.get_or_insert_with(DenseLu::default);
        if !lu.refactor_dominant(n, &self.a) {
            return Err(CoreError::NonFinite {
                time: 0.0,
                step: 0,
                last_good_time: None,
            });
        }
        if self.phi_t.is_empty() {
            // Phi_D^T, `n x n_d` row-major: row `m` holds mode `m` at every element dof.
            self.phi_t = vec![0.0; n * K];
            for (a, row) in space.phi().chunks_exact(n).enumerate() {
                for (m, &p) in row.iter().enumerate() {
                    self.phi_t[m * K + a] = p;
                }
            }
        }
        self.pt.copy_from_slice(&self.phi_t);
        lu.solve_transpose_many(&mut self.pt, K, &mut self.pt_work);
        for (m, col) in self.pt.chunks_exact(K).enumerate() {
            for (a, &p) in col.iter().enumerate() {
                self.pmat[a * n + m] = p;
            }
        }
        // G_i[a][b] = sum_m P[a][m] w_hat_i[m] Phi_D[b][m], one mode at a time.
        for (g, wh) in self.g.iter_mut().zip(&self.w_hat) {
            let mut acc = [[0.0; K]; K];
            for ((p, f), &w) in self
                .pt
                .chunks_exact(K)
                .zip(self.phi_t.chunks_exact(K))
                .zip(wh.iter())
            {
                for (row, &pa) in acc.iter_mut().zip(p) {
                    let c = pa * w;
                    for (x, &fb) in row.iter_mut().zip(f) {
                        *x += c * fb;
                    }
                }
            }
            for (dst, row) in g.chunks_exact_mut(K).zip(&acc) {
                dst.copy_from_slice(row);
            }
        }
        self.ready = true;
        Ok(())
    }
}
