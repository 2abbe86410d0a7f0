//! A kink inside a step of the coupled route: the elements' pseudo-force sampled at `2^d + 1`
//! points of the step instead of its two ends.
//!
//! The coupled route cannot take substeps (its background's step is one exact transition of
//! the run's `dt`), so a step over which an element's tangent changes fast (a gap closing, a
//! contact's ramp, a yield: [`kink_depth`]) keeps the step but refines its quadrature: the
//! displacement stays scheme b's line from `q0` to `q1` (velocity `(q1 - q0)/dt`), and the
//! pseudo-force along it is taken piecewise linear between `2^d + 1` equally spaced nodes
//! (the trapezoid on each piece, weighted exactly by `e^(lambda (dt - s))`), which places the
//! kink within `dt / 2^d` instead of smearing it over the step. The step equation
//! `q1 = q1_lin + sum_i H_i Q_i(q1)` is solved by Newton from the trapezoid's solution.

use num_complex::Complex64;

use super::{Corrector, Work};
use crate::dense::DenseLu;
use crate::error::CoreError;
use crate::kernel::cphi;
use crate::pseudo::force::{At, Jacobian};
use crate::pseudo::stiff_rule::kink_depth;

/// The deepest refinement: `2^KINK_LEVELS` pieces (the pseudo-force route's default
/// `subdivisions`, 4, for its substeps).
pub(super) const KINK_LEVELS: usize = 4;

/// The node weights of each refinement level `d = 1..=KINK_LEVELS`, and the work buffers.
pub(super) struct Nodes {
    /// Per level: for each node `i = 0..=2^d`, its weight times the gains (`r x m` complex)
    /// and what a unit modal load there does to `q1` (`m x m`).
    levels: Vec<Vec<(Vec<Complex64>, Vec<f64>)>>,
    f: Vec<Vec<f64>>,
    jac: Vec<Jacobian>,
    q: Vec<f64>,
    /// The elements' `(omega_c^2, background)` at the start of the step.
    pub start: (f64, f64),
    /// Steps whose quadrature was refined.
    pub refined: usize,
}

/// What a unit modal load weighted by `gw` (`r x m` complex) does to the real modal
/// displacement `q1` (`m x m`, row-major), through `back` (`[Re | Im] -> [q | q']`).
pub(super) fn back_project(back: &[f64], gw: &[Complex64], m: usize, r: usize) -> Vec<f64> {
    let mut out = vec![0.0; m * m];
    for kk in 0..r {
        let (re_row, im_row) = (&back[kk * 2 * m..][..m], &back[(r + kk) * 2 * m..][..m]);
        for j in 0..m {
            let x = gw[kk * m + j];
            for i in 0..m {
                out[i * m + j] += x.re * re_row[i] + x.im * im_row[i];
            }
        }
    }
    out
}

impl Nodes {
    /// The levels for first-order eigenvalues `lambda`, gains `gain` (`r x m`, re and im)
    /// and the back map `back`, steps of `dt`.
    pub fn new(
        lambda: &[Complex64],
        gain: (&[f64], &[f64]),
        back: &[f64],
        m: usize,
        dt: f64,
    ) -> Self {
        let r = lambda.len();
        let levels = (1..=KINK_LEVELS)
            .map(|d| {
                let pieces = 1usize << d;
                let h = dt / pieces as f64;
                (0..=pieces)
                    .map(|i| {
                        let mut gw = Vec::with_capacity(r * m);
                        for (kk, &lam) in lambda.iter().enumerate() {
                            let mu = cphi::moments(lam, h);
                            let (wa, wb) = (mu[0] - mu[1], mu[1]);
                            // node i starts piece i (weight wa) and ends piece i - 1 (wb),
                            // each carried to the step's end by e^(lambda (dt - its end))
                            let carry = |end: usize| (lam * (h * (pieces - end) as f64)).exp();
                            let mut w = Complex64::new(0.0, 0.0);
                            if i < pieces {
                                w += wa * carry(i + 1);
                            }
                            if i > 0 {
                                w += wb * carry(i);
                            }
                            for j in 0..m {
                                let g = Complex64::new(gain.0[kk * m + j], gain.1[kk * m + j]);
                                gw.push(w * g);
                            }
                        }
                        let hm = back_project(back, &gw, m, r);
                        (gw, hm)
                    })
                    .collect()
            })
            .collect();
        let most = (1 << KINK_LEVELS) + 1;
        Nodes {
            levels,
            f: vec![vec![0.0; m]; most],
            jac: (0..most).map(|_| Jacobian::new(m)).collect(),
            q: vec![0.0; m],
            start: (0.0, 0.0),
            refined: 0,
        }
    }
}

impl Corrector<'_> {
    /// The refinement the step from `self.q` to the trapezoid's end `w.q1` needs (0: none):
    /// the elements' tangent at that end (chord velocity) against the step's start.
    pub(super) fn kink(&mut self, t: f64, w: &mut Work) -> Result<usize, CoreError> {
        let Some(start) = self.nodes.as_ref().map(|n| n.start) else {
            return Ok(0);
        };
        for ((vb, q1), q0) in w.vb.iter_mut().zip(&w.q1).zip(&self.q) {
            *vb = (q1 - q0) / self.dt;
        }
        let (lambda, _) = self.pf.tangent_stiffness(&w.q1, &w.vb, t + self.dt)?;
        let end = (lambda, self.pf.bg());
        Ok(kink_depth(start, end, KINK_LEVELS))
    }

    /// Solves the step with `2^depth + 1` nodes (from the trapezoid's `w.q1`) and adds the
    /// pseudo-force's response to the linear step `(re, im)`; the end's pseudo-force into
    /// `self.last`. Returns the Newton iterations.
    pub(super) fn refined(
        &mut self,
        t: f64,
        (re, im): (&mut [f64], &mut [f64]),
        w: &mut Work,
        depth: usize,
    ) -> Result<usize, CoreError> {
        let m = self.m;
        let Some(mut nodes) = self.nodes.take() else {
            return Ok(0);
        };
        let result = self.refined_newton(t, w, &mut nodes, depth);
        if result.is_ok() {
            let pieces = 1usize << depth;
            let level = &nodes.levels[depth - 1];
            for (kk, (xr, xi)) in re.iter_mut().zip(im.iter_mut()).enumerate() {
                let mut x = Complex64::new(0.0, 0.0);
                for ((gw, _), f) in level.iter().zip(&nodes.f) {
                    for i in 0..m {
                        x += gw[kk * m + i] * f[i];
                    }
                }
                *xr += x.re;
                *xi += x.im;
            }
            self.last.copy_from_slice(&nodes.f[pieces]);
            nodes.refined += 1;
        }
        self.nodes = Some(nodes);
        result
    }

    fn refined_newton(
        &mut self,
        t: f64,
        w: &mut Work,
        nodes: &mut Nodes,
        depth: usize,
    ) -> Result<usize, CoreError> {
        let (m, dt) = (self.m, self.dt);
        let pieces = 1usize << depth;
        let mut residual = f64::INFINITY;
        for it in 1..=self.max_iter {
            for ((vb, q1), q0) in w.vb.iter_mut().zip(&w.q1).zip(&self.q) {
                *vb = (q1 - q0) / dt;
            }
            for i in 0..=pieces {
                let s = i as f64 / pieces as f64;
                for ((x, q0), q1) in nodes.q.iter_mut().zip(&self.q).zip(&w.q1) {
                    *x = q0 + s * (q1 - q0);
                }
                let at = At {
                    q: &nodes.q,
                    v: &w.vb,
                    t: t + s * dt,
                    p: &self.zeros,
                    a: None,
                };
                self.pf.eval(at, &mut nodes.f[i], Some(&mut nodes.jac[i]))?;
            }
            // R = q1 - q1_lin - sum_i H_i f_i; J = I - sum_i H_i (s_i K_i + C_i / dt)
            let level = &nodes.levels[depth - 1];
            for i in 0..m {
                let mut ri = w.q1[i] - w.q1_lin[i];
                for ((_, hm), f) in level.iter().zip(&nodes.f) {
                    for j in 0..m {
                        ri -= hm[i * m + j] * f[j];
                    }
                }
                w.rhs[i] = -ri;
            }
            residual = w.rhs.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            w.mat.fill(0.0);
            for (node, ((_, hm), jac)) in level.iter().zip(&nodes.jac).enumerate() {
                let s = node as f64 / pieces as f64;
                for i in 0..m {
                    for l in 0..m {
                        let a = hm[i * m + l];
                        if a == 0.0 {
                            continue;
                        }
                        for j in 0..m {
                            w.mat[i * m + j] -=
                                a * (s * jac.kq[l * m + j] + jac.cq[l * m + j] / dt);
                        }
                    }
                }
            }
            for i in 0..m {
                w.mat[i * m + i] += 1.0;
            }
            let Some(lu) = DenseLu::factor(m, &w.mat) else {
                break;
            };
            self.factorizations += 1;
            if !lu.solve(&mut w.rhs, &mut w.scratch) {
                break;
            }
            let (mut step, mut size) = (0.0_f64, 0.0_f64);
            for i in 0..m {
                w.q1[i] += w.rhs[i];
                step = step.max(w.rhs[i].abs());
                size = size.max(w.q1[i].abs());
            }
            self.iterations += 1;
            if !step.is_finite() {
                break;
            }
            if step <= self.tol * size || step == 0.0 {
                // the nodes at the converged end (the last update is within the tolerance)
                for ((vb, q1), q0) in w.vb.iter_mut().zip(&w.q1).zip(&self.q) {
                    *vb = (q1 - q0) / dt;
                }
                for i in 0..=pieces {
                    let s = i as f64 / pieces as f64;
                    for ((x, q0), q1) in nodes.q.iter_mut().zip(&self.q).zip(&w.q1) {
                        *x = q0 + s * (q1 - q0);
                    }
                    let at = At {
                        q: &nodes.q,
                        v: &w.vb,
                        t: t + s * dt,
                        p: &self.zeros,
                        a: None,
                    };
                    self.pf.eval(at, &mut nodes.f[i], None)?;
                }
                return Ok(it);
            }
        }
        Err(CoreError::NoConvergence {
            time: t + dt,
            step: 0,
            residual,
            iterations: self.max_iter,
            last_good_time: Some(t),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{Nodes, KINK_LEVELS};
    use crate::kernel::cphi;
    use num_complex::Complex64;

    /// The node weights integrate a force linear in time exactly, as the trapezoid does:
    /// their sum is `w_a + w_b` and their first moment `w_b`, at every level; and a force
    /// with a kink at a node is integrated exactly (against a fine midpoint sum).
    #[test]
    fn node_weights_are_the_piecewise_linear_quadrature() {
        let (dt, lam) = (0.3, Complex64::new(-0.4, 7.0));
        // one mode, unit gain; back maps Re eta to q (2r x 2m = 2 x 2)
        let nodes = Nodes::new(&[lam], (&[1.0], &[0.0]), &[1.0, 0.0, 0.0, 0.0], 1, dt);
        let mu = cphi::moments(lam, dt);
        let (wa, wb) = (mu[0] - mu[1], mu[1]);
        for d in 1..=KINK_LEVELS {
            let level = &nodes.levels[d - 1];
            let pieces = 1usize << d;
            let sum: Complex64 = level.iter().map(|(g, _)| g[0]).sum();
            let first: Complex64 = level
                .iter()
                .enumerate()
                .map(|(i, (g, _))| g[0] * (i as f64 / pieces as f64))
                .sum();
            assert!((sum - (wa + wb)).norm() < 1e-13 * (wa + wb).norm(), "{d}");
            assert!((first - wb).norm() < 1e-13 * wb.norm(), "{d}");
            // a ramp starting at node 1: f(s) = max(s - 1/pieces, 0)
            let kink = 1.0 / pieces as f64;
            let f = |s: f64| (s - kink).max(0.0);
            let quad: Complex64 = level
                .iter()
                .enumerate()
                .map(|(i, (g, _))| g[0] * f(i as f64 / pieces as f64))
                .sum();
            let n = 200_000;
            let exact: Complex64 = (0..n)
                .map(|k| {
                    let s = (k as f64 + 0.5) / n as f64;
                    (lam * (dt * (1.0 - s))).exp() * f(s) * (dt / n as f64)
                })
                .sum();
            assert!(
                (quad - exact).norm() < 1e-8 * exact.norm(),
                "{d}: {quad} {exact}"
            );
        }
    }
}
