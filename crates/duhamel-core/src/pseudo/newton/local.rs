//! Newton's method in the space of the elements' dofs (the FNA iteration).
//!
//! With `z` the unknown half of the end state (`q1` for schemes b and c, `v1` for scheme a),
//! the node states are affine in `z`: `q_i = q_i^0 + alpha_i z`, `v_i = v_i^0 + beta_i z`
//! (the same `alpha_i`, `beta_i` for every mode). Along the eliminated mass law (or without
//! one) the pseudo-force at node `i` is
//!
//! ```text
//! Q_i = g_i (p_i - c v_i - kappa k q_i) - mom_i v_i - (Kc_i q_i + Cc_i v_i + Phi_D^T r_i) / mu_i
//! ```
//!
//! (`Kc_i`, `Cc_i` the linear couplings at the node's time), linear in the state but for the
//! element forces `r_i`. The step equation `z = base + sum_i W_i Q_i` is therefore
//! `A z = b - sum_i diag(W_i / mu_i) Phi_D^T r_i` with a matrix `A` (diagonal without
//! couplings) that does not depend on the elements; with `X_i = A^{-1} diag(W_i/mu_i) Phi_D^T`
//! and `y = Phi_D z` it becomes, in the element coordinates,
//!
//! ```text
//! F(y) = y - Phi_D A^{-1} b + sum_i G_i r_i(U_i + alpha_i y, V_i + beta_i y) = 0,
//! G_i = Phi_D X_i,   J = I + sum_i G_i (alpha_i K_i + beta_i C_i),
//! ```
//!
//! `n_d` unknowns instead of `n`: an iteration costs `O(n_nodes n_d^2 + n_d^3)`, the step
//! `O(n n_d)` besides (`O(n^2)` with couplings). `A`, `X_i` and `G_i` are formed once per
//! run, or once per step with a mass law or couplings scaled by a time-varying speed
//! (`O(n^3 + n_nodes n_d n^2)` then).

use super::super::force::PseudoForce;
use super::super::local::ElementSpace;
use super::super::scheme::{Rule, Scheme, StepInput, Unknown};
use super::damping::backtrack;
use crate::dense::{solve_in_place, DenseLu};
use crate::error::CoreError;

/// Buffers and the per-node matrices of the element-space Newton.
pub(super) struct LocalNewton {
    n: usize,
    nd: usize,
    /// `G_i` per node (`n_d x n_d`), and whether they hold for every step.
    g: Vec<Vec<f64>>,
    g_ready: bool,
    /// `P = Phi_D A^{-1}` (`n_d x n`, row-major).
    pmat: Vec<f64>,
    /// `W_i / mu_i` per node (`n`), the right-hand side `b` then `z_b = A^{-1} b` (`n`).
    w_hat: Vec<Vec<f64>>,
    base: Vec<f64>,
    /// The diagonal of `A` (mass terms), and with couplings `A` itself and its factors.
    diag: Vec<f64>,
    a: Vec<f64>,
    lu: Option<DenseLu>,
    work: Vec<f64>,
    /// The couplings at each node (`n x n`), when there are any.
    kc: Vec<Vec<f64>>,
    cc: Vec<Vec<f64>>,
    has_kc: (bool, bool),
    /// Per node: `U_i`, `V_i`, the force and tangents (`n_d`, `n_d x n_d`).
    u0: Vec<Vec<f64>>,
    ud0: Vec<Vec<f64>>,
    r: Vec<Vec<f64>>,
    kt: Vec<Vec<f64>>,
    ct: Vec<Vec<f64>>,
    /// Modal node states for the constant part (`n` each).
    qi: Vec<f64>,
    vi: Vec<f64>,
    y: Vec<f64>,
    y0: Vec<f64>,
    y_prev: Vec<f64>,
    delta: Vec<f64>,
    res: Vec<f64>,
    mat: Vec<f64>,
    u: Vec<f64>,
    ud: Vec<f64>,
    /// The sparsity of the tangents' rows ([`ElementSpace::pattern`]).
    pattern: Vec<Vec<usize>>,
}

/// What the step needs to know about the problem besides the element space.
pub(super) struct Setting<'s> {
    pub rule: &'s Rule,
    pub scheme: Scheme,
    pub dt: f64,
    pub unknown: Unknown,
    pub constant: &'s [bool],
    pub tol: f64,
    pub max_iter: usize,
    pub linear: bool,
}

impl LocalNewton {
    pub fn new(space: &ElementSpace, pf: &PseudoForce, n: usize, nodes: usize) -> Self {
        let nd = space.len();
        let per_node = |len: usize| vec![vec![0.0; len]; nodes];
        let coupled = pf.has_couplings();
        let square = if coupled { n * n } else { 0 };
        LocalNewton {
            n,
            nd,
            g: per_node(nd * nd),
            g_ready: false,
            pmat: vec![0.0; nd * n],
            w_hat: per_node(n),
            base: vec![0.0; n],
            diag: vec![1.0; n],
            a: vec![0.0; square],
            lu: None,
            work: vec![0.0; n],
            kc: per_node(square),
            cc: per_node(square),
            has_kc: (false, false),
            u0: per_node(nd),
            ud0: per_node(nd),
            r: per_node(nd),
            kt: per_node(nd * nd),
            ct: per_node(nd * nd),
            qi: vec![0.0; n],
            vi: vec![0.0; n],
            y: vec![0.0; nd],
            y0: vec![0.0; nd],
            y_prev: vec![0.0; nd],
            delta: vec![0.0; nd],
            res: vec![0.0; nd],
            mat: vec![0.0; nd * nd],
            u: vec![0.0; nd],
            ud: vec![0.0; nd],
            pattern: space.pattern(),
        }
    }

    /// `(alpha_i, beta_i)`: the derivatives of the node state with respect to `z`.
    fn slopes(set: &Setting, i: usize) -> (f64, f64) {
        let [dqq, dqv, dvq, dvv] = set.rule.nodes[i].d;
        match set.unknown {
            Unknown::V1 => (dqv, dvv),
            _ => (dqq, dvq),
        }
    }

    /// Solves the step for `z` (in: the predictor; out: the solution). Returns the Newton
    /// iterations.
    pub fn solve(
        &mut self,
        space: &mut ElementSpace,
        pf: &PseudoForce,
        set: &Setting,
        inp: &StepInput,
        z: &mut [f64],
    ) -> Result<usize, CoreError> {
        let (n, nd, dt) = (self.n, self.nd, set.dt);
        let (kk, cc) = pf.modal_kc();
        let mass = pf.has_mass();
        let coupled = pf.has_couplings();
        let nodes = set.rule.nodes.len();
        let rebuild = mass || pf.varying_couplings() || !self.g_ready;
        let w = if set.unknown == Unknown::V1 {
            &set.rule.wv
        } else {
            &set.rule.wx
        };
        self.base.copy_from_slice(if set.unknown == Unknown::V1 {
            inp.v_lin
        } else {
            inp.q_lin
        });
        if rebuild {
            self.diag.fill(1.0);
            self.a.fill(0.0);
        }
        for (i, wi) in w.iter().enumerate() {
            let s = set.rule.nodes[i].s;
            let t = inp.t + s * dt;
            let (alpha, beta) = Self::slopes(set, i);
            for m in 0..n {
                (self.qi[m], self.vi[m]) = set.scheme.state(s, dt, inp.q0[m], inp.v0[m], 0.0, 0.0);
            }
            space.to_local(&self.qi, &mut self.u0[i]);
            space.to_local(&self.vi, &mut self.ud0[i]);
            let [mu, g, mom, kappa] = pf.node_mass(t);
            if mass {
                for m in 0..n {
                    let p = inp.pb[0][m] + inp.pb[1][m] * s + 4.0 * inp.pb[2][m] * s * (1.0 - s);
                    let damp = g * cc[m] + mom;
                    let stiff = g * kappa * kk[m];
                    self.diag[m] += wi[m] * (damp * beta + stiff * alpha);
                    self.base[m] += wi[m] * (g * p - damp * self.vi[m] - stiff * self.qi[m]);
                }
            }
            if coupled {
                if pf.varying_couplings() || !self.g_ready {
                    self.has_kc = pf.couplings_at(t, &mut self.kc[i], &mut self.cc[i]);
                }
                let (kc, ccm) = (&self.kc[i], &self.cc[i]);
                for r in 0..n {
                    let (kr, cr) = (&kc[r * n..(r + 1) * n], &ccm[r * n..(r + 1) * n]);
                    let mut acc = 0.0;
                    if self.has_kc.0 {
                        acc += kr.iter().zip(&self.qi).map(|(a, b)| a * b).sum::<f64>();
                    }
                    if self.has_kc.1 {
                        acc += cr.iter().zip(&self.vi).map(|(a, b)| a * b).sum::<f64>();
                    }
                    let f = wi[r] / mu;
                    self.base[r] -= f * acc;
                    if rebuild {
                        let row = &mut self.a[r * n..(r + 1) * n];
                        for ((a, k), c) in row.iter_mut().zip(kr).zip(cr) {
                            *a += f * (alpha * k + beta * c);
                        }
                    }
                }
            }
            if rebuild {
                for (wh, wm) in self.w_hat[i].iter_mut().zip(wi) {
                    *wh = wm / mu;
                }
            }
        }
        if rebuild {
            self.prepare(space)?;
        }
        // y0 = Phi_D A^{-1} b = P b
        for (y, row) in self.y0.iter_mut().zip(self.pmat.chunks_exact(n)) {
            *y = row.iter().zip(&self.base).map(|(p, b)| p * b).sum();
        }
        // Constant nodes: their forces once, folded into y0.
        for i in 0..nodes {
            if set.constant[i] {
                let t = inp.t + set.rule.nodes[i].s * dt;
                space.eval(&self.u0[i], &self.ud0[i], t, &mut self.r[i], None)?;
                for a in 0..nd {
                    let ga = &self.g[i][a * nd..(a + 1) * nd];
                    self.y0[a] -= ga.iter().zip(&self.r[i]).map(|(x, y)| x * y).sum::<f64>();
                }
            }
        }
        space.to_local(z, &mut self.y);
        let scale0 = self
            .y0
            .iter()
            .chain(self.u0.iter().flatten())
            .fold(0.0_f64, |a, b| a.max(b.abs()));
        let iterations = self.newton(space, set, inp, scale0)?;
        // z = A^{-1} (b - sum_i diag(W_i / mu_i) Phi_D^T r_i) from the converged forces.
        z.copy_from_slice(&self.base);
        let phi = space.phi();
        for (wh, r) in self.w_hat.iter().zip(&self.r) {
            for (row, &rb) in phi.chunks_exact(n).zip(r) {
                if rb != 0.0 {
                    for ((zm, p), w) in z.iter_mut().zip(row).zip(wh) {
                        *zm -= w * p * rb;
                    }
                }
            }
        }
        match &self.lu {
            Some(lu) => {
                lu.solve(z, &mut self.work);
            }
            None => {
                for (zm, d) in z.iter_mut().zip(&self.diag) {
                    *zm /= d;
                }
            }
        }
        Ok(iterations)
    }

    /// `P = Phi_D A^{-1}` and `G_i = P diag(W_i / mu_i) Phi_D^T` from `A` (its diagonal
    /// `diag`, plus `a` with couplings).
    fn prepare(&mut self, space: &ElementSpace) -> Result<(), CoreError> {
        let (n, nd) = (self.n, self.nd);
        let phi = space.phi();
        self.lu = if self.a.is_empty() {
            None
        } else {
            for m in 0..n {
                self.a[m * n + m] += self.diag[m];
            }
            Some(DenseLu::factor(n, &self.a).ok_or(CoreError::NonFinite {
                time: 0.0,
                step: 0,
                last_good_time: None,
            })?)
        };
        self.pmat.copy_from_slice(phi);
        for row in self.pmat.chunks_exact_mut(n) {
            match &self.lu {
                Some(lu) => {
                    lu.solve_transpose(row, &mut self.work);
                }
                None => {
                    for (p, d) in row.iter_mut().zip(&self.diag) {
                        *p /= d;
                    }
                }
            }
        }
        for (g, wh) in self.g.iter_mut().zip(&self.w_hat) {
            for (a, pa) in self.pmat.chunks_exact(n).enumerate() {
                for (b, rb) in phi.chunks_exact(n).enumerate() {
                    g[a * nd + b] = pa.iter().zip(wh).zip(rb).map(|((p, w), r)| p * w * r).sum();
                }
            }
        }
        self.g_ready = true;
        Ok(())
    }

    /// Evaluates the varying nodes at `y` and returns the residual's max norm.
    fn residual(
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
        for i in 0..set.rule.nodes.len() {
            if set.constant[i] {
                continue;
            }
            let (alpha, beta) = Self::slopes(set, i);
            for a in 0..nd {
                self.u[a] = self.u0[i][a] + alpha * self.y[a];
                self.ud[a] = self.ud0[i][a] + beta * self.y[a];
            }
            let t = inp.t + set.rule.nodes[i].s * set.dt;
            let tan = tangent.then_some((&mut self.kt[i][..], &mut self.ct[i][..]));
            space.eval(&self.u, &self.ud, t, &mut self.r[i], tan)?;
            for a in 0..nd {
                let ga = &self.g[i][a * nd..(a + 1) * nd];
                self.res[a] += ga.iter().zip(&self.r[i]).map(|(x, y)| x * y).sum::<f64>();
            }
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
    fn jacobian(&mut self, set: &Setting) {
        let nd = self.nd;
        self.mat.fill(0.0);
        for a in 0..nd {
            self.mat[a * nd + a] = 1.0;
        }
        for i in 0..set.rule.nodes.len() {
            if set.constant[i] {
                continue;
            }
            let (alpha, beta) = Self::slopes(set, i);
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

    /// Newton's method on `F(y) = 0`, damped by the modal one's [`backtrack`].
    fn newton(
        &mut self,
        space: &mut ElementSpace,
        set: &Setting,
        inp: &StepInput,
        scale0: f64,
    ) -> Result<usize, CoreError> {
        let mut last: Option<f64> = None;
        let mut norm = f64::INFINITY;
        for iter in 1..=set.max_iter {
            norm = self.residual(space, set, inp, true)?;
            if let Some(prev) = last {
                norm = backtrack(prev, norm, scale0, |lambda| {
                    for ((y, yp), d) in self.y.iter_mut().zip(&self.y_prev).zip(&self.delta) {
                        *y = yp + lambda * d;
                    }
                    self.residual(space, set, inp, true)
                })?;
            }
            self.jacobian(set);
            for (d, r) in self.delta.iter_mut().zip(&self.res) {
                *d = -r;
            }
            if !solve_in_place(self.nd, &self.mat, &mut self.delta) {
                break;
            }
            self.y_prev.copy_from_slice(&self.y);
            for (y, d) in self.y.iter_mut().zip(&self.delta) {
                *y += d;
            }
            let size = self.delta.iter().fold(0.0_f64, |a, d| a.max(d.abs()));
            let ymax = self.y.iter().fold(0.0_f64, |a, y| a.max(y.abs()));
            if set.linear || size <= set.tol * ymax.max(scale0) || size == 0.0 {
                // The forces at the accepted state.
                self.residual(space, set, inp, false)?;
                return Ok(iter);
            }
            last = Some(norm);
        }
        Err(CoreError::NoConvergence {
            time: inp.t + set.dt,
            step: 0,
            residual: norm,
            iterations: set.max_iter,
            last_good_time: Some(inp.t),
        })
    }
}
