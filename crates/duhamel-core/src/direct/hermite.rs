//! A time finite element with a C1 cubic Hermite trial function (fourth order).
//!
//! Over a step of length `h`, with `s = tau/h` and `w = h x'`,
//!
//! `x(s) = H00(s) x0 + H10(s) w0 + H01(s) x1 + H11(s) w1`
//!
//! (the cubic Hermite basis), and the residual `E = mu M x'' + (mu' M + C) x' + (s K + Kc) x
//! + sum_j w_j(t) (K_j x + C_j x') + r(x, x', t) - f(t)` of the equation of motion along it is made orthogonal to the weights
//! `{1, 2s - 1}` (the span of `{1, t}`):
//!
//! `R_i = sum_g W_g psi_i(s_g) E(s_g) = 0`, `i = 0, 1`,
//!
//! with Gauss-Legendre points `s_g`. These are `2n` equations for the unknowns `(x1, w1)`,
//! solved by Newton (elements' tangents at every Gauss point), modified as in the
//! generalized-alpha steps. The paper's "cubic Hermitian" comparison scheme is not available
//! to us: this is a reconstruction, not Argyris' own formulation.

use super::assembly::{Factorization, IterationMatrix};
use super::model::{Coefs, Model, C, K, KC, M};
use super::stepper::Stepper;
use crate::error::CoreError;
use crate::loads::ModalForcing;

/// Gauss-Legendre nodes and weights on `[0, 1]` (Newton on the Legendre polynomial).
pub(crate) fn gauss(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(n);
    let mut weights = Vec::with_capacity(n);
    for i in 1..=n {
        let mut z = (std::f64::consts::PI * (i as f64 - 0.25) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        nodes.push(0.5 * (1.0 - z));
        weights.push(1.0 / ((1.0 - z * z) * dp * dp));
    }
    (nodes, weights)
}

/// Values, first and second derivatives (in `s`) of `H00, H10, H01, H11` at `s`.
fn basis(s: f64) -> [[f64; 4]; 3] {
    let (s2, s3) = (s * s, s * s * s);
    [
        [
            1.0 - 3.0 * s2 + 2.0 * s3,
            s - 2.0 * s2 + s3,
            3.0 * s2 - 2.0 * s3,
            -s2 + s3,
        ],
        [
            -6.0 * s + 6.0 * s2,
            1.0 - 4.0 * s + 3.0 * s2,
            6.0 * s - 6.0 * s2,
            -2.0 * s + 3.0 * s2,
        ],
        [
            -6.0 + 12.0 * s,
            -4.0 + 6.0 * s,
            6.0 - 12.0 * s,
            -2.0 + 6.0 * s,
        ],
    ]
}

/// One Gauss point: position, weight, the basis there, the test functions `{1, 2s - 1}`.
struct Point {
    s: f64,
    w: f64,
    h: [[f64; 4]; 3],
    psi: [f64; 2],
}

pub(crate) struct Hermite<'a> {
    dt: f64,
    tol: f64,
    max_iter: usize,
    points: Vec<Point>,
    it: IterationMatrix<'a>,
    lu: Option<Factorization>,
    constant: bool,
    newton: bool,
    factorizations: usize,
    /// Loads at the Gauss points of the step (rows), mass-law coefficients there.
    f: Vec<f64>,
    coefs: Vec<Coefs>,
    /// Unknowns `(x1, w1)`, residual / update, work vectors.
    y: Vec<f64>,
    r: Vec<f64>,
    xg: Vec<f64>,
    vg: Vec<f64>,
    rg: Vec<f64>,
    /// Per test function: what multiplies M, C, K and Kc.
    acc: [[Vec<f64>; 4]; 2],
    /// Speed laws of the scaled couplings at the Gauss points, `[g * n_scaled + j]`.
    scales: Vec<f64>,
    /// Per test function and scaled coupling: what multiplies `K_j` and `C_j`.
    acc_scaled: [Vec<[Vec<f64>; 2]>; 2],
}

impl<'a> Hermite<'a> {
    pub fn new(model: &Model<'a>, points: usize) -> Result<Self, CoreError> {
        let p = model.p;
        let n = model.n;
        let (nodes, weights) = gauss(points);
        let points = nodes
            .iter()
            .zip(&weights)
            .map(|(&s, &w)| Point {
                s,
                w,
                h: basis(s),
                psi: [1.0, 2.0 * s - 1.0],
            })
            .collect::<Vec<_>>();
        let newton = !p.elements.is_empty();
        let zeros = || std::array::from_fn(|_| vec![0.0; n]);
        let n_scaled = p.scaled.len();
        let n_points = points.len();
        let scaled_zeros = || {
            (0..n_scaled)
                .map(|_| [vec![0.0; n], vec![0.0; n]])
                .collect::<Vec<_>>()
        };
        Ok(Hermite {
            dt: p.dt,
            tol: p.tol,
            max_iter: p.max_iter,
            it: model.iteration_matrix(2)?,
            lu: None,
            constant: p.mass.is_none() && !newton && !model.varying_scale,
            newton,
            factorizations: 0,
            f: vec![0.0; points.len() * n],
            coefs: Vec::with_capacity(points.len()),
            points,
            y: vec![0.0; 2 * n],
            r: vec![0.0; 2 * n],
            xg: vec![0.0; n],
            vg: vec![0.0; n],
            rg: vec![0.0; n],
            acc: [zeros(), zeros()],
            scales: Vec::with_capacity(n_points * n_scaled),
            acc_scaled: [scaled_zeros(), scaled_zeros()],
        })
    }

    /// The residual at the unknowns `self.y` into `self.r`; with `assemble`, also the
    /// iteration matrix (elements' tangents at every Gauss point) and its factorisation.
    fn residual(
        &mut self,
        model: &mut Model,
        t: f64,
        x0: &[f64],
        w0: &[f64],
        assemble: bool,
    ) -> Result<(), CoreError> {
        let n = x0.len();
        let h = self.dt;
        let (x1, w1) = self.y.split_at(n);
        for acc in self.acc.iter_mut().flatten() {
            acc.fill(0.0);
        }
        for acc in self.acc_scaled.iter_mut().flatten().flatten() {
            acc.fill(0.0);
        }
        let n_scaled = self.acc_scaled[0].len();
        self.r.fill(0.0);
        if assemble {
            self.it.clear();
        }
        for (g, pt) in self.points.iter().enumerate() {
            let k = self.coefs[g];
            let tg = t + pt.s * h;
            let [b, d1, d2] = pt.h;
            for i in 0..n {
                let (a, bb, c, d) = (x0[i], w0[i], x1[i], w1[i]);
                self.xg[i] = b[0] * a + b[1] * bb + b[2] * c + b[3] * d;
                self.vg[i] = (d1[0] * a + d1[1] * bb + d1[2] * c + d1[3] * d) / h;
                let xdd = (d2[0] * a + d2[1] * bb + d2[2] * c + d2[3] * d) / (h * h);
                let fg = self.f[g * n + i];
                for (ti, acc) in self.acc.iter_mut().enumerate() {
                    let c = pt.w * pt.psi[ti];
                    acc[0][i] += c * (k.mu * xdd + k.dmu * self.vg[i]);
                    acc[1][i] += c * self.vg[i];
                    acc[2][i] += c * k.s * self.xg[i];
                    acc[3][i] += c * self.xg[i];
                    self.r[ti * n + i] -= c * fg;
                }
                for (ti, accs) in self.acc_scaled.iter_mut().enumerate() {
                    let c = pt.w * pt.psi[ti];
                    for (j, acc) in accs.iter_mut().enumerate() {
                        let cw = c * self.scales[g * n_scaled + j];
                        acc[0][i] += cw * self.xg[i];
                        acc[1][i] += cw * self.vg[i];
                    }
                }
            }
            if model.slots.is_empty() {
                continue;
            }
            self.rg.fill(0.0);
            model.element_force(
                &self.xg,
                &self.vg,
                tg,
                assemble && self.newton,
                &mut self.rg,
            )?;
            for ti in 0..2 {
                let c = pt.w * pt.psi[ti];
                for (ri, gi) in self.r[ti * n..(ti + 1) * n].iter_mut().zip(&self.rg) {
                    *ri += c * gi;
                }
                if assemble && self.newton {
                    // d/dx1 (basis H01) and d/dw1 (basis H11) of r at this point.
                    for (tj, col) in [2usize, 3].into_iter().enumerate() {
                        model.add_tangents(&mut self.it, (ti, tj), c * b[col], c * d1[col] / h);
                    }
                }
            }
        }
        let p = model.p;
        for ti in 0..2 {
            let r = &mut self.r[ti * n..(ti + 1) * n];
            let acc = &self.acc[ti];
            p.m.mul_add(1.0, &acc[0], r);
            if let Some(c) = p.c {
                c.mul_add(1.0, &acc[1], r);
            }
            p.k.mul_add(1.0, &acc[2], r);
            if let Some(kc) = p.k_fixed {
                kc.mul_add(1.0, &acc[3], r);
            }
            for (sc, acc) in p.scaled.iter().zip(&self.acc_scaled[ti]) {
                if let Some(m) = sc.k {
                    m.mul_add(1.0, &acc[0], r);
                }
                if let Some(m) = sc.c {
                    m.mul_add(1.0, &acc[1], r);
                }
            }
        }
        if assemble {
            self.assemble_constant(model);
            self.lu = Some(self.it.factorize()?);
            self.factorizations += 1;
        }
        Ok(())
    }

    /// Adds the constant matrices' part of `dR/d(x1, w1)`.
    fn assemble_constant(&mut self, model: &Model) {
        let h = self.dt;
        for ti in 0..2 {
            for (tj, col) in [2usize, 3].into_iter().enumerate() {
                let mut cm = [0.0; 4];
                for (g, pt) in self.points.iter().enumerate() {
                    let k = self.coefs[g];
                    let c = pt.w * pt.psi[ti];
                    let [b, d1, d2] = pt.h;
                    cm[0] += c * (k.mu * d2[col] / (h * h) + k.dmu * d1[col] / h);
                    cm[1] += c * d1[col] / h;
                    cm[2] += c * k.s * b[col];
                    cm[3] += c * b[col];
                }
                for (which, coef) in [M, C, K, KC].into_iter().zip(cm) {
                    model.add(&mut self.it, which, (ti, tj), coef);
                }
                let n_scaled = self.acc_scaled[0].len();
                for j in 0..n_scaled {
                    let (mut ck, mut cc) = (0.0, 0.0);
                    for (g, pt) in self.points.iter().enumerate() {
                        let cw = pt.w * pt.psi[ti] * self.scales[g * n_scaled + j];
                        ck += cw * pt.h[0][col];
                        cc += cw * pt.h[1][col] / h;
                    }
                    model.add_scaled(&mut self.it, j, (ti, tj), ck, cc);
                }
            }
        }
    }
}

impl Stepper for Hermite<'_> {
    fn step(
        &mut self,
        model: &mut Model,
        forcing: Option<&mut (dyn ModalForcing + '_)>,
        t: f64,
        state: [&mut [f64]; 3],
    ) -> Result<usize, CoreError> {
        let h = self.dt;
        let [x, v, a] = state;
        let n = x.len();
        let times: Vec<f64> = self.points.iter().map(|p| t + p.s * h).collect();
        model.external(&times, forcing, &mut self.f)?;
        self.coefs.clear();
        self.coefs
            .extend(times.iter().map(|&tg| model.coefs(tg, false)));
        self.scales.clear();
        for &tg in &times {
            self.scales.extend(model.scales(tg));
        }
        let w0: Vec<f64> = v.iter().map(|vi| h * vi).collect();
        // Predictor: Taylor with the acceleration at the start.
        for i in 0..n {
            self.y[i] = x[i] + h * v[i] + 0.5 * h * h * a[i];
            self.y[n + i] = w0[i] + h * h * a[i];
        }
        let nonfinite = || CoreError::NonFinite {
            time: t + h,
            step: 0,
            last_good_time: Some(t),
        };
        let mut factor = self.lu.is_none() || !self.constant;
        let mut iters = 0;
        let mut last = f64::INFINITY;
        loop {
            self.residual(model, t, x, &w0, factor)?;
            let res = super::alpha::norm(&self.r);
            if !res.is_finite() {
                return Err(nonfinite());
            }
            if self.newton && iters > 0 && res > 0.25 * last && !factor {
                self.residual(model, t, x, &w0, true)?;
            }
            factor = false;
            last = res;
            for ri in self.r.iter_mut() {
                *ri = -*ri;
            }
            // Set by `residual(.., factor = true)` on the first pass (`factor` starts true while
            // `lu` is None; a failed factorisation returns above): the `expect` cannot fail.
            let lu = self.lu.as_ref().expect("factorised above");
            if !lu.solve_in_place(&mut self.r) {
                return Err(nonfinite());
            }
            for (yi, di) in self.y.iter_mut().zip(&self.r) {
                *yi += di;
            }
            if !self.newton {
                break;
            }
            iters += 1;
            let scale = super::alpha::norm(&self.y)
                .max(super::alpha::norm(x))
                .max(super::alpha::norm(&w0));
            let update = super::alpha::norm(&self.r);
            if update <= self.tol * scale {
                break;
            }
            if !update.is_finite() {
                return Err(nonfinite());
            }
            if iters >= self.max_iter {
                return Err(CoreError::NoConvergence {
                    step: 0,
                    time: t + h,
                    residual: update / scale,
                    iterations: iters,
                    last_good_time: Some(t),
                });
            }
        }
        let (x1, w1) = self.y.split_at(n);
        // The end acceleration of the cubic: the next predictor only (the saved one comes
        // from the equation of motion).
        for i in 0..n {
            a[i] = (6.0 * x[i] + 2.0 * w0[i] - 6.0 * x1[i] + 4.0 * w1[i]) / (h * h);
        }
        x.copy_from_slice(x1);
        for (vi, wi) in v.iter_mut().zip(w1) {
            *vi = wi / h;
        }
        Ok(iters)
    }

    fn factorizations(&self) -> usize {
        self.factorizations
    }

    fn equation_acceleration(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::problem::MAX_POINTS;
    use super::*;

    #[test]
    fn gauss_rules_integrate_polynomials() {
        for n in 2..=MAX_POINTS {
            let (s, w) = gauss(n);
            for k in 0..2 * n {
                let q: f64 = s.iter().zip(&w).map(|(s, w)| w * s.powi(k as i32)).sum();
                assert!(
                    (q - 1.0 / (k as f64 + 1.0)).abs() < 1e-14,
                    "n = {n}, k = {k}"
                );
            }
        }
    }

    #[test]
    fn hermite_basis_interpolates() {
        let [b0, d0, _] = basis(0.0);
        let [b1, d1, _] = basis(1.0);
        assert_eq!(b0, [1.0, 0.0, 0.0, 0.0]);
        assert_eq!(b1, [0.0, 0.0, 1.0, 0.0]);
        assert_eq!(d0, [0.0, 1.0, 0.0, 0.0]);
        assert_eq!(d1, [0.0, 0.0, 0.0, 1.0]);
    }
}
