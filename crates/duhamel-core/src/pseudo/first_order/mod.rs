//! Nonlinear forces on top of the exact coupled background: the step correction of the
//! first-order (complex) modes by the pseudo-force of the elements.
//!
//! Over a step the coupled linear background (non-classical damping, gyroscopic and
//! circulatory terms) is integrated exactly in its first-order modes
//! ([`crate::background::first_order`]);
//! only the element forces `Q = -Phi^T r(Phi q, Phi q', t)` enter as a pseudo-force, with the
//! paper's scheme b (displacement linear from `q0` to `q1`, velocity `(q1 - q0)/dt`) and the
//! trapezoidal rule (`Q` linear in time between its values at the step's ends):
//!
//! ```text
//! eta_k(1) = eta_lin_k + w_a(lambda_k) g_k . Q(q0, vb, t) + w_b(lambda_k) g_k . Q(q1, vb, t + dt)
//! ```
//!
//! with `w_a = int e^(lambda (dt - s)) (1 - s/dt) ds`, `w_b = int e^(lambda (dt - s)) s/dt ds`
//! and `vb = (q1 - q0)/dt`. The unknown is `q1` (the real modal displacements at the step's
//! end, linear in `eta`): `R(q1) = q1 - q1_lin - H_a Q0 - H_b Q1 = 0` is solved by Newton with
//! the elements' tangents, `H_a`, `H_b` (`m x m`) being what a unit modal load does to `q1`.

use num_complex::Complex64;

mod kink;
mod watch;

use super::force::{At, Jacobian, Parts, PseudoForce};
use super::growth::GrowthGuard;
use crate::dense::DenseLu;
use crate::elements::Element;
use crate::error::CoreError;
use crate::history::{size, zeroed, ElementRows};
use crate::kernel::cphi;

/// The nonlinear part of a coupled problem.
pub struct Nonlinear<'a> {
    /// Mode shapes, `n_dof x n_modes` row-major (mass-normalised).
    pub phi: &'a [f64],
    /// Number of physical degrees of freedom.
    pub n_dof: usize,
    /// Force elements.
    pub elements: &'a [&'a dyn Element],
    /// `[Re eta | Im eta] @ back = [q | q']`, `2 r x 2 m` row-major.
    pub back: &'a [f64],
    /// Relative tolerance of the Newton updates.
    pub tol: f64,
    /// Newton iterations per step before giving up.
    pub max_iter: usize,
    /// The elements' committed internal variables at the start (a continued run), if any.
    pub element_state: Option<&'a [f64]>,
    /// The growth guard's limit ([`super::GrowthGuard`]); infinite: no guard.
    pub growth_limit: f64,
    /// The guard's bounds at the start of a continued run, if any.
    pub guard_state: Option<&'a [f64]>,
}

/// What a corrected run keeps at its end: the elements' saved rows, their committed
/// variables and the growth guard's state.
pub(crate) type Records = (Option<ElementRows>, Option<Vec<f64>>, Option<Vec<f64>>);

/// The per-run state of the correction.
pub(crate) struct Corrector<'a> {
    pf: PseudoForce<'a>,
    m: usize,
    r: usize,
    dt: f64,
    back: &'a [f64],
    /// `w_a g_k`, `w_b g_k` per first-order mode (`r x m` complex, row-major).
    ga: Vec<Complex64>,
    gb: Vec<Complex64>,
    /// `H_a`, `H_b`: `q1` per unit modal load at the start / end (`m x m`, row-major).
    ha: Vec<f64>,
    hb: Vec<f64>,
    tol: f64,
    max_iter: usize,
    /// Current modal displacement (the step's start).
    pub q: Vec<f64>,
    /// The last step's end pseudo-force (the next step's first guess).
    last: Vec<f64>,
    /// Newton iterations over the run.
    pub iterations: usize,
    zeros: Vec<f64>,
    work: Work,
    /// The factorised iteration matrix, kept over iterations and steps (modified Newton);
    /// refreshed when the iteration contracts slowly.
    lu: Option<DenseLu>,
    /// How many times it was factorised.
    pub factorizations: usize,
    /// The elements' saved rows, when kept ([`Corrector::keep_rows`]).
    rows: Option<ElementRows>,
    /// Whether the elements' tangent stiffness is watched against the step's stability
    /// limit (native elements with tangents; this route does not subdivide: it stops).
    watch: bool,
    /// The growth guard.
    guard: Option<GrowthGuard>,
    /// The refined quadrature of steps with a kink (watched elements only; `kink.rs`).
    nodes: Option<kink::Nodes>,
}

#[derive(Default)]
struct Work {
    q1: Vec<f64>,
    q1_lin: Vec<f64>,
    vb: Vec<f64>,
    f0: Vec<f64>,
    f1: Vec<f64>,
    j0: Jacobian,
    j1: Jacobian,
    mat: Vec<f64>,
    rhs: Vec<f64>,
    scratch: Vec<f64>,
    v: Vec<f64>,
}

impl<'a> Corrector<'a> {
    pub(crate) fn new(
        nl: &Nonlinear<'a>,
        k: &'a [f64],
        c: &'a [f64],
        lambda: &[Complex64],
        gain: (&[f64], &[f64]),
        eta0: (&[f64], &[f64]),
        (t0, dt): (f64, f64),
    ) -> Result<Self, CoreError> {
        let (m, r) = (k.len(), lambda.len());
        // `r m` is the length of the gains (checked by the caller): `4 r m` cannot overflow.
        if nl.back.len() != 4 * r * m {
            return Err(CoreError::LengthMismatch {
                name: "back",
                got: nl.back.len(),
                expected: 4 * r * m,
            });
        }
        if !(nl.tol.is_finite() && nl.tol > 0.0) || nl.max_iter == 0 {
            return Err(CoreError::InvalidInput {
                name: "tol",
                problem: "must be positive (and `max_iter` at least 1)".into(),
            });
        }
        let dofs_x_modes = nl.n_dof.saturating_mul(m);
        if nl.phi.len() != dofs_x_modes {
            return Err(CoreError::LengthMismatch {
                name: "phi",
                got: nl.phi.len(),
                expected: dofs_x_modes,
            });
        }
        let pf = PseudoForce::new(Parts {
            phi: nl.phi,
            n_dof: nl.n_dof,
            elements: nl.elements,
            coupling_k: None,
            coupling_c: None,
            scaled: &[],
            mass: None,
            k,
            c,
        })?;
        let mut ga = Vec::with_capacity(r * m);
        let mut gb = Vec::with_capacity(r * m);
        for (kk, &lam) in lambda.iter().enumerate() {
            let mu = cphi::moments(lam, dt);
            let (wa, wb) = (mu[0] - mu[1], mu[1]);
            for i in 0..m {
                let g = Complex64::new(gain.0[kk * m + i], gain.1[kk * m + i]);
                ga.push(wa * g);
                gb.push(wb * g);
            }
        }
        let h = |gw: &[Complex64]| kink::back_project(nl.back, gw, m, r);
        let (ha, hb) = (h(&ga), h(&gb));
        let mut corrector = Corrector {
            pf,
            m,
            r,
            dt,
            back: nl.back,
            ga,
            gb,
            ha,
            hb,
            tol: nl.tol,
            max_iter: nl.max_iter,
            q: vec![0.0; m],
            last: vec![0.0; m],
            iterations: 0,
            zeros: vec![0.0; m],
            lu: None,
            factorizations: 0,
            rows: None,
            watch: false,
            guard: None,
            nodes: None,
            work: Work {
                q1: vec![0.0; m],
                q1_lin: vec![0.0; m],
                vb: vec![0.0; m],
                f0: vec![0.0; m],
                f1: vec![0.0; m],
                j0: Jacobian::new(m),
                j1: Jacobian::new(m),
                mat: vec![0.0; m * m],
                rhs: vec![0.0; m],
                scratch: vec![0.0; m],
                v: vec![0.0; m],
            },
        };
        let mut q = vec![0.0; m];
        corrector.map(eta0.0, eta0.1, 0, &mut q);
        if corrector.pf.stateful() {
            let mut v = vec![0.0; m];
            corrector.map(eta0.0, eta0.1, 1, &mut v);
            corrector.pf.commit(&q, &v, t0, true)?;
        }
        if let Some(state) = nl.element_state {
            corrector.pf.set_element_state(state)?;
        }
        corrector.watch = corrector.pf.space().watched();
        if corrector.watch {
            let mut nodes = kink::Nodes::new(lambda, gain, nl.back, m, dt);
            let mut v = vec![0.0; m];
            corrector.map(eta0.0, eta0.1, 1, &mut v);
            let start = corrector.pf.tangent_stiffness(&q, &v, t0);
            nodes.start = start.map_or((0.0, 0.0), |(l, _)| (l, corrector.pf.bg()));
            corrector.nodes = Some(nodes);
        }
        if nl.growth_limit.is_finite() {
            let mut v = vec![0.0; m];
            corrector.map(eta0.0, eta0.1, 1, &mut v);
            // A pseudo-force that cannot be evaluated at the start leaves the run unguarded:
            // its first step reports that failure in its place.
            let mut force0 = vec![0.0; m];
            if let Some(state) = nl.guard_state {
                corrector.guard = GrowthGuard::resume(nl.growth_limit, k, state);
            } else if corrector
                .pf
                .at_state(&q, &v, 0.0, &vec![0.0; m], &mut force0)
                .is_ok()
            {
                corrector.guard = GrowthGuard::new(nl.growth_limit, k, (&q, &v), &force0);
            }
        }
        corrector.q = q;
        Ok(corrector)
    }

    /// Keeps the elements' local states and forces at each of the `n_saved` saved states.
    pub(crate) fn keep_rows(&mut self, n_saved: usize) -> Result<(), CoreError> {
        let widths = self.pf.element_widths();
        let width: usize = widths.iter().sum();
        let cells = size(n_saved, width, "the element history")?;
        let buffer = |what| zeroed(cells, what);
        self.rows = Some(ElementRows {
            width,
            widths,
            x: buffer("the element displacements")?,
            v: buffer("the element velocities")?,
            r: buffer("the element forces")?,
        });
        Ok(())
    }

    /// The elements' saved rows, if kept, their committed variables (hysteretic) and the
    /// growth guard's state.
    pub(crate) fn take_records(&mut self) -> Records {
        let state = self.pf.stateful().then(|| self.pf.element_state());
        let guard = self.guard.as_ref().map(GrowthGuard::state);
        (self.rows.take(), state, guard)
    }

    /// Number of real modes.
    pub(crate) fn n_modes(&self) -> usize {
        self.m
    }

    /// `part` 0: `q`, 1: `q'` of the first-order coordinates `(re, im)`.
    pub(crate) fn map(&self, re: &[f64], im: &[f64], part: usize, out: &mut [f64]) {
        let (m, r) = (self.m, self.r);
        out.fill(0.0);
        for kk in 0..r {
            let (a, b) = (re[kk], im[kk]);
            let row_re = &self.back[kk * 2 * m + part * m..][..m];
            let row_im = &self.back[(r + kk) * 2 * m + part * m..][..m];
            for i in 0..m {
                out[i] += a * row_re[i] + b * row_im[i];
            }
        }
    }

    /// The element pseudo-force at the state of the first-order coordinates `(re, im)` and
    /// time `t` into `out`, and the elements' row in `slot` when kept.
    pub(crate) fn at_state(
        &mut self,
        (re, im): (&[f64], &[f64]),
        (t, slot): (f64, usize),
        out: &mut [f64],
    ) -> Result<(), CoreError> {
        let (mut q, mut v) = (
            std::mem::take(&mut self.work.q1_lin),
            std::mem::take(&mut self.work.v),
        );
        self.map(re, im, 0, &mut q);
        self.map(re, im, 1, &mut v);
        let mut result = self.pf.at_state(&q, &v, t, &self.zeros, out);
        if let (Some(rows), Ok(())) = (&mut self.rows, &result) {
            let e = slot * rows.width..(slot + 1) * rows.width;
            let rows = (
                &mut rows.x[e.clone()],
                &mut rows.v[e.clone()],
                &mut rows.r[e],
            );
            result = self.pf.record((&q, &v), t, rows);
        }
        self.work.q1_lin = q;
        self.work.v = v;
        result
    }

    /// Corrects the linear step `eta_lin` (in `re`, `im`) of the step `[t, t + dt]` into the
    /// step's end; returns the Newton iterations. `loads`: the modal load at the step's start
    /// and end and its bubble coefficient, for the growth guard (None when it is not known:
    /// the guard skips the step).
    pub(crate) fn correct(
        &mut self,
        t: f64,
        (re, im): (&mut [f64], &mut [f64]),
        loads: Option<(&[f64], &[f64], &[f64])>,
    ) -> Result<usize, CoreError> {
        let mut w = std::mem::take(&mut self.work);
        let result = self.correct_with(t, re, im, &mut w).and_then(|iters| {
            self.watch_end(t + self.dt, (re, im), loads, &mut w)
                .map(|_| iters)
        });
        self.work = w;
        result
    }

    fn correct_with(
        &mut self,
        t: f64,
        re: &mut [f64],
        im: &mut [f64],
        w: &mut Work,
    ) -> Result<usize, CoreError> {
        let m = self.m;
        let mut iters = self.newton(t, re, im, w)?;
        let depth = self.kink(t, w)?;
        if depth > 0 {
            iters += self.refined(t, (re, im), w, depth)?;
        } else {
            // The step's end from the converged displacement: both pseudo-forces there.
            self.ends(t, w, false)?;
            for kk in 0..self.r {
                let mut x = Complex64::new(0.0, 0.0);
                for i in 0..m {
                    x += self.ga[kk * m + i] * w.f0[i] + self.gb[kk * m + i] * w.f1[i];
                }
                re[kk] += x.re;
                im[kk] += x.im;
            }
            self.last.copy_from_slice(&w.f1);
        }
        let mut q = std::mem::take(&mut self.q);
        self.map(re, im, 0, &mut q);
        if self.pf.stateful() {
            self.map(re, im, 1, &mut w.v);
            self.pf.commit(&q, &w.v, t + self.dt, false)?;
        }
        self.q = q;
        Ok(iters)
    }

    /// The pseudo-force at the step's start and end along scheme b for the end displacement
    /// `w.q1` (into `w.f0`, `w.f1`; with `tangents`, their tangents into `w.j0`, `w.j1`).
    fn ends(&mut self, t: f64, w: &mut Work, tangents: bool) -> Result<(), CoreError> {
        let dt = self.dt;
        for ((vb, q1), q0) in w.vb.iter_mut().zip(&w.q1).zip(&self.q) {
            *vb = (q1 - q0) / dt;
        }
        let (j0, j1) = if tangents {
            (Some(&mut w.j0), Some(&mut w.j1))
        } else {
            (None, None)
        };
        let start = At {
            q: &self.q,
            v: &w.vb,
            t,
            p: &self.zeros,
            a: None,
        };
        self.pf.eval(start, &mut w.f0, j0)?;
        // The end of the step: a mass law's derivative from the left (none here, but the
        // pseudo-force keeps the convention).
        self.pf.set_left_limit(true);
        let end = At {
            q: &w.q1,
            v: &w.vb,
            t: t + dt,
            p: &self.zeros,
            a: None,
        };
        let end = self.pf.eval(end, &mut w.f1, j1);
        self.pf.set_left_limit(false);
        end
    }

    fn newton(&mut self, t: f64, re: &[f64], im: &[f64], w: &mut Work) -> Result<usize, CoreError> {
        let (m, dt) = (self.m, self.dt);
        self.map(re, im, 0, &mut w.q1_lin);
        // First guess: the linear step plus the last pseudo-force held over the step.
        for i in 0..m {
            w.q1[i] = w.q1_lin[i]
                + (0..m)
                    .map(|j| (self.ha[i * m + j] + self.hb[i * m + j]) * self.last[j])
                    .sum::<f64>();
        }
        let mut residual = f64::INFINITY;
        let mut refresh = self.lu.is_none();
        let mut previous = f64::INFINITY;
        for it in 1..=self.max_iter {
            self.ends(t, w, refresh)?;
            // R = q1 - q1_lin - Ha f0 - Hb f1
            for i in 0..m {
                let mut ri = w.q1[i] - w.q1_lin[i];
                for j in 0..m {
                    ri -= self.ha[i * m + j] * w.f0[j] + self.hb[i * m + j] * w.f1[j];
                }
                w.rhs[i] = -ri;
            }
            residual = w.rhs.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
            if refresh {
                // J = I - Ha (C0 / dt) - Hb (K1 + C1 / dt)
                for i in 0..m {
                    for j in 0..m {
                        let mut s = 0.0;
                        for l in 0..m {
                            s += self.ha[i * m + l] * w.j0.cq[l * m + j] / dt
                                + self.hb[i * m + l]
                                    * (w.j1.kq[l * m + j] + w.j1.cq[l * m + j] / dt);
                        }
                        w.mat[i * m + j] = if i == j { 1.0 } else { 0.0 } - s;
                    }
                }
                self.lu = DenseLu::factor(m, &w.mat);
                self.factorizations += 1;
                refresh = false;
            }
            let Some(lu) = self.lu.as_ref() else { break };
            if !lu.solve(&mut w.rhs, &mut w.scratch) {
                break;
            }
            let mut step = 0.0_f64;
            let mut size = 0.0_f64;
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
                return Ok(it);
            }
            // A slowly contracting iteration: the kept tangent is stale, refresh it.
            if step > 0.1 * previous {
                refresh = true;
            }
            previous = step;
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
