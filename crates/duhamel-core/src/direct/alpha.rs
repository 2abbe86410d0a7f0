//! The generalized-alpha family (Chung and Hulbert 1993): Newmark, HHT-alpha, generalized
//! alpha and, with `beta = 0`, the central difference method, as one parametrised step.
//!
//! With the Newmark updates
//!
//! `x1 = x0 + dt v0 + dt^2 [(1/2 - beta) a0 + beta a1]`, `v1 = v0 + dt [(1 - gamma) a0 + gamma a1]`
//!
//! the step equation for `a1` is the equation of motion with each force term weighted between
//! the two ends of the step:
//!
//! `mu_f M [(1 - am) a1 + am a0] + (1 - af) F1 + af F0 = (1 - af) f1 + af f0`,
//!
//! `F = mu' M v + C v + s K x + Kc x + sum_j w_j(t) (K_j x + C_j v) + r(x, v, t)` the internal
//! force (`w_j` the speed laws of scaled couplings), `f` the external load at
//! the step's ends. Newmark is `am = af = 0`; HHT is `am = 0`, `af = -alpha`. Weighting the
//! forces (rather than evaluating them at a weighted state) keeps a linear element identical to
//! the same term in `K` or `C` and sees the loads only at the grid times. The equation as a
//! whole approximates the equation of motion at `t_{n+1-af}`, so a mass law is evaluated
//! there, `mu_f = mu(t + (1 - af) dt)`: weighting `mu M a` like the forces instead would put
//! the inertia at `t_{n+1-am}` and cost an order whenever `am != af` (HHT measured first
//! order on the decaying-mass pendulum).

use super::assembly::{singular, Factorization, IterationMatrix, Matrix};
use super::lowrank::LowRank;
use super::model::{Coefs, Model, C, K, KC, M};
use super::problem::AlphaParams;
use super::stepper::Stepper;
use crate::error::CoreError;
use crate::loads::ModalForcing;

/// One generalized-alpha step with modified Newton on `a1`.
pub(crate) struct Alpha<'a> {
    par: AlphaParams,
    dt: f64,
    tol: f64,
    max_iter: usize,
    it: IterationMatrix<'a>,
    lu: Option<Factorization>,
    /// Sparse model, constant linear part, elements on few dofs: the linear part is
    /// factorised once and the elements' tangents enter as a low-rank update
    /// ([`LowRank`]); None until the first factorisation, or when not applicable.
    low: Option<LowRank>,
    low_rank: bool,
    /// The iteration matrix is the same for every step (no elements, constant mass).
    constant: bool,
    /// The step equation is nonlinear in `a1` (Newton iterations needed).
    newton: bool,
    /// Internal force, `M a` and external load at the start of the step.
    fint: Vec<f64>,
    ma: Vec<f64>,
    f0: Vec<f64>,
    f1: Vec<f64>,
    xt: Vec<f64>,
    vt: Vec<f64>,
    known: Vec<f64>,
    fint1: Vec<f64>,
    r: Vec<f64>,
    a1: Vec<f64>,
    x1: Vec<f64>,
    v1: Vec<f64>,
    factorizations: usize,
    /// The massless dofs (zero diagonal of `M`), with `beta > 0` (see [`Stepper::step`]).
    massless: Vec<usize>,
    /// The largest element's [`Element::resolution`](crate::elements::Element): a
    /// displacement correction below it is accepted (it cannot contract further).
    resolution: f64,
}

impl<'a> Alpha<'a> {
    /// The stepper at the initial state `(x0, v0, a0)` under the load `f0`.
    pub fn new(
        model: &mut Model<'a>,
        par: AlphaParams,
        state: [&[f64]; 3],
        f0: &[f64],
    ) -> Result<Self, CoreError> {
        let p = model.p;
        let n = model.n;
        let newton = !p.elements.is_empty() && (par.beta != 0.0 || model.velocity_elements);
        let constant = p.mass.is_none() && !newton && !model.varying_scale;
        let it = model.iteration_matrix(1)?;
        let low_rank = newton
            && it.is_sparse()
            && p.mass.is_none()
            && !model.varying_scale
            && LowRank::dofs(model).is_some();
        let [x0, v0, a0] = state;
        let k0 = model.coefs(0.0, false);
        let mut fint = vec![0.0; n];
        model.internal(x0, v0, 0.0, k0, false, &mut fint)?;
        let mut ma = vec![0.0; n];
        p.m.mul_add(1.0, a0, &mut ma);
        let massless = if par.beta > 0.0 && newton {
            massless_dofs(p.m)
        } else {
            Vec::new()
        };
        Ok(Alpha {
            par,
            dt: p.dt,
            tol: p.tol,
            max_iter: p.max_iter,
            it,
            lu: None,
            low: None,
            low_rank,
            constant,
            newton,
            fint,
            ma,
            f0: f0.to_vec(),
            f1: vec![0.0; n],
            xt: vec![0.0; n],
            vt: vec![0.0; n],
            known: vec![0.0; n],
            fint1: vec![0.0; n],
            r: vec![0.0; n],
            a1: vec![0.0; n],
            x1: vec![0.0; n],
            v1: vec![0.0; n],
            factorizations: 0,
            massless,
            resolution: p
                .elements
                .iter()
                .fold(0.0_f64, |a, e| a.max(e.resolution())),
        })
    }

    /// Assembles and factorises `dR/da1` at the step's end time `t1` with the elements' last
    /// evaluated tangents.
    fn factorize(&mut self, model: &Model, k1: Coefs, mu_f: f64, t1: f64) -> Result<(), CoreError> {
        let AlphaParams {
            alpha_m: am,
            alpha_f: af,
            gamma: g,
            beta: b,
        } = self.par;
        let h = self.dt;
        let (cv, kx) = ((1.0 - af) * g * h, (1.0 - af) * b * h * h);
        if let Some(low) = self.low.as_mut() {
            // the linear part is constant: only the elements' tangents changed
            return if low.update(model, kx, cv) {
                Ok(())
            } else {
                Err(singular())
            };
        }
        let it = &mut self.it;
        it.clear();
        model.add(it, M, (0, 0), (1.0 - am) * mu_f + cv * k1.dmu);
        model.add(it, C, (0, 0), cv);
        model.add(it, K, (0, 0), kx * k1.s);
        model.add(it, KC, (0, 0), kx);
        for (j, w) in model.scales(t1).enumerate() {
            model.add_scaled(it, j, (0, 0), kx * w, cv * w);
        }
        if self.low_rank {
            let base = it.factorize()?;
            self.factorizations += 1;
            let dofs = LowRank::dofs(model).expect("checked in new");
            self.low = Some(LowRank::new(base, model.n, dofs)?);
            self.lu = None;
            return self.factorize(model, k1, mu_f, t1);
        }
        if self.newton {
            model.add_tangents(it, (0, 0), kx, cv);
        }
        self.lu = Some(it.factorize()?);
        self.factorizations += 1;
        Ok(())
    }

    fn trial_state(&mut self) {
        let AlphaParams { gamma, beta, .. } = self.par;
        let h = self.dt;
        for i in 0..self.a1.len() {
            self.x1[i] = self.xt[i] + beta * h * h * self.a1[i];
            self.v1[i] = self.vt[i] + gamma * h * self.a1[i];
        }
    }
}

/// The dofs whose diagonal entry of `m` is zero (massless).
fn massless_dofs(m: &Matrix) -> Vec<usize> {
    let mut diag = vec![0.0; m.n()];
    match m {
        Matrix::Dense { n, data } => {
            for (i, d) in diag.iter_mut().enumerate() {
                *d = data[i * n + i];
            }
        }
        Matrix::Csr {
            indptr,
            indices,
            data,
            ..
        } => {
            for (i, d) in diag.iter_mut().enumerate() {
                for k in indptr[i]..indptr[i + 1] {
                    if indices[k] == i {
                        *d += data[k];
                    }
                }
            }
        }
    }
    (0..diag.len()).filter(|&i| diag[i] == 0.0).collect()
}

/// Largest magnitude.
pub(crate) fn norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m: f64, x| m.max(x.abs()))
}

impl Stepper for Alpha<'_> {
    fn step(
        &mut self,
        model: &mut Model,
        forcing: Option<&mut (dyn ModalForcing + '_)>,
        t: f64,
        state: [&mut [f64]; 3],
    ) -> Result<usize, CoreError> {
        let AlphaParams {
            alpha_m: am,
            alpha_f: af,
            gamma: g,
            beta: b,
        } = self.par;
        let h = self.dt;
        let t1 = t + h;
        let [x, v, a] = state;
        let n = x.len();
        model.external(&[t1], forcing, &mut self.f1)?;
        let k1 = model.coefs(t1, true);
        let mu_f = model.coefs(t + (1.0 - af) * h, true).mu;
        for i in 0..n {
            self.xt[i] = x[i] + h * v[i] + h * h * (0.5 - b) * a[i];
            self.vt[i] = v[i] + h * (1.0 - g) * a[i];
            self.known[i] = am * mu_f * self.ma[i] + af * self.fint[i]
                - (1.0 - af) * self.f1[i]
                - af * self.f0[i];
        }
        self.a1.copy_from_slice(a);
        // Massless dofs: the iteration starts from their displacement at the step's start
        // (what OpenSees' Newmark predicts for every dof), not from the extrapolation
        // `x0 + dt v0 + dt^2 a0 / 2`: their velocity and acceleration are no state of an
        // undamped massless dof (the trapezoidal rule leaves them an undamped alternation
        // after every kink), and Newton on a bilinear element started beyond its reversal
        // point cycles between its branches ("the step equation did not converge").
        for &i in &self.massless {
            self.a1[i] = (x[i] - self.xt[i]) / (b * h * h);
        }
        let nonfinite = || CoreError::NonFinite {
            time: t1,
            step: 0,
            last_good_time: Some(t),
        };
        let mut factor = (self.lu.is_none() && self.low.is_none()) || !self.constant;
        let mut iters = 0;
        let mut done = false;
        let mut last = f64::INFINITY;
        loop {
            self.trial_state();
            let tangent = self.newton && factor;
            model.internal(&self.x1, &self.v1, t1, k1, tangent, &mut self.fint1)?;
            if done {
                break;
            }
            self.r.copy_from_slice(&self.known);
            model.p.m.mul_add((1.0 - am) * mu_f, &self.a1, &mut self.r);
            for (ri, fi) in self.r.iter_mut().zip(&self.fint1) {
                *ri += (1.0 - af) * fi;
            }
            let res = norm(&self.r);
            if !res.is_finite() {
                return Err(nonfinite());
            }
            if self.newton && iters > 0 && res > 0.25 * last && !factor {
                // Modified Newton contracts too slowly: refresh the tangent here.
                factor = true;
                model.internal(&self.x1, &self.v1, t1, k1, true, &mut self.fint1)?;
            }
            if factor {
                self.factorize(model, k1, mu_f, t1)?;
                factor = false;
            }
            last = res;
            for ri in self.r.iter_mut() {
                *ri = -*ri;
            }
            // Set by `factorize` on the first pass (`factor` starts true while neither is set;
            // a failed factorisation returns above): the `expect` cannot fail.
            let solved = match self.low.as_mut() {
                Some(low) => low.solve_in_place(&mut self.r),
                None => self
                    .lu
                    .as_ref()
                    .expect("factorised above")
                    .solve_in_place(&mut self.r),
            };
            if !solved {
                return Err(nonfinite());
            }
            for (ai, di) in self.a1.iter_mut().zip(&self.r) {
                *ai += di;
            }
            if !self.newton {
                done = true;
                continue;
            }
            iters += 1;
            // Converged when the update is small against the state, all as accelerations.
            let mut scale: f64 = 0.0;
            for i in 0..n {
                let xi = self.xt[i] + b * h * h * self.a1[i];
                let vi = self.vt[i] + g * h * self.a1[i];
                scale = scale.max(self.a1[i].abs().max(vi.abs() / h).max(xi.abs() / (h * h)));
            }
            let update = norm(&self.r);
            if update <= self.tol * scale || b * h * h * update <= self.resolution {
                done = true;
                continue;
            }
            if !update.is_finite() {
                return Err(nonfinite());
            }
            if iters >= self.max_iter {
                return Err(CoreError::NoConvergence {
                    step: 0,
                    time: t1,
                    residual: update / scale,
                    iterations: iters,
                    last_good_time: Some(t),
                });
            }
        }
        x.copy_from_slice(&self.x1);
        v.copy_from_slice(&self.v1);
        a.copy_from_slice(&self.a1);
        std::mem::swap(&mut self.fint, &mut self.fint1);
        std::mem::swap(&mut self.f0, &mut self.f1);
        self.ma.fill(0.0);
        model.p.m.mul_add(1.0, a, &mut self.ma);
        Ok(if self.newton { iters } else { 0 })
    }

    fn factorizations(&self) -> usize {
        self.factorizations
    }

    fn equation_acceleration(&self) -> bool {
        false
    }
}
