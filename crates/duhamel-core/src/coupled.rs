//! Exact stepping of a coupled linear system in its first-order (complex) modes.
//!
//! Non-classical damping, gyroscopic (`speed * G`) and circulatory (cross-coupled bearing)
//! terms couple the modal oscillators of the symmetric background: the retained modes obey
//! `q'' + D q' + S q = p(t)` with full `D`, `S`. Written in first order, `y = (q, q')`,
//! `y' = A y + B p`, and diagonalised, `A = V diag(lambda) V^-1`, each first-order modal
//! coordinate `eta_k` is an independent scalar equation `eta_k' = lambda_k eta_k + g_k . p(t)`
//! (`g_k` row `k` of `V^-1 B`), advanced exactly over a step (Duhamel's integral with the
//! complex exponential-integrator functions of [`crate::cphi`]):
//!
//! ```text
//! eta_k(n+1) = e^(lambda_k dt) eta_k(n) + sum_j w_j(lambda_k) (g_k . basis_j)
//! ```
//!
//! with the loads in the same per-step basis `(p0, Dp, DDp)` as the uncoupled engine and jumps
//! inside a step added exactly. So a linear time-invariant system with these couplings is
//! integrated as exactly as an uncoupled one: the only error is the representation of the
//! loads within a step (none for steps, ramps and quadratics). The decomposition itself
//! (eigenvalues, which of each conjugate pair to keep, and the way back to `(q, q')`) is done
//! by the caller; the engine only advances the given coordinates and saves them.

use faer::linalg::matmul::matmul;
use faer::{Accum, MatMut, MatRef, Par};
use num_complex::Complex64;

use crate::coupled_step::{Corrector, Nonlinear};
use crate::cphi;
use crate::error::CoreError;
use crate::linear::{check, LinearProblem};
use crate::stepping::{zeroed, BlockLoads, Failure, History, ModalForcing};

/// The first-order modes of the coupled system, as complex numbers split into real and
/// imaginary parts (`r` coordinates, `m = problem.k.len()` real modes).
#[derive(Debug, Clone)]
pub struct FirstOrderModes<'a> {
    /// Eigenvalues `lambda_k`, real parts (length `r`).
    pub lambda_re: &'a [f64],
    /// Eigenvalues, imaginary parts.
    pub lambda_im: &'a [f64],
    /// `g[k * m + i]`: how much of the modal load `p_i` drives `eta_k` (row `k` of
    /// `V^-1 B`), real parts (`r x m`, row-major).
    pub gain_re: &'a [f64],
    /// The same, imaginary parts.
    pub gain_im: &'a [f64],
    /// Initial values `eta_k(0)`, real parts.
    pub eta0_re: &'a [f64],
    /// Initial values, imaginary parts.
    pub eta0_im: &'a [f64],
}

impl FirstOrderModes<'_> {
    fn check(&self, n_modes: usize) -> Result<(), CoreError> {
        let r = self.lambda_re.len();
        let lens = [
            ("lambda_im", self.lambda_im.len(), r),
            ("gain_re", self.gain_re.len(), r * n_modes),
            ("gain_im", self.gain_im.len(), r * n_modes),
            ("eta0_re", self.eta0_re.len(), r),
            ("eta0_im", self.eta0_im.len(), r),
        ];
        for (name, got, expected) in lens {
            if got != expected {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected,
                });
            }
        }
        let all = [
            self.lambda_re,
            self.lambda_im,
            self.gain_re,
            self.gain_im,
            self.eta0_re,
            self.eta0_im,
        ];
        if all.iter().any(|s| s.iter().any(|x| !x.is_finite())) {
            return Err(CoreError::InvalidInput {
                name: "first-order modes",
                problem: "must be finite".to_string(),
            });
        }
        Ok(())
    }

    fn lambda(&self, k: usize) -> Complex64 {
        Complex64::new(self.lambda_re[k], self.lambda_im[k])
    }

    /// `g_k . p` for a real modal vector `p`.
    fn project(&self, k: usize, p: &[f64]) -> Complex64 {
        let m = p.len();
        let (gr, gi) = (&self.gain_re[k * m..][..m], &self.gain_im[k * m..][..m]);
        let re = gr.iter().zip(p).map(|(g, x)| g * x).sum();
        let im = gi.iter().zip(p).map(|(g, x)| g * x).sum();
        Complex64::new(re, im)
    }
}

/// Per-coordinate constants, split into real and imaginary parts (vectorisable loops).
struct Constants {
    /// `e^(lambda dt)`.
    e: [Vec<f64>; 2],
    /// `w_j(lambda)`, the weights of the basis `(p0, Dp, DDp)`.
    w: [[Vec<f64>; 2]; 3],
    /// `gl[l][j]`: `w_j (g . pattern_l)`.
    gl: Vec<[[Vec<f64>; 2]; 3]>,
}

impl Constants {
    fn new(problem: &LinearProblem, modes: &FirstOrderModes) -> Self {
        let r = modes.lambda_re.len();
        let mut e = [vec![0.0; r], vec![0.0; r]];
        let mut w: [[Vec<f64>; 2]; 3] = std::array::from_fn(|_| [vec![0.0; r], vec![0.0; r]]);
        let mut gl: Vec<[[Vec<f64>; 2]; 3]> = problem
            .loads
            .iter()
            .map(|_| std::array::from_fn(|_| [vec![0.0; r], vec![0.0; r]]))
            .collect();
        for k in 0..r {
            let lam = modes.lambda(k);
            let ek = (lam * problem.dt).exp();
            (e[0][k], e[1][k]) = (ek.re, ek.im);
            let wk = cphi::basis_weights(lam, problem.dt);
            for j in 0..3 {
                (w[j][0][k], w[j][1][k]) = (wk[j].re, wk[j].im);
            }
            for (load, g) in problem.loads.iter().zip(gl.iter_mut()) {
                let gk = modes.project(k, &load.pattern);
                for j in 0..3 {
                    let x = wk[j] * gk;
                    (g[j][0][k], g[j][1][k]) = (x.re, x.im);
                }
            }
        }
        Constants { e, w, gl }
    }
}

/// Coordinates advanced together in registers (one AVX-512 vector, two AVX2 vectors).
const LANES: usize = 8;

/// Advances coordinates `i0..i0 + N` by one step, `eta <- e eta + sum_t b_t g_t` over the
/// step's load terms `(b, g_re, g_im)`; returns whether they stay finite.
#[inline(always)]
fn advance<const N: usize>(
    xr: &mut [f64],
    xi: &mut [f64],
    i0: usize,
    e: &[Vec<f64>; 2],
    terms: &[(f64, &[f64], &[f64])],
) -> bool {
    let r = i0..i0 + N;
    let (er, ei) = (&e[0][r.clone()], &e[1][r.clone()]);
    let mut ar = [0.0; N];
    let mut ai = [0.0; N];
    {
        let (x, y) = (&xr[r.clone()], &xi[r.clone()]);
        for j in 0..N {
            ar[j] = er[j] * x[j] - ei[j] * y[j];
            ai[j] = er[j] * y[j] + ei[j] * x[j];
        }
    }
    for &(b, gr, gi) in terms {
        let (gr, gi) = (&gr[r.clone()], &gi[r.clone()]);
        for j in 0..N {
            ar[j] += b * gr[j];
            ai[j] += b * gi[j];
        }
    }
    xr[r.clone()].copy_from_slice(&ar);
    xi[r].copy_from_slice(&ai);
    // A boolean AND-reduction vectorises; a floating-point sum would not.
    let mut finite = true;
    for j in 0..N {
        finite &= ar[j].is_finite() & ai[j].is_finite();
    }
    finite
}

/// Physical outputs computed from the first-order coordinates during the run: each saved
/// row of `[Re eta | Im eta]` (and of the load values) is mapped to `n_cols` outputs, e.g.
/// displacements, velocities and accelerations of the wanted degrees of freedom.
#[derive(Debug, Clone)]
pub struct Outputs<'a> {
    /// `map[k * n_cols + o]`: output `o` per unit of entry `k` of `[Re eta | Im eta]`
    /// (`2 r x n_cols`, row-major).
    pub map: &'a [f64],
    /// `loads[l * n_cols + o]`: output `o` per unit value of load `l`'s time function
    /// (`n_loads x n_cols`).
    pub loads: &'a [f64],
    /// Number of outputs.
    pub n_cols: usize,
}

impl Outputs<'_> {
    fn check(&self, width: usize, n_loads: usize) -> Result<(), CoreError> {
        for (name, got, expected) in [
            ("output map", self.map.len(), width * self.n_cols),
            ("output load map", self.loads.len(), n_loads * self.n_cols),
        ] {
            if got != expected {
                return Err(CoreError::LengthMismatch {
                    name,
                    got,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// `out = eta @ map + values @ loads` for a block of saved rows (faer's matrix product:
    /// measured twice as fast here as a register-blocked row loop).
    fn apply(&self, eta: &[f64], values: &[f64], out: &mut [f64]) {
        let n = self.n_cols;
        let rows = out.len() / n.max(1);
        if rows == 0 || n == 0 {
            return;
        }
        let width = eta.len() / rows;
        let n_loads = values.len() / rows;
        let mut dst = MatMut::from_row_major_slice_mut(out, rows, n);
        let lhs = MatRef::from_row_major_slice(eta, rows, width);
        let rhs = MatRef::from_row_major_slice(self.map, width, n);
        matmul(&mut dst, Accum::Replace, lhs, rhs, 1.0, Par::Seq);
        if n_loads > 0 {
            let lhs = MatRef::from_row_major_slice(values, rows, n_loads);
            let rhs = MatRef::from_row_major_slice(self.loads, n_loads, n);
            matmul(&mut dst, Accum::Add, lhs, rhs, 1.0, Par::Seq);
        }
    }
}

/// A block of saved rows to map to outputs: first-order coordinates, load values, where
/// the outputs go.
type Job<'b> = (&'b [f64], Vec<f64>, &'b mut [f64]);

/// Integrates the coupled problem exactly in its first-order modes; `forcing` adds modal
/// loads computed outside the engine. `problem.k`, `problem.c` are the diagonal of the real
/// modal background (checked, and defining the number of real modes); the saved history
/// holds `eta` (see [`History::eta`]) and the load values, not `q`, `v`.
///
/// With `outputs`, the saved rows are also mapped to outputs ([`History::out`]), block by
/// block, on a second thread while the next block is stepped (unless `problem.threads` is
/// 1 or the machine has one core). With `nonlinear`, element forces enter every step as a
/// pseudo-force on the exact coupled background ([`crate::coupled_step`]); the pseudo-force
/// at the saved states is kept in [`History::pseudo`]. Also returns the Newton iterations.
pub fn integrate(
    problem: &LinearProblem,
    modes: &FirstOrderModes,
    outputs: Option<&Outputs>,
    nonlinear: Option<&Nonlinear>,
    mut forcing: Option<&mut dyn ModalForcing>,
) -> Result<(History, usize), Box<Failure>> {
    check(problem).map_err(|e| Box::new(Failure::from(e)))?;
    let m = problem.k.len();
    modes.check(m).map_err(|e| Box::new(Failure::from(e)))?;
    let r = modes.lambda_re.len();
    let n_loads = problem.loads.len();
    if let Some(o) = outputs {
        o.check(2 * r, n_loads)
            .map_err(|e| Box::new(Failure::from(e)))?;
    }
    let co = Constants::new(problem, modes);
    let mut corrector = match nonlinear {
        Some(nl) => {
            let lambda: Vec<Complex64> = (0..r).map(|k| modes.lambda(k)).collect();
            let c = Corrector::new(
                nl,
                problem.k,
                problem.c,
                &lambda,
                (modes.gain_re, modes.gain_im),
                (modes.eta0_re, modes.eta0_im),
                problem.dt,
            )
            .map_err(|e| Box::new(Failure::from(e)))?;
            Some(c)
        }
        None => None,
    };
    let mut loads = BlockLoads::raw(problem);
    let n_saved = loads.n_saved();
    let mut eta = zeroed(n_saved * 2 * r)?;
    let mut pseudo = if corrector.is_some() {
        zeroed(n_saved * m)?
    } else {
        Vec::new()
    };
    let n_cols = outputs.map_or(0, |o| o.n_cols);
    let mut out = zeroed(n_saved * n_cols)?;
    let threads = problem
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    let pipelined = outputs.is_some() && threads > 1;

    let failure = std::thread::scope(|scope| {
        let (tx, rx) = std::sync::mpsc::channel::<Job>();
        if pipelined {
            let o = outputs.expect("pipelined implies outputs");
            scope.spawn(move || {
                for (e, v, dst) in rx {
                    o.apply(e, &v, dst);
                }
            });
        } else {
            drop(rx);
        }
        let mut eta_rest: &mut [f64] = &mut eta;
        let mut out_rest: &mut [f64] = &mut out;
        let mut stepper = Stepper::new(modes);
        let mut row0 = 0;
        let mut n0 = 0;
        while n0 < problem.n_steps {
            if let Err(e) = loads.prepare(problem, n0, forcing.as_deref_mut()) {
                return Some((e, n0));
            }
            let rows = loads.slot.iter().flatten().count();
            let (eta_blk, tail) = std::mem::take(&mut eta_rest).split_at_mut(rows * 2 * r);
            eta_rest = tail;
            let failed = stepper.block(
                problem,
                modes,
                &co,
                &loads,
                (n0, row0),
                eta_blk,
                corrector.as_mut().map(|c| (c, &mut pseudo[..])),
            );
            if let Some(o) = outputs {
                let (out_blk, tail) = std::mem::take(&mut out_rest).split_at_mut(rows * n_cols);
                out_rest = tail;
                let values = loads.load_values[row0 * n_loads..][..rows * n_loads].to_vec();
                let eta_blk: &[f64] = eta_blk;
                if pipelined {
                    // The worker lives until `tx` is dropped, so the send cannot fail.
                    let _ = tx.send((eta_blk, values, out_blk));
                } else {
                    o.apply(eta_blk, &values, out_blk);
                }
            }
            if failed.is_some() {
                return failed;
            }
            row0 += rows;
            n0 += loads.len;
        }
        None
    });
    let iterations = corrector.as_ref().map_or(0, |c| c.iterations);
    let mut result = loads.finish_first_order(m, eta, pseudo, failure);
    // Attach the outputs (truncated like the rest on failure).
    match &mut result {
        Ok(h) => h.out = out,
        Err(f) => {
            let keep = f.partial.t.len();
            out.truncate(keep * n_cols);
            f.partial.out = out;
        }
    }
    result.map(|h| (h, iterations))
}

/// The stepping state: current coordinates and per-step work arrays.
struct Stepper {
    xr: Vec<f64>,
    xi: Vec<f64>,
    /// The forcing's contribution to each step of the block (`len x r`), or empty.
    fr: Vec<f64>,
    fi: Vec<f64>,
    /// This block's in-step jumps: `(local step, response re, response im)`.
    jumps: Vec<(usize, Vec<f64>, Vec<f64>)>,
}

impl Stepper {
    fn new(modes: &FirstOrderModes) -> Self {
        Stepper {
            xr: modes.eta0_re.to_vec(),
            xi: modes.eta0_im.to_vec(),
            fr: Vec::new(),
            fi: Vec::new(),
            jumps: Vec::new(),
        }
    }

    /// Steps one block, saving its rows (the first being history row `row0`) into `eta`;
    /// returns the failure if the state stops being finite.
    #[allow(clippy::too_many_arguments)]
    fn block(
        &mut self,
        problem: &LinearProblem,
        modes: &FirstOrderModes,
        co: &Constants,
        loads: &BlockLoads,
        (n0, row0): (usize, usize),
        eta: &mut [f64],
        mut nonlinear: Option<(&mut Corrector, &mut [f64])>,
    ) -> Option<(CoreError, usize)> {
        let r = self.xr.len();
        let m = problem.k.len();
        let n_loads = problem.loads.len();
        let len = loads.len;
        // The forcing's contribution to each step: the first-order forcing g . f at the
        // step's start, middle and end (samples 2s, 2s + 1, 2s + 2) in the load basis.
        self.fr.clear();
        self.fi.clear();
        if !loads.forcing.is_empty() {
            let h: Vec<Complex64> = loads
                .forcing
                .chunks_exact(m)
                .flat_map(|f| (0..r).map(move |k| modes.project(k, f)))
                .collect();
            for s in 0..len {
                for k in 0..r {
                    let (p0, pm, p1) = (
                        h[2 * s * r + k],
                        h[(2 * s + 1) * r + k],
                        h[(2 * s + 2) * r + k],
                    );
                    let w = |j: usize| Complex64::new(co.w[j][0][k], co.w[j][1][k]);
                    let x = w(0) * p0 + w(1) * (p1 - p0) + w(2) * (pm - (p0 + p1) * 0.5);
                    self.fr.push(x.re);
                    self.fi.push(x.im);
                }
            }
        }
        self.jumps.clear();
        for &(s, l, rest, j) in &loads.raw_jumps {
            let pattern = &problem.loads[l].pattern;
            let (dr, di): (Vec<f64>, Vec<f64>) = (0..r)
                .map(|k| {
                    let x = cphi::polynomial_response(modes.lambda(k), rest, j)
                        * modes.project(k, pattern);
                    (x.re, x.im)
                })
                .unzip();
            self.jumps.push((s, dr, di));
        }
        let Stepper {
            xr,
            xi,
            fr,
            fi,
            jumps,
        } = self;
        // Reused across the steps of the block: no allocation per step.
        let mut terms: Vec<(f64, &[f64], &[f64])> = Vec::new();
        for s in 0..=len {
            if let Some(slot) = loads.slot[s] {
                let row = &mut eta[(slot - row0) * 2 * r..][..2 * r];
                row[..r].copy_from_slice(xr);
                row[r..].copy_from_slice(xi);
                if let Some((c, pseudo)) = nonlinear.as_mut() {
                    // The element pseudo-force at the saved state (for the accelerations).
                    let t = (n0 + s) as f64 * problem.dt;
                    if let Err(e) = c.at_state(xr, xi, t, &mut pseudo[slot * m..][..m]) {
                        return Some((e, n0 + s));
                    }
                }
            }
            if s == len {
                break;
            }
            terms.clear();
            for (l, g) in co.gl.iter().enumerate() {
                for (j, &b) in loads.basis[s * n_loads + l].iter().enumerate() {
                    if b != 0.0 {
                        terms.push((b, &g[j][0], &g[j][1]));
                    }
                }
            }
            for (_, dr, di) in jumps.iter().filter(|jp| jp.0 == s) {
                terms.push((1.0, dr, di));
            }
            if !fr.is_empty() {
                terms.push((1.0, &fr[s * r..][..r], &fi[s * r..][..r]));
            }
            let mut finite = true;
            let mut i0 = 0;
            while i0 + LANES <= r {
                finite &= advance::<LANES>(xr, xi, i0, &co.e, &terms);
                i0 += LANES;
            }
            while i0 < r {
                finite &= advance::<1>(xr, xi, i0, &co.e, &terms);
                i0 += 1;
            }
            if let (true, Some((c, _))) = (finite, nonlinear.as_mut()) {
                let t = (n0 + s) as f64 * problem.dt;
                if let Err(e) = c.correct(t, xr, xi) {
                    let step = n0 + s + 1;
                    // A residual that is no longer finite is a diverging response.
                    let e = match e {
                        CoreError::NoConvergence { residual, .. } if !residual.is_finite() => {
                            CoreError::NonFinite {
                                time: step as f64 * problem.dt,
                                step,
                                last_good_time: (step - 1) as f64 * problem.dt,
                            }
                        }
                        other => other,
                    };
                    return Some((e, step));
                }
                finite = xr.iter().chain(xi.iter()).all(|x| x.is_finite());
            }
            if !finite {
                let step = n0 + s + 1;
                let dt = problem.dt;
                return Some((
                    CoreError::NonFinite {
                        time: step as f64 * dt,
                        step,
                        last_good_time: (step - 1) as f64 * dt,
                    },
                    step,
                ));
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linear;
    use crate::loads::{ModalLoad, TimeFunction};

    /// One damped oscillator `q'' + c q' + k q = p` in first-order modes (computed by hand)
    /// gives the uncoupled engine's answer, loads and in-step jumps included.
    #[test]
    fn one_oscillator_matches_the_uncoupled_engine() {
        let (k, c) = ([4.0], [0.4]);
        let loads = [
            ModalLoad {
                pattern: vec![1.5],
                time: TimeFunction::Step { t0: 0.123 },
            },
            ModalLoad {
                pattern: vec![-0.7],
                time: TimeFunction::Harmonic {
                    omega: 3.0,
                    phase: 0.2,
                },
            },
        ];
        let problem = LinearProblem {
            k: &k,
            c: &c,
            q0: &[0.3],
            v0: &[-0.2],
            loads: &loads,
            dt: 0.05,
            n_steps: 200,
            save_every: 1,
            threads: Some(1),
        };
        // A = [[0, 1], [-k, -c]]: lambda = (-c + i sqrt(4k - c^2)) / 2, V = [[1, 1], [l, conj l]].
        let lam = Complex64::new(-c[0] / 2.0, (4.0 * k[0] - c[0] * c[0]).sqrt() / 2.0);
        let det = lam.conj() - lam; // det V
                                    // row 0 of V^-1 = [conj l, -1] / det
        let w0 = lam.conj() / det;
        let w1 = Complex64::new(-1.0, 0.0) / det;
        let eta0 = w0 * 0.3 + w1 * -0.2;
        let modes = FirstOrderModes {
            lambda_re: &[lam.re],
            lambda_im: &[lam.im],
            gain_re: &[w1.re],
            gain_im: &[w1.im],
            eta0_re: &[eta0.re],
            eta0_im: &[eta0.im],
        };
        // [Re eta, Im eta] -> (q, v) = 2 Re(V_0 eta): q = 2 Re eta, v = 2 Re(l eta).
        let map = [2.0, 2.0 * lam.re, 0.0, -2.0 * lam.im];
        let outputs = Outputs {
            map: &map,
            loads: &[0.0; 4],
            n_cols: 2,
        };
        let (h, _) = integrate(&problem, &modes, Some(&outputs), None, None).unwrap();
        let reference = linear::integrate(&problem, None).unwrap();
        assert_eq!(h.t, reference.t);
        for (s, row) in h.out.chunks_exact(2).enumerate() {
            assert!((row[0] - reference.q[s]).abs() < 1e-14, "q at step {s}");
            assert!((row[1] - reference.v[s]).abs() < 1e-13, "v at step {s}");
        }
    }
}
