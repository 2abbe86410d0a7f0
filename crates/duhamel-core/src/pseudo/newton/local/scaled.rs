//! The element-space step's matrix under a scalar mass law `M(t) = mu(t) M0` with constant
//! couplings.
//!
//! Along the eliminated law the couplings at node `i` enter divided by the mass,
//! `s_i = 1/mu(t_i)`, so `A = I + sum_i W_i (diag(d_i) + s_i M_i)` changes every step
//! (parent module). Its coupling part is `sum_i s_i H_i` with `H_i = diag(W_i) M_i`
//! (`M_i = alpha_i K + beta_i C`) fixed for the run: formed once here, each step then costs
//! one pass of `n_nodes` scaled additions instead of reading both couplings per node.
//!
//! A factorisation per step remains: the nodes' `s_i` differ (the law at the start and the
//! end of the step) and multiply different dense matrices (`H_i`), so `A` is a
//! two-parameter family for the trapezoid rule, not a scalar shift of a fixed matrix; only
//! without couplings is it diagonal (no factorisation at all, as before).

use super::{LocalNewton, Setting};

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
        for i in 0..self.map.len() {
            let si = self.s[i];
            for (wh, wm) in self.w_hat[i].iter_mut().zip(&w[i]) {
                *wh = si * wm;
            }
            for ((dg, wm), dm) in self.diag.iter_mut().zip(&w[i]).zip(&self.d[i]) {
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
